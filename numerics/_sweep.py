"""Frequency sweeps up and down, for many force amplitudes at once (Fig. 2, 3).

Each point starts from the previous point's steady state, as in the paper's
method; every (amplitude, direction) pair is a lane, and all lanes advance
through their frequency lists together. The walk runs in one compiled call per
sweep (``_sweep_template.sweep_lanes``, which does per point what ``steady_states``
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

from common import Result, Status, check_choice, lane_array, lookup, progress, result
from perturb import ContactModel, eq26_numbers

from ._codegen import CacheWarning, forget_sweep_driver, sweep_driver_built
from ._orbits import Orbits, fates
from ._simulate import check_model
from ._steady import DEFAULTS, check_steps, steady_states
from ._sweep_compiled import DriverUnusable, supported, sweep_lanes_compiled

__all__ = ["SweepRun", "Sweep", "sweep", "DIRECTIONS"]

DIRECTIONS = ("up", "down", "both")
#: How the points are walked: one compiled call per sweep, or steady_states per point;
#: "auto" takes the compiled call where its driver is built for the model (building it
#: costs tens of seconds once per model: a saving only after dozens of sweeps).
ENGINES = ("auto", "compiled", "python")
#: A step in App by more than this factor between neighbouring points is a candidate
#: jump: ``sweep`` checks whether it leaves the branch (``_left_branch``).
JUMP_RATIO = 1.3
#: The relative App within which the orbit of point i, followed back to point i-1's
#: frequency, is the orbit of point i-1 (the same branch).
SAME_BRANCH_RTOL = 0.01
#: The most steady states one sweep computes (points x amplitudes x directions): about
#: 12,000 are found per second at the paper's settings, so this is a minute or two.
MAX_STATES = 1_000_000


@result
class SweepRun(Orbits):
    """One amplitude swept in one direction: the ``Orbits`` columns, in the order swept.

    ``jumped[i]``: the sweep left its branch between points i-1 and i (checked by
    ``sweep``: the orbit of point i, followed back to the frequency of point i-1, is
    not the orbit of point i-1); None where no check was made.
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
        return _candidates(self.app_m, ratio).tolist()

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
            lines.append(f"  P_a = {run.pa_frac:.2f} Q {run.direction:>4}: max App "
                         f"{np.nanmax(settled, initial=0) * 1e9:9.1f} nm, jumps at "
                         f"{[float(f) for f in jumps]} Hz, contact lost at "
                         f"{int(run.contact_lost.sum())} points")
        return "\n".join(lines)


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
        The whole walk in one compiled call (with ``keep_orbits`` the Python route is
        taken), or point by point in Python (the reference); both give the same points.
        "auto" (the default) takes the compiled call where its driver is built for the
        model already (compiling it takes tens of seconds, once), Python otherwise.

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
    check_steps(steps_per_period)
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
    points = _sweep_lanes(freq, p_a, model, quiet, steps_per_period=steps_per_period, tol=tol,
                          app_rtol=app_rtol, max_periods=max_periods, method=method,
                          refinements=refinements, keep_orbits=keep_orbits, engine=engine)
    runs = [
        SweepRun(pa_frac=float(frac), direction=d,
                 **points.take(np.arange(i, points.status.size, len(lanes))).columns())
        for i, (frac, d) in enumerate(lanes)
    ]
    _check_jumps(runs, model, steps_per_period=steps_per_period, tol=tol,
                 app_rtol=app_rtol, max_periods=max_periods, method=method,
                 refinements=refinements)
    settings = {"frequency_hz": grid.tolist(), "pa_frac": fracs.tolist(), "direction": direction,
                "steps_per_period": steps_per_period, "tol": tol, "app_rtol": app_rtol,
                "max_periods": max_periods,
                "method": method, "refinements": refinements, "keep_orbits": keep_orbits}
    return Sweep(model=model.as_dict(), settings=settings, runs=runs,
                 elapsed_s=time.perf_counter() - start)


def _candidates(app: np.ndarray, ratio: float = JUMP_RATIO) -> np.ndarray:
    """Indices i where App changes by more than ``ratio`` from point i-1 to i."""
    with np.errstate(divide="ignore", invalid="ignore"):
        change = np.maximum(app[1:] / app[:-1], app[:-1] / app[1:])
    return np.flatnonzero(change > ratio) + 1


