"""Frequency sweeps up and down, for many force amplitudes at once (Fig. 2, 3).

Each point starts from the previous point's steady state, as in the paper's
method; every (amplitude, direction) pair is a lane, and all lanes advance
through their frequency lists together. The sweep runs in one compiled call per
sweep (``kernels.sweep_template.sweep_lanes``, which does per point what ``steady_states``
does) or point by point in Python, one ``steady_states`` call per frequency
(``engine="python"``, the reference); tests/test_sweep_compiled.py holds them
equal. The compiled driver takes tens of seconds to build once per model
(bench_sweep's cold start row), so the default, "auto", takes it only where it is
built already.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import (
    Result,
    Status,
    check_choice,
    check_int,
    lane_array,
    lookup,
    progress,
    result,
)

from ..kernels.codegen import CacheWarning, forget_sweep_driver, sweep_driver_built
from ..simulation.ranges import check_tested
from ..simulation.rk4 import check_model
from .options import SteadyOptions, check_steps, steady_options
from .orbits import Orbits, fates
from .shooting import DEFAULTS, steady_settings, steady_states
from .sweep_compiled import DriverUnusable, supported, sweep_lanes_compiled

__all__ = ["SweepRun", "Sweep", "sweep", "DIRECTIONS"]

DIRECTIONS = ("up", "down", "both")
#: How the points are swept: one compiled call per sweep, or steady_states per point;
#: "auto" takes the compiled call where its driver is built for the model (building it
#: costs tens of seconds once per model: a saving only after dozens of sweeps).
ENGINES = ("auto", "compiled", "python")
#: A step in App by more than this factor between neighbouring points is a candidate
#: jump: ``sweep`` checks whether it leaves the branch (``_check_jumps``).
JUMP_RATIO = 1.3
#: The step, relative to f_e, to which ``_check_jumps`` halves a candidate step.
JUMP_RESOLUTION = 1e-4
#: The most candidate steps of one sweep that ``_check_jumps`` checks (each costs one
#: steady state, and two per halving: some 30 at most); past them no step is checked
#: (``jumped`` is None: jumps by App's change alone), so that the check stays within the
#: sweep's own work.
MAX_CHECKED_STEPS = 10_000
#: App below this fraction of |y| is at the round-off of y (some 4,500 units in the last
#: place): its changes from point to point are noise, never a jump.
ROUND_OFF_APP = 1e-12
#: The most steady states one sweep computes (points x amplitudes x directions): about
#: 12,000 are found per second at the paper's settings, so this is a minute or two; the
#: command at the limit peaks at 1.1 GB (tests/benchmarks/bench_limits.py).
MAX_STATES = 1_000_000


@result
class SweepRun(Orbits):
    """One amplitude swept in one direction: the ``Orbits`` columns, in the order swept.

    ``jumped[i]``: the sweep left its branch between points i-1 and i (checked by
    ``sweep``, ``_check_jumps``: the orbit after the step lands elsewhere when followed
    back, or halving the step finds two orbits, or a change that does not shrink with
    the half); None where no check was made.
    """

    pa_frac: float
    direction: str
    jumped: np.ndarray | None = None

    def jumps(self, ratio: float = JUMP_RATIO) -> list[int]:
        """Indices i where the sweep jumps from point i-1 to i: where it left its branch
        (``jumped``), or, for a run without that check, where App changes by more than
        ``ratio``."""
        if self.jumped is not None:
            return np.flatnonzero(self.jumped).tolist()
        return [int(i) for i in _candidates(self.app_m, ratio) if _above_round_off(self, i)]

    def summary(self) -> str:
        return (f"SweepRun: P_a = {self.pa_frac:g} Q {self.direction}, {self.status.size} "
                f"points, {self.fates() or 'all settled'}")


@result
class Sweep(Result):
    """All runs of a sweep, with the model and the settings that made them."""

    model: dict
    settings: dict
    runs: list[SweepRun]
    elapsed_s: float

    def run(self, pa_frac: float, direction: str) -> SweepRun:
        """The run of one amplitude and direction (a KeyError lists the runs there are)."""
        return lookup(f"run with pa_frac={pa_frac!r}, direction={direction!r}", self.runs,
                      lambda r: np.isclose(r.pa_frac, pa_frac) and r.direction == direction,
                      lambda r: (r.pa_frac, r.direction))

    def summary(self) -> str:
        status = np.concatenate([r.status for r in self.runs]) if self.runs else np.empty(0)
        return (f"Sweep: {len(self.runs)} runs, {status.size} points, "
                f"{fates(status) or 'all settled'}, {self.elapsed_s:.3g} s")

    def table(self) -> str:
        lines = []
        for run in self.runs:
            jumps = [run.frequency_hz[i] for i in run.jumps()]
            settled = np.where(run.settled, run.app_m, np.nan)
            app = (f"{_short(np.nanmax(settled) * 1e9, 1, 9)} nm" if run.settled.any()
                   else "(none settled)")
            lines.append(f"  P_a = {_short(run.pa_frac, 2)} Q {run.direction:>4}: max App "
                         f"{app}, jumps at "
                         f"{[float(f) for f in jumps]} Hz, contact lost at "
                         f"{int(run.contact_lost.sum())} points")
        return "\n".join(lines)


def _short(value: float, decimals: int, width: int = 0) -> str:
    """``value`` with ``decimals`` decimals where that prints it to three significant
    digits or exactly, else in three significant digits; right-aligned in ``width``."""
    text = f"{value:.{decimals}f}"
    if float(text) != value and (value == 0 or abs(value) < 10 ** (2 - decimals)):
        text = f"{value:.3g}"
    return text.rjust(width)


def sweep(
    frequency_hz,
    pa_frac,
    *,
    direction: str = "both",
    model: ContactModel | None = None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    app_rtol: float | None = DEFAULTS["app_rtol"],
    max_periods: int | None = DEFAULTS["max_periods"],
    method: str = "newton",
    refinements: int = DEFAULTS["refinements"],
    keep_orbits: bool = False,
    quiet: bool = True,
    engine: str = "auto",
    unchecked: bool = False,
    options: SteadyOptions | None = None,
    max_checked_steps: int = MAX_CHECKED_STEPS,
) -> Sweep:
    """Sweep the excitation frequency up and/or down for each force amplitude.

    Parameters
    ----------
    frequency_hz : array_like
        The frequency grid f_e [Hz], increasing; "down" runs take it in reverse.
    pa_frac : float or array_like
        Force amplitudes P_a as fractions of the weight Q.
    direction : {"up", "down", "both"}
    model : ContactModel, optional
    steps_per_period, tol, app_rtol, max_periods, method, refinements, keep_orbits
        As in ``steady_states``.
    quiet : bool
        No progress bar on stderr.
    engine : {"auto", "compiled", "python"}
        The whole sweep in one compiled call (with ``keep_orbits`` the Python route is
        taken), or point by point in Python (the reference); both give the same points.
        "auto" (the default), as everywhere: the compiled route where it is built or
        builds within seconds; the driver takes tens of seconds to build, so "auto"
        takes it once it is built for the model (``make compiled``), Python before.
    unchecked : bool
        Go past the ranges of f_e, P_a and the contact where the answers are measured
        to hold (``numerics.simulation.ranges.TESTED``); refused otherwise.
    options : SteadyOptions, optional
        The steady-state settings as one object, in place of ``steps_per_period``,
        ``tol``, ``app_rtol``, ``max_periods``, ``method`` and ``refinements``. The
        compiled route is built with the default engine decisions: other decisions
        take the Python route.
    max_checked_steps : int
        Steps between neighbouring points whose App changes by more than
        ``JUMP_RATIO`` are checked for a jump with the full model (``SweepRun.jumped``);
        a sweep with more such steps than this checks none, and its runs' ``jumped`` is
        None: jumps by App's change alone (0: no check, the cheapest sweep).

    Examples
    --------
    >>> result = sweep([1300.0, 1350.0, 1400.0], 0.05, direction="up")
    >>> [round(float(a) * 1e9, 1) for a in result.runs[0].app_m]
    [48.1, 65.0, 106.1]
    """
    check_choice("direction", direction, DIRECTIONS)
    check_choice("engine", engine, ENGINES)
    model = check_model(model)
    grid = lane_array("frequency_hz", frequency_hz, positive=True)
    if grid.size > 1 and np.any(np.diff(grid) <= 0):
        raise ValueError("`frequency_hz` must be strictly increasing.")
    fracs = lane_array("pa_frac", pa_frac)
    if np.unique(fracs).size != fracs.size:
        raise ValueError(f"`pa_frac` must not repeat an amplitude, got {fracs.tolist()}.")
    options = steady_options(options, steps_per_period=steps_per_period, tol=tol,
                             app_rtol=app_rtol, max_periods=max_periods, method=method,
                             refinements=refinements)
    max_checked_steps = check_int("max_checked_steps", max_checked_steps, minimum=0)
    check_tested(grid, fracs, model, unchecked=unchecked)
    directions = ("up", "down") if direction == "both" else (direction,)
    states = grid.size * fracs.size * len(directions)
    if states > MAX_STATES:
        raise ValueError(
            f"`frequency_hz` x `pa_frac` x directions asks for {states} steady states, more "
            f"than the limit of {MAX_STATES} (about 80 s at the paper's settings); split the "
            "band or the amplitudes.")
    lanes = [(frac, d) for frac in fracs for d in directions]
    order = {"up": grid, "down": grid[::-1]}
    freq = np.array([order[d] for _, d in lanes])  # (lanes, points)
    p_a = np.array([frac for frac, _ in lanes]) * model.parameters.Q_n

    start = time.perf_counter()
    points = sweep_points(freq, p_a, model, quiet, options=options, keep_orbits=keep_orbits,
                          engine=engine)
    runs = [
        SweepRun(pa_frac=float(frac), direction=d,
                 **points.take(np.arange(i, points.status.size, len(lanes))).columns())
        for i, (frac, d) in enumerate(lanes)
    ]
    _check_jumps(runs, model, options, max_checked_steps)
    settings = {"frequency_hz": grid.tolist(), "pa_frac": fracs.tolist(), "direction": direction,
                **steady_settings(options), "keep_orbits": keep_orbits,
                **({"unchecked": True} if unchecked else {}),
                **({"max_checked_steps": max_checked_steps}
                   if max_checked_steps != MAX_CHECKED_STEPS else {})}
    return Sweep(model=model.as_dict(), settings=settings, runs=runs,
                 elapsed_s=time.perf_counter() - start)


def _candidates(app: np.ndarray, ratio: float = JUMP_RATIO) -> np.ndarray:
    """Indices i where App changes by more than ``ratio`` from point i-1 to i."""
    with np.errstate(divide="ignore", invalid="ignore"):
        change = np.maximum(app[1:] / app[:-1], app[:-1] / app[1:])
    return np.flatnonzero(change > ratio) + 1


def _above_round_off(run: SweepRun, i: int) -> bool:
    """Whether both orbits' App at points i-1 and i lie above the round-off of y
    (``ROUND_OFF_APP``)."""
    pair = slice(i - 1, i + 1)
    scale = np.maximum(np.abs(run.ymin_m[pair]), np.abs(run.ymax_m[pair]))
    return bool((run.app_m[pair] > ROUND_OFF_APP * scale).all())


def _beyond_errors(run: SweepRun, i: int) -> bool:
    """Whether App changes from point i-1 to i by more than the two orbits' estimated
    errors (``error_estimate``, relative; none known counts as none), both orbits' App
    above the round-off of y. (A change within the estimates between two under-resolved
    orbits is not checked: the orbits are not known well enough to tell a jump.)"""
    if not _above_round_off(run, i):
        return False
    pair = slice(i - 1, i + 1)
    error = np.nan_to_num(run.error_estimate[pair] * run.app_m[pair])
    return bool(abs(run.app_m[i] - run.app_m[i - 1]) > error.sum())


def _check_jumps(runs: list[SweepRun], model: ContactModel, options: SteadyOptions,
                 most: int) -> None:
    """Set ``jumped`` on every run: whether the sweep left its branch at each step where
    App changes by more than ``JUMP_RATIO`` between two orbits (settled or
    under-resolved). A smooth peak on a coarse grid changes by more than the ratio at
    every step and has no jump; a bent one has one wherever the grid puts it.

    First, the orbit after the step is followed back to the frequency before it: if it
    lands elsewhere than the sweep's orbit there (App off by more than 1 % or another
    period), two orbits coexist there and the sweep left a branch. If it lands on it,
    the step may still hold a whole bistable band narrower than the grid's step, or
    none: it is halved again and again, as a finer sweep would take it, until the half
    is below ``JUMP_RESOLUTION`` of f_e (``_jump_within``). A midpoint with two orbits
    (reached from either end) is a jump; a smooth change shrinks with the half and a
    jump does not, so the step also jumps where the last half still holds a quarter of
    the step's change. A point where no orbit is found (neither settled nor
    under-resolved) counts as a jump. A sweep with more than ``most`` candidate steps
    is not checked (``jumped`` stays None). Nor is a change of App within
    the two orbits' own error estimates (App at the round-off of y, under-resolved).
    """
    steps = []  # (run, i): the step from point i-1 to point i
    for run in runs:
        good = run.orbit_found
        run.jumped = np.zeros(run.status.size, dtype=bool)
        steps += [(run, int(i)) for i in _candidates(run.app_m)
                  if good[i] and good[i - 1] and _beyond_errors(run, i)]
    if len(steps) > most:  # past the bound: no run is checked, and each
        for run in runs:  # says so (``jumped`` None: App's ratio alone)
            run.jumped = None
        return
    if not steps:
        return
    column = lambda name, shift: np.array([getattr(run, name)[i - shift]  # noqa: E731
                                           for run, i in steps])
    f_lo, f_hi, p_a = column("frequency_hz", 1), column("frequency_hz", 0), column("p_a_n", 0)
    app_lo, app_hi = column("app_m", 1), column("app_m", 0)
    back = steady_states(f_lo, p_a, model=model, y_init_m=column("y_start_m", 0),
                         v_init_m_s=column("v_start_m_s", 0), period_guess=column("period", 0),
                         app_guess_m=app_hi, options=options)
    jumped = ~back.orbit_found | (back.period != column("period", 1)) | (
        np.abs(back.app_m / app_lo - 1) > 0.01)
    same = np.flatnonzero(~jumped)
    if same.size:
        ends = [{"f": f, "p_a": p_a[same], "app": app[same].copy(),
                 **{name: column(key, shift)[same] for name, key in (
                     ("y", "y_start_m"), ("v", "v_start_m_s"), ("period", "period"))}}
                for f, app, shift in ((f_lo[same], app_lo, 1), (f_hi[same], app_hi, 0))]
        jumped[same] = _jump_within(*ends, model, options)
    for (run, i), jump in zip(steps, jumped):
        run.jumped[i] = jump


def _jump_within(lo: dict, hi: dict, model, options: SteadyOptions) -> np.ndarray:
    """Whether each step holds a jump, by bisection (``_check_jumps``). ``lo`` and
    ``hi`` hold, per step, the frequency ``f``, the force ``p_a`` and the orbit (``y``,
    ``v``, ``period``, ``app``) at its two ends; every step of the batch moves together.

    The midpoint is reached from both ends. Two orbits there: the sweep left its branch.
    One: a bistable band, if any, lies in one half, the one whose end that orbit is
    farther from in log App (from the start, the forward orbit ends where the band
    begins; from the end, the backward one where it ends).
    """
    change = np.abs(np.log(hi["app"] / lo["app"]))
    jumped = np.zeros(change.size, dtype=bool)
    active = np.arange(change.size)
    while active.size:
        mid = (lo["f"][active] + hi["f"][active]) / 2
        both = steady_states(
            np.concatenate([mid, mid]), np.concatenate([lo["p_a"][active]] * 2), model=model,
            **{f"{key}": np.concatenate([lo[name][active], hi[name][active]])
               for key, name in (("y_init_m", "y"), ("v_init_m_s", "v"),
                                 ("period_guess", "period"), ("app_guess_m", "app"))},
            options=options)
        n = active.size
        good = both.orbit_found
        good = good[:n] & good[n:]
        app = both.app_m[:n]
        two = (both.period[:n] != both.period[n:]) | (np.abs(both.app_m[n:] / app - 1) > 0.01)
        jumped[active[~good | two]] = True
        go_on = good & ~two
        first = go_on & (np.abs(np.log(app / lo["app"][active]))
                         >= np.abs(np.log(hi["app"][active] / app)))
        for side, pick in ((hi, first), (lo, go_on & ~first)):
            at = active[pick]
            side["f"][at], side["app"][at] = mid[pick], app[pick]
            side["y"][at], side["v"][at] = both.y_start_m[:n][pick], both.v_start_m_s[:n][pick]
            side["period"][at] = both.period[:n][pick]
        narrow = go_on & (np.abs(hi["f"][active] - lo["f"][active]) < JUMP_RESOLUTION * mid)
        last = active[narrow]
        jumped[last] = np.abs(np.log(hi["app"][last] / lo["app"][last])) > change[last] / 4
        active = active[go_on & ~narrow]
    return jumped


def sweep_points(freq, p_a, model, quiet, start: Orbits | None = None, *,
                 options: SteadyOptions | None = None, keep_orbits: bool = False,
                 engine: str = "auto") -> Orbits:
    """Walk every lane through its frequencies; the points, frequency by frequency.

    ``engine="compiled"`` runs the whole sweep in one compiled call (where it supports
    the settings: not with ``keep_orbits``, nor with other engine decisions than the
    defaults), "python" point by point with ``steady_states``; both give the same points
    (tests/test_sweep_compiled.py).
    """
    check_choice("engine", engine, ENGINES)
    options = SteadyOptions() if options is None else options
    solve = {"options": options, "keep_orbits": keep_orbits}
    points = _points_by_engine(freq, p_a, model, quiet, start, engine, **solve)
    for row, seed_row in _unresolved_jumps(points, freq.shape[0]):
        if not _resweep_finer(points, row, seed_row, freq, p_a, model, engine, solve):
            _flag(points, row, seed_row)
    return points


def _points_by_engine(freq, p_a, model, quiet, start, engine, **solve) -> Orbits:
    """``sweep_points``' points by the engine asked for."""
    chosen = engine
    if engine == "auto":
        engine = "compiled" if sweep_driver_built(model) else "python"
    if engine == "compiled" and supported(**solve):
        bar = progress(freq.shape[1], "sweep", quiet=quiet)
        try:
            points = sweep_lanes_compiled(freq, p_a, model, start, done=bar.update, **solve)
        except DriverUnusable as error:
            forget_sweep_driver(model)  # the next call that asks for it compiles it again
            if chosen != "auto":
                raise
            warnings.warn(f"{error}; its cache files are removed, this sweep takes the "
                          f"Python route", CacheWarning, stacklevel=2)
            bar.close()
            return _sweep_lanes_python(freq, p_a, model, quiet, start, **solve)
        bar.close()
        return points
    return _sweep_lanes_python(freq, p_a, model, quiet, start, **solve)


