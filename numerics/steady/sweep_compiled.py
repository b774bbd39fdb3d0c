"""The sweep's per-frequency loop in compiled calls (``kernels.sweep_template.sweep_lanes``).

Python prepares every point's numbers (steps per period, settling cap, divergence
limit, the drive tables of every step count a pass may take), calls the compiled
driver once per block of points (the lanes in groups, a thread each), and builds the
same ``Orbits`` that ``sweeps._sweep_lanes_python`` builds point by point with
``steady_states``, messages included."""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from perturb import eq26_numbers
from perturb.common import Status, check_int, processors

from ..kernels.codegen import compiled_kernels
from ..kernels.lanes import divergence_limit, drive_table, failure_message
from .options import MAX_STEPS, SteadyOptions
from .orbits import Orbits
from .shooting import (
    check_period_guess,
    lane_steps,
    not_settled_message,
    settling_cap,
    under_resolved_message,
)

__all__ = ["sweep_lanes_compiled", "supported", "DriverUnusable"]


class DriverUnusable(RuntimeError):
    """The compiled driver raised on checked inputs: its cached machine code is broken
    (a truncated or garbled numba cache file), not the call."""


def supported(options: SteadyOptions, keep_orbits: bool = False) -> bool:
    """Whether the compiled driver does what ``steady_states`` does with these settings:
    it is built with the default engine decisions (``SteadyOptions.engine_is_default``),
    and it does not keep the orbits' histories."""
    return options.engine_is_default() and not keep_orbits