def _check_jumps(runs: list[SweepRun], model: ContactModel, **accuracy) -> None:
    """Set ``jumped`` on every run: at each candidate step (App changes by more than
    ``JUMP_RATIO``) between two orbits (settled or under-resolved), the orbit of point i
    is followed back to the frequency of point i-1, all in one ``steady_states`` call. A
    fold lies between the points, and the sweep left its branch, unless that lands on
    the orbit of point i-1 (same period, App within ``SAME_BRANCH_RTOL``). A smooth
    curve on a coarse grid changes by more than the ratio at every step of a peak and
    has no jump; a sweep over a fold has one wherever the grid puts it.
    """
    steps = []  # (run, i)
    for r, run in enumerate(runs):
        good = run.settled | (run.status == Status.UNDER_RESOLVED)
        run.jumped = np.zeros(run.status.size, dtype=bool)
        steps += [(r, int(i)) for i in _candidates(run.app_m) if good[i] and good[i - 1]]
    if not steps:
        return
    at = [(runs[r], i) for r, i in steps]
    back = steady_states(
        np.array([run.frequency_hz[i - 1] for run, i in at]),
        np.array([run.p_a_n[i] for run, i in at]), model=model,
        y_init_m=np.array([run.y_start_m[i] for run, i in at]),
        v_init_m_s=np.array([run.v_start_m_s[i] for run, i in at]),
        period_guess=np.array([run.period[i] for run, i in at]),
        app_guess_m=np.array([run.app_m[i] for run, i in at]), **accuracy)
    for q, (run, i) in enumerate(at):
        same = (back.settled[q] and back.period[q] == run.period[i - 1]
                and abs(back.app_m[q] / run.app_m[i - 1] - 1) <= SAME_BRANCH_RTOL)
        run.jumped[i] = not same


def _sweep_lanes(freq, p_a, model, quiet, start: Orbits | None = None, *,
                 engine: str = "auto", **accuracy) -> Orbits:
    """Walk every lane through its frequencies; the points, frequency by frequency.

    ``engine="compiled"`` runs the whole walk in one compiled call (where it supports
    the settings: not with ``keep_orbits``), "python" point by point with
    ``steady_states``; both give the same points (tests/test_sweep_compiled.py).
    """
    check_choice("engine", engine, ENGINES)
    points = _walk(freq, p_a, model, quiet, start, engine, **accuracy)
    for row, seed_row in _unresolved_jumps(points, freq.shape[0]):
        if not _resweep_finer(points, row, seed_row, freq, p_a, model, engine, accuracy):
            _flag(points, row, seed_row)
    return points


def _walk(freq, p_a, model, quiet, start, engine, **accuracy) -> Orbits:
    """``_sweep_lanes``' walk by the engine asked for."""
    chosen = engine
    if engine == "auto":
        engine = "compiled" if sweep_driver_built(model) else "python"
    if engine == "compiled" and supported(accuracy):
        bar = progress(freq.shape[1], "sweep", quiet=quiet)
        try:
            points = sweep_lanes_compiled(freq, p_a, model, start, done=bar.update, **accuracy)
        except DriverUnusable as error:
            forget_sweep_driver(model)  # the next call that asks for it compiles it again
            if chosen != "auto":
                raise
            warnings.warn(f"{error}; its cache files are removed, this sweep takes the "
                          f"Python route", CacheWarning, stacklevel=2)
            bar.close()
            return _sweep_lanes_python(freq, p_a, model, quiet, start, **accuracy)
        bar.close()
        return points
    return _sweep_lanes_python(freq, p_a, model, quiet, start, **accuracy)


def _sweep_lanes_python(freq, p_a, model, quiet, start: Orbits | None = None,
                        **accuracy) -> Orbits:
    """The walk point by point, one ``steady_states`` call per frequency.

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
                              period_guess=period, app_guess_m=continued, **accuracy)
        # A settled orbit seeds the next point, an under-resolved one too (it is an
        # orbit, only its error estimate is above app_rtol); a failed or unsettled one never.
        good = point.settled | (point.status == Status.UNDER_RESOLVED)
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
                   accuracy: dict) -> bool:
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
        check_steps(finer, accuracy["refinements"])
    except ValueError:
        return False
    again = _sweep_lanes(freq[lane:lane + 1, point:], p_a[lane:lane + 1], model, True,
                         start=points.take([seed_row]), engine=engine,
                         **(accuracy | {"steps_per_period": finer}))
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