def _sweep_lanes_python(freq, p_a, model, quiet, start: Orbits | None = None,
                        **solve) -> Orbits:
    """The sweep point by point, one ``steady_states`` call per frequency.

    Each point starts from the orbit of the last point that settled, under-resolved
    or not (the paper's method), or from rest if none has: a point that failed,
    diverged or did not settle is reported with its status, and its last state,
    which can be huge but finite, never seeds the next point. With ``start`` (one
    settled orbit per lane), the lanes continue from it instead of starting at rest.
    """
    found = []
    lanes = freq.shape[0]
    y = np.full(lanes, eq26_numbers(model.parameters).y0_m)  # rest
    v, app, period = np.zeros(lanes), np.zeros(lanes), np.ones(lanes, dtype=np.int64)
    continued = None  # no orbit to continue before the first point
    if start is not None:
        y, v = start.y_start_m.copy(), start.v_start_m_s.copy()
        app, period = start.app_m.copy(), start.period.copy()
        continued = app
    bar = progress(freq.shape[1], "sweep", quiet=quiet)
    for j in range(freq.shape[1]):
        point = steady_states(freq[:, j], p_a, model=model, y_init_m=y, v_init_m_s=v,
                              period_guess=period, app_guess_m=continued, **solve)
        # A settled orbit seeds the next point, an under-resolved one too (it is an
        # orbit, only its error estimate is above app_rtol); a failed or unsettled one never.
        good = point.orbit_found
        y = np.where(good, point.y_start_m, y)
        v = np.where(good, point.v_start_m_s, v)
        app = np.where(good, point.app_m, app)
        period = np.where(good, point.period, period)
        continued = app
        found.append(point)
        bar.update()
    bar.close()
    return Orbits.stack(found)