#: The sweep is cut into blocks of points lasting about this long [s], so that the
#: progress bar moves and Ctrl-C is heard between them (the driver cannot be
#: interrupted inside a call).
BLOCK_SECONDS = 0.25
def sweep_threads(lanes: int, least: int) -> int:
    """How many threads sweep ``lanes`` lanes: one per core this process may run on, each
    with at least ``least`` lanes (the kernels' ``VECTOR_LANES``: their vector loops take
    that many lanes at a time, fewer run one by one; ``bench_kernel`` measures both)."""
    return max(1, min(processors(), lanes // least))


def deal_lanes(lanes: int, count: int) -> list[np.ndarray]:
    """The lanes 0..``lanes``-1 dealt to ``count`` groups back and forth (0, 1, ..., c-1,
    then c-1, ..., 0, and again), each group's in increasing order.

    Each group takes one lane of every round of ``count`` lanes, from alternate ends, so
    that alike loads spread: ``sweep()`` lays each amplitude's sweep up and sweep down
    side by side, and each group gets up and down sweeps in near-equal numbers (for an
    even count, every such pair is split). On the Fig. 2 + 3 job the ten down sweeps took
    2.2 times the RK4 steps of the ten up (8.3e6 against 3.7e6 lane-steps): dealt round
    robin (every second lane), one thread took 0.082 s and the other 0.053 s; back and
    forth, 0.074 s and 0.068 s (medians of 7 and 9 runs; measured once by hand,
    2026-11-24).

    >>> [group.tolist() for group in deal_lanes(7, 2)]
    [[0, 3, 4], [1, 2, 5, 6]]
    """
    order = np.arange(lanes)
    forth = (order // count) % 2 == 0
    group = np.where(forth, order % count, count - 1 - order % count)
    return [np.flatnonzero(group == k) for k in range(count)]


def sweep_lanes_compiled(freq, p_a, model, start: Orbits | None = None, *,
                         options: SteadyOptions, keep_orbits=False, done=None,
                         threads: int | None = None,
                         block_seconds: float = BLOCK_SECONDS) -> Orbits:
    """``sweeps.sweep_points`` in compiled calls, a block of points at a time (each block
    continues from the last good orbit of every lane, as a point does): the points,
    frequency by frequency. ``done(points)`` is called as blocks end (from the groups'
    threads, when there are several).

    The lanes are swept in ``threads`` groups at once, a thread each (default
    ``sweep_threads``). A lane's arithmetic is its own, whatever lanes share its batch,
    so the points are those of one sweep of all lanes, to the last bit
    (tests/test_sweep_compiled.py). An error in one group stops the others after their
    block, and is raised. Each call sweeps a block of points lasting about
    ``block_seconds`` (the first block is one point, to measure the time per point)."""
    if keep_orbits:
        raise ValueError("the compiled sweep does not keep orbits; use the Python route")
    if not supported(options):
        raise ValueError("the compiled sweep is built with the default engine decisions "
                         f"(changed: {options.engine_changes()}); use the Python route")
    steps_per_period, tol, app_rtol = options.steps_per_period, options.tol, options.app_rtol
    max_periods, method, refinements = options.max_periods, options.method, options.refinements
    # The driver's argument types are fixed (a new type would compile it once more).
    freq = np.ascontiguousarray(freq, dtype=float)
    p_a = np.ascontiguousarray(np.broadcast_to(p_a, freq.shape[:1]), dtype=float)
    kernels = compiled_kernels(model)
    numbers = eq26_numbers(model.parameters)
    steps = lane_steps(steps_per_period, freq.ravel(), numbers.fastest_rate_per_s)
    steps = steps.reshape(freq.shape)
    lanes = freq.shape[0]
    if start is None:  # rest, and no orbit to continue before the first point
        y, v = np.full(lanes, numbers.y0_m), np.zeros(lanes)
        app, period, continued = np.zeros(lanes), np.ones(lanes, dtype=np.int64), False
    else:  # settled orbits only, as steady_states asks of its seeds on the Python route
        period = check_period_guess(start.period).astype(np.int64)
        y, v = start.y_start_m.astype(float), start.v_start_m_s.astype(float)
        app, continued = start.app_m.astype(float), True
    table_steps, table_offset, tables = _drive_tables(steps, refinements)
    cap, limit = settling_cap(freq, numbers, max_periods), divergence_limit(model, freq)
    settings = (method == "newton", float(tol), -1.0 if app_rtol is None else float(app_rtol),
                int(refinements), MAX_STEPS, float(numbers.y0_m or 1.0), tables, table_steps,
                table_offset)
    count = (sweep_threads(lanes, kernels.VECTOR_LANES) if threads is None
             else check_int("threads", threads, minimum=1))
    groups = deal_lanes(lanes, count)

    def run_group(group: np.ndarray, report, stop: threading.Event) -> Orbits:
        seed = [np.ascontiguousarray(a[group]) for a in (y, v, app, period)]
        try:
            return _sweep_group(kernels, freq[group], p_a[group], steps[group], cap[group],
                         limit[group], seed, continued, settings, app_rtol,
                         numbers.fastest_rate_per_s, report, stop, block_seconds)
        except BaseException:
            stop.set()  # the other groups stop after their block
            raise

    if count == 1:
        return run_group(groups[0], done, threading.Event())
    bar, stop = _Progress(done, count), threading.Event()
    with ThreadPoolExecutor(count, thread_name_prefix="sweep") as pool:
        futures = [pool.submit(run_group, group, bar.reporter(k), stop)
                   for k, group in enumerate(groups)]
        try:
            parts = [future.result() for future in futures]
        except BaseException:  # Ctrl-C too: the other groups stop after their block
            stop.set()
            raise
    return _interleave(parts, groups, freq.shape)


def _sweep_group(kernels, freq, p_a, steps, cap, limit, seed, continued, settings, app_rtol, rate,
                 done, stop: threading.Event, block_seconds: float) -> Orbits:
    """One group of lanes swept, a block of points per call, until the end or ``stop``."""
    blocks, first, size = [], 0, 1
    while first < freq.shape[1] and not stop.is_set():
        block = slice(first, min(first + size, freq.shape[1]))
        started = time.perf_counter()
        points = block.stop - block.start
        out = _driver(kernels, freq[:, block], p_a, steps[:, block], cap[:, block],
                      limit[:, block], *seed, continued, settings, loading=not blocks)
        p_a_table = np.broadcast_to(p_a, (points, freq.shape[0])).T
        blocks.append(_orbits(kernels, freq[:, block], p_a_table, *out, app_rtol, rate))
        seed, continued = _last_good(kernels, out[0], out[1], seed), True
        if done is not None:
            done(points)
        per_point = (time.perf_counter() - started) / points
        first, size = block.stop, max(1, int(block_seconds / max(per_point, 1e-9)))
    return Orbits.stack(blocks)


class _Progress:
    """``done(points)`` for groups swept at once: the points every group has passed."""

    def __init__(self, done, groups: int):
        self.done, self.passed, self.told = done, [0] * groups, 0
        self.lock = threading.Lock()

    def reporter(self, group: int):
        def report(points: int) -> None:
            with self.lock:
                self.passed[group] += points
                now = min(self.passed)
                if self.done is not None and now > self.told:
                    self.done(now - self.told)
                self.told = now
        return report


def _interleave(parts: list[Orbits], groups: list[np.ndarray], shape) -> Orbits:
    """The groups' points as one sweep's: point after point, the lanes of each in order."""
    lanes, points = shape
    row = [(np.arange(points)[:, None] * lanes + group[None, :]).ravel() for group in groups]
    return Orbits.stack(parts).take(np.argsort(np.concatenate(row)))


def _driver(kernels, freq, p_a, steps, cap, limit, y, v, app, period, continued, settings,
            loading: bool):
    """One compiled call of the driver on a block of points (contiguous copies). The first
    call (``loading``) loads its machine code: an error there, on checked inputs, is a
    broken cache (``DriverUnusable``); an error in a later block is raised as it is."""
    block = [np.ascontiguousarray(a) for a in (freq, steps, cap, limit)]
    try:
        return kernels.sweep_lanes(block[0], p_a, block[1], block[2], block[3], y, v, app,
                                   period, continued, *settings)
    except Exception as error:
        if _interrupted(error):  # a Ctrl-C during the call surfaces as a SystemError
            raise KeyboardInterrupt from None
        if not loading:
            raise
        raise DriverUnusable(f"the compiled sweep driver could not be loaded ({error!r})") \
            from error


def _interrupted(error: BaseException | None) -> bool:
    while error is not None:
        if isinstance(error, KeyboardInterrupt):
            return True
        error = error.__cause__ or error.__context__
    return False


def _last_good(kernels, fl, it, seed) -> list[np.ndarray]:
    """Each lane's seed after a block: its last settled or under-resolved orbit (the
    driver's rule for the next point), or the seed it came in with."""
    y, v, app, period = (a.copy() for a in seed)
    status = it[:, :, kernels.I_STATUS]
    good = (status == Status.SUCCESS) | (status == Status.UNDER_RESOLVED)
    lanes = np.flatnonzero(good.any(axis=1))
    last = good.shape[1] - 1 - np.argmax(good[lanes, ::-1], axis=1)
    row = fl[lanes, last]
    y[lanes], v[lanes] = row[:, kernels.F_Y], row[:, kernels.F_V]
    app[lanes] = row[:, kernels.F_YMAX] - row[:, kernels.F_YMIN]
    period[lanes] = it[lanes, last, kernels.I_PERIOD]
    return [y, v, app, period]


def _drive_tables(steps: np.ndarray, refinements: int):
    """Every step count a pass or its half-step estimate may take, and their drive
    tables in one flat array: (counts, offsets, tables)."""
    passes = np.unique(np.concatenate(
        [np.minimum(np.unique(steps) * 2**level, MAX_STEPS) for level in range(refinements + 1)]))
    counts = np.unique(np.concatenate([passes, np.maximum(passes // 2, 2)]))
    parts = [drive_table(int(n)) for n in counts]
    offsets = np.cumsum([0] + [part.size for part in parts[:-1]]).astype(np.int64)
    tables = np.concatenate(parts)
    # Read-only as drive_table's own: the kernels are called with the types they were
    # compiled for on the Python route (no second specialisation to compile).
    tables.flags.writeable = False
    return counts.astype(np.int64), offsets, tables


def _orbits(kernels, freq, p_a, fl, it, mult, extrema, counts, app_rtol, rate) -> Orbits:
    """The driver's tables as ``Orbits``, point after point (all lanes of a point together)."""
    lanes, points = freq.shape
    point_major = lambda a: np.swapaxes(a, 0, 1).reshape(lanes * points, *a.shape[2:])  # noqa

    fl, it, mult = point_major(fl), point_major(it), point_major(mult)
    # Lane-major: maxima, minima of each point (slices: np.split takes 5x as long).
    bounds = np.concatenate([[0], np.cumsum(counts.ravel())]).tolist()
    pieces = [extrema[a:b] for a, b in zip(bounds[:-1], bounds[1:])]
    order = (np.arange(lanes)[None, :] * points + np.arange(points)[:, None]).ravel()
    k = kernels
    status = it[:, k.I_STATUS].copy()
    orbits = Orbits(
        frequency_hz=point_major(freq), p_a_n=point_major(p_a).astype(float), status=status,
        message=[""] * status.size, period=it[:, k.I_PERIOD].copy(),
        ymin_m=fl[:, k.F_YMIN].copy(), ymax_m=fl[:, k.F_YMAX].copy(),
        maxima_m=[pieces[2 * i] for i in order], minima_m=[pieces[2 * i + 1] for i in order],
        y_start_m=fl[:, k.F_Y].copy(), v_start_m_s=fl[:, k.F_V].copy(), multipliers=mult,
        method=np.array(k.METHODS, dtype=object)[it[:, k.I_METHOD]],
        steps_used=it[:, k.I_STEPS].copy(), periods_run=it[:, k.I_RUN].copy(),
        error_estimate=fl[:, k.F_ERROR].copy(),
    )
    for i in np.flatnonzero(status != Status.SUCCESS):  # the few points with a message
        orbits.message[i] = _message(Status(status[i]), orbits, i, it[i], k, app_rtol, rate)
    return orbits


def _message(status: Status, orbits: Orbits, i: int, row, k, app_rtol, rate) -> str:
    """``shooting._fate``'s message of point i."""
    steps = int(row[k.I_STEPS])
    if status == Status.FAILED:
        f_e = orbits.frequency_hz[i]
        return failure_message(f_e, orbits.p_a_n[i], int(row[k.I_FAILED_AT]),
                               rate * (1.0 / (steps * f_e)))  # rate * Lanes.dt
    if status == Status.UNDER_RESOLVED:
        return under_resolved_message(orbits.error_estimate[i], app_rtol, steps)
    return not_settled_message(int(row[k.I_CAP]))