def _unresolved_jumps(points: Orbits, lanes: int) -> list[tuple[int, int]]:
    """(row, seed row) of the first settled point of each lane where it jumped off a branch
    that was under-resolved at the point it was continued from (its seed).

    Such a jump is where the coarse map's branch ends, and an under-resolved step moves
    a fold: at 16 steps a down sweep at 0.15 Q left the bouncing branch at 375 Hz, the
    1024-step sweep at 352.5 Hz (tests/test_hard_cases.py). ``points`` holds all lanes
    of a point together, point after point (row = point * lanes + lane).
    """
    status = points.status.reshape(-1, lanes)
    app = points.app_m.reshape(-1, lanes)
    good = (status == Status.SUCCESS) | (status == Status.UNDER_RESOLVED)
    # Each point's seed: the last good point before it in its lane (-1: none).
    index = np.where(good, np.arange(status.shape[0])[:, None], -1)
    seed = np.vstack([np.full((1, lanes), -1), np.maximum.accumulate(index, axis=0)[:-1]])
    has_seed = seed >= 0
    lane = np.broadcast_to(np.arange(lanes), status.shape)
    seed_status = np.where(has_seed, status[np.maximum(seed, 0), lane], Status.FAILED)
    seed_app = np.where(has_seed, app[np.maximum(seed, 0), lane], np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        change = np.maximum(app / seed_app, seed_app / app)
    jumped = ((status == Status.SUCCESS) & (seed_status == Status.UNDER_RESOLVED)
              & (change > JUMP_RATIO))
    first = [(int(np.argmax(jumped[:, k])), k) for k in range(lanes) if jumped[:, k].any()]
    return [(point * lanes + k, int(seed[point, k]) * lanes + k) for point, k in first]


def _resweep_finer(points: Orbits, row: int, seed_row: int, freq, p_a, model, engine,
                   solve: dict) -> bool:
    """Sweep the lane of ``row`` again from its seed's orbit, from ``row`` to its end, at
    twice the steps its seed was found with (and its refinements beyond), and put those
    points in place of its own: where the finer map's branch ends is where it jumps now.
    False (nothing changed) where those steps would pass ``MAX_STEPS``.

    The lane's later points move with it: the coarse lane went on along the branch it
    jumped to, which a finer sweep may not be on (0.15 Q down at 16 steps: 372.5-355 Hz
    were on the 36 nm orbit, 99.6 % below the 1024-step sweep's bouncing orbit).
    """
    lanes = freq.shape[0]
    point, lane = divmod(row, lanes)
    finer = 2 * int(points.steps_used[seed_row])
    try:
        check_steps(finer, solve["options"].refinements)
    except ValueError:
        return False
    finer_options = solve["options"].replace(steps_per_period=finer)
    again = sweep_points(freq[lane:lane + 1, point:], p_a[lane:lane + 1], model, True,
                         start=points.take([seed_row]), engine=engine,
                         **(solve | {"options": finer_options}))
    points.put(np.arange(row, points.status.size, lanes), again)
    return True


def _flag(points: Orbits, row: int, seed_row: int) -> None:
    """Mark the settled point ``row`` under-resolved: a jump off an under-resolved branch
    that could not be swept again at finer steps."""
    points.status[row] = Status.UNDER_RESOLVED
    points.message[row] = unresolved_jump_message(points.app_m[seed_row],
                                                  int(points.steps_used[seed_row]))


def unresolved_jump_message(seed_app_m: float, steps: int) -> str:
    """Why a settled point where a sweep jumped off an under-resolved branch is flagged."""
    return (f"under-resolved: the sweep jumped here off a branch (App {seed_app_m * 1e9:.4g} "
            f"nm) that was under-resolved at {steps} steps per period where it was "
            "continued from, and finer steps would pass the most steps per period, so where "
            "that branch ends is not resolved (a coarse step moves folds); this orbit is "
            "right to its error estimate")
