"""Pseudo-arclength continuation of periodic orbits in f_e, with their stability.

Sweeps see only stable states and jump where a branch folds. Here a periodic
orbit is followed continuously, stable or not: a point
of the branch is a zero of R(x, f) = Phi_p(x, f) - x, Phi_p being p periods
of the simulator's RK4 map at N fixed steps per period (``period_map``).

- Predictor: a step ds along the unit tangent t of the branch in the scaled
  unknowns z = (y / y0, v / (omega0 y0), f / f_n0).
- Corrector: Newton on the bordered system [R(z) = 0, t . (z - z_k) = ds], given up
  when an update is not at most half the one before (``WalkOptions.contraction``),
  stopped when the updates still to come add up to less than its tolerance
  (``period_map.near_enough``).
- Step control: ds grows by 1.5 after an easy step (at most 3 iterations), up to
  ds_max, or on a large orbit where the branch runs straight, up to ds_max times the
  orbit's size (``largest_step``); it shrinks by 2 on a failed Newton (by 4 below a
  corner's step, ``WalkOptions.corner_shrink``), and by the share of ``max_angle`` over
  the turn
  (by 2 at least) whenever consecutive tangents differ by more than ``max_angle``, so
  that no fold is stepped across unseen; over a step shorter than a corner's
  (``corner_step``: longer on a large orbit, at most ds_max) such a turn is taken for a
  corner of the map and the step accepted. A step below
  ``WalkOptions.stall_ds`` hands over to a step in f alone first (a corner where the
  branch turns
  back), and only then shrinks on.
- Stability: the Floquet multipliers, eigenvalues of the monodromy matrix; an orbit
  is stable when both lie inside the unit circle. As det M < 1 (the contact's
  damping), a multiplier leaves the circle only through +1 (a fold) or -1 (period
  doubling): no Neimark-Sacker point can arise in this model.
- Bifurcations: a fold where the f-component of t changes sign, a period doubling
  where det(M + I) does; each is located by Brent's method on the arclength,
  to ``LOCATE_TOL`` in z, and inserted in the branch (a fold once the walk has ended,
  and only one that is reported: near a turn of f, not a turn of a zigzag over the
  map's corners). One that Brent's method cannot
  locate (Newton cannot correct between the two points) is marked at a point of the
  branch within one step, and says so (``Bifurcation.located``, with the step's reach
  in the parameter as its tolerance).
- App of every point: one batched run of one orbit period of all points
  (``record_periods``, one lane per point, Hermite-refined extrema).
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq
from scipy.signal import find_peaks

from perturb import ContactModel, eq26_numbers
from perturb.common import Result, Status, check_choice, check_int, check_positive, progress, result

from ..kernels.lanes import Lanes
from ..simulation.rk4 import check_model
from ..steady.options import MAX_STEPS
from ..steady.shooting import PERIODS_TRIED, lane_steps, steady_states
from ..steady.sweeps import ENGINES
from .options import WalkOptions
from .period_map import PeriodMap, Point, floquet_multipliers

__all__ = ["Bifurcation", "Continuation", "ContinuedBranch", "continue_orbits", "DEFAULTS"]

DEFAULTS = {"steps_per_period": "auto", "ds_max": 0.02, "max_angle": 0.1, "max_points": 20_000}
#: The most points a walk may keep: some 830 bytes each, the result's included (measured
#: on the paper's branch at 0.15 Q by tests/test_continuation.py), so a walk at the limit
#: holds some 0.2 GB, and the few walks of one command (two step counts, the branches
#: switched to, a fold curve's two directions) stay well under 2 GiB; at the default steps
#: the paper's branch walks some 6,000 points a second.
MAX_WALK_POINTS = 250_000
#: The least N of "auto": the map's corners (a step's stage crossing y = 0) grow with the
#: step; at 0.15 Q, N = 128 shows zigzags of f by 0.27 Hz on the bouncing middle branch
#: (taken for folds) and stops at 398 Hz, N = 512 none and reaches 355 Hz (352.55 Hz with
#: the contraction test and the steps past ds_max, 354.00 Hz with ``corner_step`` and
#: corner_shrink: ``corner_step`` alone gave 352.33 Hz; 2026-11-24, both engines).
_AUTO_MIN_STEPS = 512
#: "auto" doubles N, up to this, while a walk stops inside the band at a corner: at 0.15 Q
#: the walk up stops near the bouncing fold (354.00 Hz) at 512 steps, and the branch passes
#: it (the fold at 352.4 Hz, where a 1024-step sweep jumps) at 1024.
_AUTO_MAX_STEPS = 2048
#: How the message of a walk that stopped at a corner begins.
_STUCK = "step below"
#: Brent's method locates a bifurcation to this arclength in z: f to about 1e-5 Hz on
#: the paper's model (f_n0 = 1485 Hz), App to 1e-9 y0.
LOCATE_TOL = 1e-8
KINDS = ("fold", "period-doubling")


@result
class ContinuedBranch(Result):
    """One continued branch of p-periodic orbits, point by point along its arclength.

    Attributes
    ----------
    frequency_hz : ndarray
        f_e of each point [Hz] (not monotonic: it turns back at each fold; constant along
        a branch continued in P_a).
    pa_frac : ndarray
        P_a / Q of each point (constant along a branch continued in f_e).
    app_m : ndarray
        App = max y - min y over one orbit period (p excitation periods) [m].
    stable : ndarray of bool
        Both Floquet multipliers inside the unit circle.
    period : int
        p, the orbit's period in excitation periods.
    multipliers : ndarray, shape (points, 2), complex
        The Floquet multipliers of each point.
    y_start_m, v_start_m_s : ndarray
        The orbit's state at phase 0 [m, m/s].
    status : int
        ``common.Status``: success when the branch reached the band's end.
    message : str
        Why the branch ended early ("" when it reached the end).
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    frequency_hz: np.ndarray
    app_m: np.ndarray
    stable: np.ndarray
    period: int
    multipliers: np.ndarray
    y_start_m: np.ndarray
    v_start_m_s: np.ndarray
    status: int = int(Status.SUCCESS)
    message: str = ""
    pa_frac: np.ndarray | None = None

    @classmethod
    def from_dict(cls, data: dict) -> ContinuedBranch:
        branch = super().from_dict(data)
        branch.stable = np.asarray(branch.stable, dtype=bool)
        return branch

    def summary(self) -> str:
        return (f"ContinuedBranch: period {self.period}, {self.frequency_hz.size} points "
                f"({int(self.stable.sum())} stable), {Status(self.status).name.lower()}"
                + (f": {self.message}" if self.message else ""))


@result
class Bifurcation(Result):
    """A fold (a multiplier through +1) or a period doubling (through -1) on a branch.

    Attributes
    ----------
    kind : str
        "fold" or "period-doubling" (in JSON it takes the place of the class name: a
        bifurcation is read back through its parent).
    frequency_hz, app_m, pa_frac : float
        Where it is: a point of its branch.
    located : bool or None
        Located by Brent's method between two points of the branch (to ``LOCATE_TOL``
        in z, some 1.5e-5 Hz), or, where Newton cannot correct between them (a corner
        of the map) or f merely turns, only marked at a point within one step of it.
        None (null in JSON): unknown, in a file saved before this field existed (such
        files also held marked bifurcations, not told apart).
    frequency_tol_hz, pa_frac_tol : float
        How far the bifurcation of the N-step period map may lie from ``frequency_hz``
        and ``pa_frac`` (0 in the one held fixed): located, Brent's tolerance; marked,
        the step's reach in the parameter (its length times the larger rate of the
        parameter along the branch at its ends). A fold about which the map's corners
        make f zigzag (each turn a fold of the discrete map, closer than the 1e-4 f_n0
        that tells folds apart) is known to that resolution: 1e-4 f_n0 at least
        (0.149 Hz on the paper's model). Compare a
        sweep's jump with ``frequency_hz`` to within the sweep's grid spacing plus
        ``frequency_tol_hz``.
        NaN (null in JSON): unknown, in a file saved before these fields existed.
    """

    kind: str
    frequency_hz: float
    app_m: float
    pa_frac: float
    located: bool | None
    frequency_tol_hz: float
    pa_frac_tol: float

    @classmethod
    def from_dict(cls, data: dict) -> Bifurcation:
        """As ``Result.from_dict``; a file saved before ``located``, ``frequency_tol_hz``
        and ``pa_frac_tol`` existed loads with them unknown (None, NaN, NaN): a user's
        saved results are not lost."""
        return super().from_dict({**_UNKNOWN_PRECISION, **data})

    def summary(self) -> str:
        return (f"Bifurcation: {self.kind} at {self.frequency_hz:.6g} Hz, App "
                f"{self.app_m * 1e9:.4g} nm, P_a = {self.pa_frac:g} Q, {self.precision()}")

    def precision(self) -> str:
        """"located to +-x" or "marked within one step, +-x", in the parameter walked
        ("precision unknown" when the file it was read from did not say)."""
        if self.located is None or np.isnan([self.frequency_tol_hz, self.pa_frac_tol]).any():
            return "precision unknown (saved before it was recorded)"
        how = "located to" if self.located else "marked within one step,"
        if self.pa_frac_tol > self.frequency_tol_hz == 0.0:
            return f"{how} +-{self.pa_frac_tol:.2g} Q"
        return f"{how} +-{self.frequency_tol_hz:.2g} Hz"


#: The fields a ``Bifurcation`` saved before they existed is read with: unknown.
_UNKNOWN_PRECISION = {"located": None, "frequency_tol_hz": None, "pa_frac_tol": None}


@result
class Continuation(Result):
    """Branches of periodic orbits continued in f_e at one P_a, and their bifurcations.

    Attributes
    ----------
    pa_frac : float
        P_a / Q.
    branches : list of ContinuedBranch
    bifurcations : list of Bifurcation
        In the order met along the branches.
    model, settings : dict
        The model (``ContactModel.as_dict()``); fmin_hz, fmax_hz, steps_per_period
        (the N used), ds_max, max_angle, max_points, engine (the one that ran).
    elapsed_s : float
    """

    pa_frac: float
    branches: list[ContinuedBranch]
    bifurcations: list[Bifurcation]
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def folds(self) -> list[Bifurcation]:
        return [b for b in self.bifurcations if b.kind == "fold"]

    def summary(self) -> str:
        return (f"Continuation: P_a = {self.pa_frac:g} Q, {len(self.branches)} branch(es), "
                f"{sum(b.frequency_hz.size for b in self.branches)} points, "
                f"{count_kinds(self.bifurcations)}, {self.elapsed_s:.3g} s")

    def table(self) -> str:
        lines = [f"  {b.summary()}" for b in self.branches]
        lines += [f"  {b.kind:<16} {b.frequency_hz:>12.6f} Hz, {b.precision()}  App "
                  f"{b.app_m * 1e9:>9.4f} nm" for b in self.bifurcations]
        return "\n".join(lines)


def continue_orbits(
    pa_frac: float,
    fmin_hz: float,
    fmax_hz: float,
    *,
    model: ContactModel | None = None,
    period: int = 1,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    ds_max: float = DEFAULTS["ds_max"],
    max_angle: float = DEFAULTS["max_angle"],
    max_points: int = DEFAULTS["max_points"],
    quiet: bool = True,
    engine: str = "auto",
    options: WalkOptions | None = None,
) -> Continuation:
    """Continue the p-periodic orbit reached at ``fmin_hz`` from rest up to ``fmax_hz``.

    Parameters
    ----------
    pa_frac : float
        Force amplitude P_a / Q (> 0).
    fmin_hz, fmax_hz : float
        The band of f_e [Hz]; the branch starts at the stable orbit that time
        marching from rest reaches at ``fmin_hz`` (``steady_states``) and ends where
        it reaches ``fmax_hz``. If it ends inside the band (Newton cannot pass a
        corner of the piecewise smooth map) a second walk starts from the orbit
        reached at ``fmax_hz``, down in f; where the two walks end at the same point
        they are one branch, otherwise two.
    model : ContactModel, optional
        The paper's full model by default.
    period : int
        p of the orbit (1 to 8); the orbit reached at ``fmin_hz`` must have it.
    steps_per_period : int or "auto"
        N, fixed along the branch (so that the period map is smooth in f_e); "auto"
        takes ``steady_states``' choice at ``fmin_hz`` (the finest of the band), but at
        least 512, and walks again at twice N (up to 2048) while a walk stops inside the
        band at a corner of the map (``settings["steps_per_period"]`` says which N).
    ds_max : float
        Largest step along the branch, in the scaled unknowns z, for orbits within twice
        the static deflection; where a larger (bouncing) orbit's branch runs straight, a
        step may be ds_max times |(y, v)| / 2 in z, up to 20 ds_max (``largest_step``).
    max_angle : float
        Largest angle [rad] between the tangents of consecutive points, except over
        steps shorter than a corner's step (``corner_step``).
    max_points : int
        A walk gives up after this many points; the folds located once it has ended
        are added to them (one per fold reported). At most ``MAX_WALK_POINTS``
        (250,000: some 0.2 GB a walk).
    quiet : bool
        No progress bar on stderr.
    engine : {"auto", "compiled", "python"}
        The walk's steps (predictor, Newton, step control) in compiled code, handing
        back to Python only where a bifurcation is located or the band ends
        ("compiled": built once per model, some 12 s), or step by step in Python (the
        reference). "auto" (the default), as everywhere: the compiled route where it is
        built or builds within seconds, as the walk does; so "auto" compiles here.
        Both walk the same branch, to Newton's tolerance, but where the map's corners
        crowd (loss of contact) a round-off can end a walk at another corner.
    options : WalkOptions, optional
        The walk's tuning: its step control and corrector (the tested defaults by
        default).

    Returns
    -------
    Continuation

    Examples
    --------
    >>> run = continue_orbits(0.05, 1300.0, 1600.0)
    >>> [(b.kind, round(b.frequency_hz)) for b in run.bifurcations]
    [('fold', 1420), ('fold', 1373)]
    """
    model = check_model(model)
    pa_frac = check_positive("pa_frac", pa_frac)
    fmin_hz, fmax_hz = check_positive("fmin_hz", fmin_hz), check_positive("fmax_hz", fmax_hz)
    if not fmin_hz < fmax_hz:
        raise ValueError(f"`fmax_hz` must be above `fmin_hz`, got {fmin_hz!r} and {fmax_hz!r}.")
    ds_max, max_angle, max_points = check_walk(period, ds_max, max_angle, max_points)
    check_choice("engine", engine, ENGINES)
    options = check_options(options)
    numbers = eq26_numbers(model.parameters)
    check_band("fmin_hz", fmin_hz, model.parameters)
    check_band("fmax_hz", fmax_hz, model.parameters)
    steps = branch_steps(steps_per_period, fmin_hz, numbers)
    start = time.perf_counter()
    p_a = pa_frac * model.parameters.Q_n
    shoot, branches, bifurcations = walk_finest(
        lambda n: PeriodMap(model, p_a, n, period, engine, options), steps,
        steps_per_period == "auto",
        model, fmin_hz, fmax_hz, ds_max, max_angle, max_points, quiet)
    settings = {"fmin_hz": fmin_hz, "fmax_hz": fmax_hz,
                **walk_settings(shoot, ds_max, max_angle, max_points)}
    return Continuation(pa_frac=pa_frac, branches=branches, bifurcations=bifurcations,
                        model=model.as_dict(), settings=settings,
                        elapsed_s=time.perf_counter() - start)


def walk_settings(shoot: PeriodMap, ds_max, max_angle, max_points) -> dict:
    """The settings of a walk on ``shoot`` for a result: the N it took, the step control
    (with the walk's ``WalkOptions``) and the engine that ran."""
    return {"steps_per_period": shoot.steps, "ds_max": ds_max, "max_angle": max_angle,
            "max_points": max_points,
            "engine": "python" if shoot.walker is None else "compiled",
            "walk_options": shoot.options.as_dict()}


def check_options(options: WalkOptions | None) -> WalkOptions:
    """``options``, the defaults for None; a ValueError naming it if it is not a
    ``WalkOptions``."""
    if options is None:
        return WalkOptions()
    if not isinstance(options, WalkOptions):
        raise ValueError(f"`options` must be a WalkOptions, got {options!r}.")
    return options


def check_band(name: str, f_hz: float, parameters) -> None:
    """A ValueError naming ``name`` unless f_e = ``f_hz`` lies in the band where a branch of
    the model (its ``ContactParameters``) can be continued: ``_BAND_OF_F_N0`` times f_n0."""
    f_n0 = eq26_numbers(parameters).f_n0_hz
    low, high = _BAND_OF_F_N0[0] * f_n0, _BAND_OF_F_N0[1] * f_n0
    if not low <= f_hz <= high:
        raise ValueError(f"`{name}` must lie within {low:.3g}-{high:.3g} Hz "
                         f"({_BAND_OF_F_N0[0]:g} to {_BAND_OF_F_N0[1]:g} f_n0: a period of a "
                         f"branch is a few to some ten thousand natural periods), got "
                         f"{f_hz!r}.")


def check_walk(period, ds_max, max_angle, max_points) -> tuple[float, float, int]:
    """The walk's settings checked (a ValueError naming the argument): ds_max, max_angle,
    max_points."""
    if period not in PERIODS_TRIED:
        raise ValueError(f"`period` must be one of {PERIODS_TRIED}, got {period!r}.")
    return (check_positive("ds_max", ds_max), check_positive("max_angle", max_angle),
            check_int("max_points", max_points, minimum=2, maximum=MAX_WALK_POINTS,
                      why="some 830 bytes a point, 0.2 GB a walk"))


def branch_steps(steps_per_period, f_hz: float, numbers) -> int:
    """N, fixed along a branch: "auto" takes ``steady_states``' choice at ``f_hz``, but at
    least _AUTO_MIN_STEPS."""
    if steps_per_period == "auto":
        return max(int(lane_steps("auto", np.array([f_hz]), numbers.fastest_rate_per_s)[0]),
                   _AUTO_MIN_STEPS)
    return check_int("steps_per_period", steps_per_period, minimum=4, maximum=MAX_STEPS,
                     why="the bound of the steps of every command")


def largest_step(z: np.ndarray, angle: float, ds_max: float, options: WalkOptions) -> float:
    """The largest next step after a point ``z`` whose step turned the tangent by
    ``angle``: ds_max, or, where the branch runs straight (``options.straight``), ds_max
    times the orbit's size |(y, v)| in z over ``options.size_reference`` (twice the
    static deflection) where that is above 1, up to ``options.size_ceiling`` ds_max: a
    step moves a
    large bouncing orbit by as little, relative to its size, as ds_max moves one in
    contact."""
    if angle > options.straight:
        return ds_max
    return ds_max * orbit_scale(z, options.size_ceiling, options)


def corner_step(z: np.ndarray, ds_max: float, options: WalkOptions) -> float:
    """The step from a point ``z`` below which a tangent that turns by more than
    max_angle is taken to turn at a corner of the map: ``options.corner_ds``, times the
    orbit's size over ``options.size_reference`` on a large orbit, up to
    ``options.corner_ceiling`` times, and
    at most ``ds_max`` (the user's largest step: a turn over a step of ds_max or more is
    never a corner's). At the defaults the cap is 20 x 1e-3 = ds_max: it changes no
    walk."""
    return min(options.corner_ds * orbit_scale(z, options.corner_ceiling, options), ds_max)


def orbit_scale(z: np.ndarray, ceiling: float, options: WalkOptions) -> float:
    """The orbit's size |(y, v)| in z over ``options.size_reference``, clipped to [1,
    ``ceiling``]: how much longer a step may be on it than on an orbit in contact (at
    least 1 only while ``ceiling`` is, as the options' ceilings are)."""
    size = math.sqrt(z[0] * z[0] + z[1] * z[1]) / options.size_reference
    return min(max(1.0, size), ceiling)


def arclength_step(shoot: PeriodMap, z: np.ndarray, t: np.ndarray, ds: float,
                   ds_max: float, max_angle: float, orientation: float, options: WalkOptions,
                   resume: float | None):
    """One accepted pseudo-arclength step from ``z`` along the unit tangent ``t``: the
    step routine of every walk (``Walk`` in f_e or P_a, branch switching, the fold
    curves' ``folds.FoldWalk``), of which ``kernels.walk_template.walk_steps`` is the
    compiled twin.

    Newton corrects z + ds t on the plane t . (z' - z) = ds (with the options' contraction
    test and stop), and the step is taken where the new tangent turned by at most
    ``max_angle``; else it shrinks and is tried again. Returns ((point, tangent, next
    ds) or None when it failed at every ds, the ds to go on with (or that it failed at:
    below ``stall_ds`` if it began above, else below ``ds_min``), the step to resume
    with after a corner, or None).
    """
    least = options.stall_ds if ds >= options.stall_ds else options.ds_min
    corner = corner_step(z, ds_max, options) if options.corners else 0.0
    while ds >= least:
        point = shoot.correct(z + ds * t, t, t @ z + ds, options.contraction,
                              estimated=options.stop_by_estimate)
        t_new = None if point is None else point.tangent(t, orientation)
        # No tangent, or one turned back below the stall's ds: a failed step.
        if (point is not None and np.isfinite(t_new).all()
                and not (ds < options.stall_ds and t_new @ t < 0.0)):
            angle = np.arccos(np.clip(t_new @ t, -1.0, 1.0))
            if angle <= max_angle:
                # An easy step grows the next; so does a step shorter than corner_ds
                # (Newton may stay slow near a corner however short the step): flat,
                # not the corner's step, which took more evaluations (tuning log).
                grow = point.iterations <= options.easy_iterations or (
                    options.corners and ds < options.corner_ds)
                ds = min(ds * options.grow if grow else ds,
                         largest_step(point.z, angle, ds_max, options))
                return (point, t_new, ds), ds, None
            if ds < corner:
                # The tangent turns as much over a step this short: a corner of the
                # piecewise smooth map (a stage of a step crossing y = 0, Eq. 2.1),
                # not a fold; walk on with the step taken before the corner.
                resume = resume or ds
                return (point, t_new, resume), resume, None
            if resume is None:  # the step to come back to after a corner
                resume = ds
            ds *= (min(options.shrink, options.turn_share * max_angle / angle)
                   if options.shrink_by_turn else options.shrink)
            continue
        ds *= options.corner_shrink if ds < corner else options.shrink
    return None, ds, resume


def count_kinds(bifurcations: list[Bifurcation]) -> str:
    """"N folds, M period doublings" of a list of bifurcations, for a summary."""
    counts = {k: sum(b.kind == k for b in bifurcations) for k in KINDS}
    return f"{counts['fold']} folds, {counts['period-doubling']} period doublings"


def walk_finest(make_shoot, steps: int, auto: bool, model, low: float, high: float, ds_max,
                max_angle, max_points, quiet):
    """``walk_band`` on the map ``make_shoot(steps)``; if ``auto``, again at twice the steps
    while a walk stops inside the band at a corner that Newton cannot pass (the map's
    corners shrink with the step), up to ``_AUTO_MAX_STEPS``: (the map, the branches, the
    bifurcations) of the walk that covered most of the band (of equal ones, the finest).

    A walk up that stops at a corner goes on to twice the steps at once: the walk down at
    its N is made only if the branches of the finest N tried do not span the whole band
    (then a coarser N might cover more). At 0.15 Q the walk up at 512 steps stops near
    the bouncing fold and the one at 1024 steps passes it: the walk down at 512 steps is
    not made.
    """
    tried = []  # per N, coarsest first: the arguments of its walks, and its walks
    while True:
        args = (make_shoot(steps), model, low, high, ds_max, max_angle, max_points, quiet)
        walks = [_band_walk(*args, +1)]
        finer = auto and 2 * steps <= _AUTO_MAX_STEPS
        if not (finer and _stuck(walks)):
            walks = _walked_down(walks, *args)
        tried.append((args, walks))
        if not (finer and _stuck(walks)):
            break
        steps *= 2
    finest = _covered(*tried[-1])
    if finest[0] >= (1.0 - _WHOLE) * (high - low):
        return finest[1:]
    best = finest
    for args, walks in reversed(tried[:-1]):  # of equal coverage, the finer is kept
        coarser = _covered(args, _walked_down(walks, *args))
        best = coarser if coarser[0] > best[0] else best
    return best[1:]


#: Branches that cover the band but for this share of it cover it whole (f at the band's
#: edges is clipped to it in z, and scaled back with a round-off).
_WHOLE = 1e-12


def _covered(args, walks: list[Walk]):
    """(the band's length that the walks cover, the map, the branches, the bifurcations)."""
    shoot, model = args[:2]
    branches, bifurcations = branch_results(shoot, model, join_walks(walks))
    return _coverage(branches, shoot), shoot, branches, bifurcations


def _stuck(walks: list[Walk]) -> bool:
    """Whether a walk stopped at a corner of the map that Newton cannot pass (and was not
    joined there by the walk from the other end)."""
    return any(message.startswith(_STUCK) for *_, message in join_walks(walks))


def _coverage(branches: list[ContinuedBranch], shoot: PeriodMap) -> float:
    """The length of the parameter's band that the branches cover (the union of their
    ranges), in its physical unit."""
    spans = sorted((float(v.min()), float(v.max())) for v in
                   (b.frequency_hz if not shoot.force_is_parameter else b.pa_frac
                    * shoot.scale[2] for b in branches) if v.size)
    total, end = 0.0, -np.inf
    for lo, hi in spans:
        total += max(hi - max(lo, end), 0.0)
        end = max(end, hi)
    return total


def walk_band(shoot: PeriodMap, model, low: float, high: float, ds_max, max_angle,
              max_points, quiet) -> tuple[list[ContinuedBranch], list[Bifurcation]]:
    """The branch through the stable orbit reached from rest at the band's lower end
    (``low``, ``high``: the parameter in its physical unit), walked up; if it ends inside
    the band, also the one from the upper end, walked down, joined to it where they meet.
    """
    args = (shoot, model, low, high, ds_max, max_angle, max_points, quiet)
    return branch_results(shoot, model, join_walks(_walked_down(
        [_band_walk(*args, +1)], *args)))


def _walked_down(walks: list[Walk], shoot, model, low, high, ds_max, max_angle, max_points,
                 quiet) -> list[Walk]:
    """``walks`` (the walk up), and the walk down from the band's upper end if the walk up
    ended inside the band (at a corner of the map that Newton cannot pass, or at an
    isola's edge) and there is none yet."""
    if len(walks) == 1 and walks[0].status != Status.SUCCESS:
        walks = [*walks, _band_walk(shoot, model, low, high, ds_max, max_angle, max_points,
                                    quiet, -1)]
    return walks


def _band_walk(shoot, model, low, high, ds_max, max_angle, max_points, quiet,
               direction: int) -> Walk:
    """One walk over the band, up (``direction`` +1) or down (-1), with its progress bar."""
    bar = Coverage(low, high, quiet, shoot.steps)
    walk = _walk_from(shoot, model, low, high, direction, bar, ds_max, max_angle, max_points)
    bar.close()
    return walk


def _walk_from(shoot, model, fmin_hz, fmax_hz, direction, bar, ds_max, max_angle,
               max_points) -> Walk:
    """The branch through the stable orbit reached from rest at the band's lower end
    (``direction`` +1, walked up in f) or upper end (-1, walked down)."""
    f_start = fmin_hz if direction > 0 else fmax_hz
    walk = Walk(shoot, fmin_hz, fmax_hz, direction, ds_max, max_angle, max_points, bar)
    first, reached = first_point(shoot, model, f_start)
    if first is None:
        walk.end(Status.FAILED, f"no stable {shoot.period}-periodic orbit reached from rest "
                 f"at {shoot.label(shoot.scaled(0.0, 0.0, f_start))} to start from ({reached})")
    else:
        walk.run(first)
    return walk


class Coverage:
    """The progress bar: the share of the band that the walks have covered."""

    def __init__(self, fmin_hz, fmax_hz, quiet, steps: int | None = None):
        self.lo, self.hi = fmin_hz, fmax_hz
        self.reached = [fmin_hz, fmax_hz]  # by the walk up, by the walk down
        label = "continue" if steps is None else f"continue, N = {steps}"  # "auto" may redo
        self.bar = progress(1000, label, quiet=quiet)

    def update(self, f_hz: float, direction: int) -> None:
        if direction > 0:
            self.reached[0] = max(self.reached[0], f_hz)
        else:
            self.reached[1] = min(self.reached[1], f_hz)
        covered = (self.reached[0] - self.lo) + (self.hi - self.reached[1])
        share = min(covered / (self.hi - self.lo), 1.0)
        self.bar.update(max(0, int(1000 * share) - self.bar.n))

    def close(self) -> None:
        self.bar.close()


def first_point(shoot: PeriodMap, model, value: float) -> tuple[Point | None, str]:
    """The stable orbit reached from rest where the parameter is ``value`` (time marching,
    then Newton at our N), polished at that value, or None if none of period p is
    reached; and what the march reached, for a message."""
    (f_hz,), (p_a,) = shoot.drives([value])
    state = steady_states(f_hz, p_a, model=model, steps_per_period=shoot.steps, app_rtol=None,
                          refinements=0)
    if not state.settled[0]:
        return None, "the march from rest did not settle"
    if state.period[0] != shoot.period:
        return None, f"the march from rest settled on period {int(state.period[0])}"
    z = shoot.scaled(state.y_start_m[0], state.v_start_m_s[0], value)
    point = shoot.correct(z, _E_F, z[2])
    return point, "" if point else "Newton did not polish the orbit the march reached"


class ArclengthWalk:
    """The walks' one engine: the points of a branch of ``shoot`` and their tangents, each
    step ``arclength_step``, with Brent's method along the arclength for the events met
    between two points (``locate``) and the correction onto an edge (``clip``).

    ``shoot`` is any ``PeriodMap``: orbits in f_e (``continue_orbits``, ``switch_branch``),
    in P_a (``ForceMap``) or the fold system in (f_e, P_a) (``folds.FoldMap``). What a walk
    does between its steps, the events it looks for and where it stops, is its
    subclass's: ``Walk`` (bifurcations, the band's edges) and ``folds.FoldWalk`` (cusps,
    the box's edges)."""

    def __init__(self, shoot: PeriodMap, ds_max: float, max_angle: float, max_points: int,
                 options: WalkOptions):
        self.shoot, self.options = shoot, options
        self.ds_max, self.max_angle, self.max_points = ds_max, max_angle, max_points
        self.points: list[Point] = []
        self.tangents: list[np.ndarray] = []
        self.status, self.message = Status.SUCCESS, ""
        self.orientation = 1.0  # the sign of det([J; t]) along the branch
        self.resume: float | None = None  # the step to resume with after a corner

    def end(self, status: Status, message: str) -> None:
        self.status, self.message = status, message

    def _keep(self, point: Point, t: np.ndarray) -> None:
        self.points.append(point)
        self.tangents.append(t)

    def _step(self, ds: float):
        """One accepted step from the last point (``arclength_step``): ((point, tangent,
        next ds), next ds), or (None, the ds it failed at)."""
        step, ds, self.resume = arclength_step(
            self.shoot, self.points[-1].z, self.tangents[-1], ds, self.ds_max,
            self.max_angle, self.orientation, self.options, self.resume)
        return step, ds

    def locate(self, base: Point, t_base, end: Point, test, orientation: float):
        """Brent's method on the arclength s from ``base`` towards ``end``: (s, the point
        there, its tangent) where ``test`` (of a corrected point and its tangent, signed by
        ``orientation``, the branch's there) is zero, to ``LOCATE_TOL``; None where Newton
        cannot correct between the two."""
        ds = t_base @ (end.z - base.z)

        def corrected(s):
            p = self.shoot.correct(base.z + s * t_base, t_base, t_base @ base.z + s)
            if p is None:
                raise _NotLocated
            return p, p.tangent(t_base, orientation)

        def g(s):
            if s == ds:
                return test(end, end.tangent(t_base, orientation))
            return test(*corrected(s)) if s else test(base, t_base)

        try:
            s = brentq(g, 0.0, ds, xtol=LOCATE_TOL)
            point, t = corrected(s)
        except _NotLocated:
            return None
        return s, point, t

    def clip(self, point: Point, row: np.ndarray, edge: float, reference: np.ndarray) -> None:
        """Keep the point exactly on the edge row . z = ``edge`` between the last point and
        ``point``, which crossed it (its tangent from ``reference``), if Newton finds it."""
        last = self.points[-1]
        share = (edge - row @ last.z) / (row @ point.z - row @ last.z)
        clipped = self.shoot.correct(last.z + share * (point.z - last.z), row, edge)
        if clipped is not None:
            self._keep(clipped, clipped.tangent(reference, self.orientation))


class Walk(ArclengthWalk):
    """The points of a branch and the bifurcations met, walked step by step, through the
    band [fmin_hz, fmax_hz] of the parameter."""

    def __init__(self, shoot, fmin_hz, fmax_hz, direction, ds_max, max_angle, max_points, bar):
        super().__init__(shoot, ds_max, max_angle, max_points, shoot.options)
        self.direction, self.bar = direction, bar
        self.f_lo, self.f_hi = fmin_hz / shoot.scale[2], fmax_hz / shoot.scale[2]
        self.marks: list[Mark] = []
        self.from_edge = True  # started at the band's edge (not off a bifurcation)
        self.natural_steps = 0  # steps in the parameter alone, past corners
        # Folds met and not yet located: (index of the step's first point, the branch's
        # orientation then); ``_locate_folds`` settles them when the walk ends.
        self.pending_folds: list[tuple[int, float]] = []
        # The walk's numbers as the compiled steps read them.
        self.settings = self.options.numbers(ds_max, max_angle, self.f_lo, self.f_hi)

    def run(self, first: Point, away: np.ndarray | None = None) -> None:
        """From ``first``, into the band (up or down in f) or along ``away`` (a direction
        in z: off a bifurcation), until f leaves the band."""
        # Into the band at the start; the branch keeps that orientation.
        inward = np.array([0.0, 0.0, float(self.direction)]) if away is None else away
        self.from_edge = away is None
        self.orientation = first.orientation(inward) or 1.0
        t = first.tangent(inward, self.orientation)
        self._keep(first, t)
        ds = self.options.ds_start
        while True:
            if len(self.points) >= self.max_points:
                self.end(Status.FAILED, f"gave up after {self.max_points} points (max_points)")
                break
            step, ds = self._arclength_steps(ds)
            if step is None:
                step = self._natural_step()
                if step is None and ds >= self.options.ds_min:  # stalled: on, to ds_min,
                    step, ds = self._arclength_steps(ds)
                    if step is None:  # and again in f alone from where that ended
                        step = self._natural_step()
            if step is _PLAIN:  # plain points kept, none needing Python: walk on
                continue
            if step is None:
                self.end(Status.FAILED, f"{_STUCK} {self.options.ds_min:g} at "
                         f"{self.shoot.label(self.points[-1].z)}: Newton does not converge there")
                break
            point, t, ds = step
            edge = point.z[2] >= self.f_hi or point.z[2] <= self.f_lo
            unlocated = self._bifurcations(point, t, defer_folds=not edge)
            if edge:
                self._clip(point, t)
                self._mark_at_last(unlocated)
                break
            self._keep(point, t)
            self._mark_at_last(unlocated)
            self.bar.update(point.z[2] * self.shoot.scale[2], self.direction)
        self._locate_folds()

    def _mark_at_last(self, unlocated: list[tuple[str, float]]) -> None:
        """Bifurcations that Brent's method could not locate ((kind, reach) of each),
        marked at the last point kept: within one step of where they are."""
        self.marks += [Mark(len(self.points) - 1, kind, False, reach)
                       for kind, reach in unlocated]

    def _natural_step(self):
        """Past a corner that the arclength step cannot pass: a step in the parameter alone
        (Newton at a fixed f, from the last orbit), on in the direction that f was moving
        (the sign of the last tangent's f-component), as ``_step`` gives it; None if no
        short one converges near the last point and ahead of the walk.

        Where the map's corners crowd (the orbit landing and taking off within a step,
        loss of contact), the branch in z turns sharply at each, and at some the one-sided
        Jacobians send the bordered Newton off on both sides at any ds. Newton at a fixed
        f a little further converges. The step is taken only where the orbit moves little
        (``_NATURAL_REACH``: not onto another branch) and not back onto the walk's own
        recent points (where f zigzags, f a little further may lie behind the walk: the
        walk would turn round and walk its branch again); at most ``_NATURAL_STEPS``
        times in a walk.
        """
        if self.natural_steps >= _NATURAL_STEPS:
            return None
        last = self.points[-1].z
        recent = np.array([p.z for p in self.points[-_NATURAL_BEHIND - 1:-1]]).reshape(-1, 3)
        sign = np.sign(self.tangents[-1][2]) or self.direction
        for df in _NATURAL_DF:
            target = last[2] + sign * df
            point = self.shoot.correct(np.array([last[0], last[1], target]), _E_F, target)
            if point is None:
                continue
            moved = np.linalg.norm(point.z - last)
            behind = np.linalg.norm(recent - point.z, axis=1).min(initial=np.inf) < 0.5 * moved
            if not moved <= _NATURAL_REACH or behind:
                continue
            self.natural_steps += 1
            chord = (point.z - last) / moved
            t = point.tangent(chord, 1.0)
            t = t if t @ chord > 0 else -t  # on along the chord: the branch's new orientation
            self.orientation = point.orientation(t) or 1.0
            self.resume = None
            return point, t, self.options.ds_start
        return None

    def _arclength_steps(self, ds: float):
        """(the next step for Python to finish, as ``_step`` gives it, or None when it
        failed, or _PLAIN; the ds to go on with): ``_step`` by the walk's engine."""
        return self._step(ds) if self.shoot.walker is None else self._compiled_steps(ds)

    def _compiled_steps(self, ds: float):
        """``_step`` repeated in compiled code (``kernels.walk_template.walk_steps``), keeping
        the plain points: (the step for Python to finish, as ``_step`` gives it, or None
        when the step failed, or _PLAIN when only plain points were walked; the ds)."""
        shoot, walker = self.shoot, self.shoot.walker
        rows = min(CHUNK, self.max_points - len(self.points))
        z, t, jac = np.empty((rows, 3)), np.empty((rows, 3)), np.empty((rows, 2, 3))
        mono, iterations = np.empty((rows, 2, 2)), np.empty(rows, dtype=np.int64)
        state = np.array([ds, -1.0 if self.resume is None else self.resume])
        outcome, kept = walker.walk_steps(
            self.points[-1].z, self.tangents[-1], self.points[-1].monodromy,
            float(self.orientation), state, shoot.scale, shoot.steps, shoot.period,
            shoot.drive, shoot.force_is_parameter, shoot.other, self.settings, z, t, jac,
            mono, iterations)
        self.resume = None if state[1] < 0.0 else float(state[1])
        # The rows walked, copied out of the chunk: a point kept as a view would keep the
        # whole chunk's buffers alive (some 1.5 kB a point more).
        n = min(kept + 1, rows)
        z, t, jac, mono = z[:n].copy(), t[:n].copy(), jac[:n].copy(), mono[:n].copy()
        for i in range(kept):
            self._keep(Point(z[i], jac[i], mono[i], int(iterations[i])), t[i])
        if kept:
            self.bar.update(self.points[-1].z[2] * shoot.scale[2], self.direction)
        if outcome == walker.WALK_FULL:
            return _PLAIN, float(state[0])
        if outcome == walker.WALK_FAILED:
            return None, float(state[0])
        point = Point(z[kept], jac[kept], mono[kept], int(iterations[kept]))
        return (point, t[kept], float(state[0])), float(state[0])

    def _bifurcations(self, point: Point, t: np.ndarray,
                      defer_folds: bool = False) -> list[tuple[str, float]]:
        """Locate the folds and period doublings between the last point and ``point``
        and keep them as points of the branch; returns (kind, the step's reach,
        ``_reach``) of those it could not locate (Newton cannot correct between the two
        points: a corner lies between, or the step was one in f alone), to be marked at
        ``point``, not lost. With ``defer_folds`` a fold alone in its step is left for
        ``_locate_folds``, once the walk knows which turns of f are folds."""
        base, t_base = self.points[-1], self.tangents[-1]
        tests = {"fold": _fold_test, "period-doubling": lambda p, tp: p.period_doubling_test}
        found, unlocated = [], []
        # A fold passes a real multiplier through +1: where t_f turns with no change in
        # the count of multipliers outside the unit circle, it turned at a corner of the
        # piecewise smooth map (an artefact of the fixed step), not at a fold.
        turns = {"fold": _unstable_count(base) != _unstable_count(point),
                 "period-doubling": True}
        crossed = [kind for kind, test in tests.items()
                   if turns[kind] and test(base, t_base) * test(point, t) < 0]
        if defer_folds and crossed == ["fold"]:
            self.pending_folds.append((len(self.points) - 1, self.orientation))
            return []
        for kind in crossed:
            located = self.locate(base, t_base, point, tests[kind], self.orientation)
            if located is None:
                unlocated.append((kind, _reach(base, point)))
            else:
                found.append((located[0], kind, located[1], located[2]))
        for _, kind, p, tp in sorted(found, key=lambda item: item[0]):
            self.marks.append(Mark(len(self.points), kind, True, LOCATE_TOL))
            self._keep(p, tp)
        return unlocated

    def _locate_folds(self) -> None:
        """The folds left by ``_bifurcations``: Brent's method locates those within
        ``WalkOptions.near_turn`` points of a turn of f that f follows by ``_FOLD_PROMINENCE``
        (the folds ``_significant_folds`` reports) and keeps them as points of the
        branch; the others (turns of a zigzag over the map's corners, dropped there)
        are only marked at the step's end, as one Brent's method cannot locate.

        At 0.15 Q, N = 1024, the walk meets 66 folds, nearly all of them turns of the
        zigzag about the bouncing fold, and locates 2 (``bench_continuation`` times
        the call against one that locates every fold met).
        """
        if not self.pending_folds:
            return
        f = np.array([p.z[2] for p in self.points])
        turns = _turns(f)
        if self.status != Status.SUCCESS:
            # Ended inside the band: joined to a walk from the other end, its last points
            # may turn significantly; the folds there are located too.
            turns = np.append(turns, _tail(f))
        # From the last: a point kept at one index leaves the indices below it as they are.
        for first, orientation in sorted(self.pending_folds, reverse=True):
            base, end = self.points[first], self.points[first + 1]
            near = turns.size and np.abs(turns - (first + 1)).min() <= self.options.near_turn
            located = (self.locate(base, self.tangents[first], end, _fold_test, orientation)
                       if near else None)
            if located is None:
                self.marks.append(Mark(first + 1, "fold", False, _reach(base, end)))
                continue
            _, point, t = located
            self.marks = [m._replace(index=m.index + 1) if m.index > first else m
                          for m in self.marks]
            self.marks.append(Mark(first + 1, "fold", True, LOCATE_TOL))
            self.points.insert(first + 1, point)
            self.tangents.insert(first + 1, t)
        self.pending_folds = []
        self.marks.sort()  # in the walk's order, as _significant_folds breaks its ties

    def _clip(self, point: Point, t: np.ndarray) -> None:
        """The branch's last point exactly at the band's edge that ``point`` crossed."""
        edge = self.f_hi if point.z[2] >= self.f_hi else self.f_lo
        self.clip(point, _E_F, edge, t)
        if self.from_edge and (edge == self.f_lo) == (self.direction > 0):
            self.end(Status.FAILED, "the branch turned back and left the band where it "
                     "started (a peak bent beyond the band, or an isola)")


#: The band a branch may be continued in, in units of f_n0: at a fixed step count a
#: period holds some ten thousand natural periods at the low end (65,536 steps at
#: "auto"), and a few steps per natural period at the high end.
_BAND_OF_F_N0 = (1e-4, 1e2)


class _NotLocated(Exception):
    pass


class Mark(NamedTuple):
    """A bifurcation met by a walk: the index of its point in the walk's points, its kind,
    whether Brent's method located it, and how far (in z, in the parameter) it may lie
    from that point."""

    index: int
    kind: str
    located: bool
    reach: float


def _reach(a: Point, b: Point) -> float:
    """How far in the parameter (in z) a bifurcation between two consecutive points of a
    branch may lie from either: the step's length times the larger rate of the parameter
    along the branch (the tangent's parameter component) at its two ends. The tangent
    turns by at most ``max_angle`` over a step, so the rate between them stays within
    theirs (at a fold it passes through 0 between them). Across a corner of the map that
    need not hold, so the reach is never below the chord's own move in the parameter."""
    chord = b.z - a.z
    length = float(np.linalg.norm(chord))
    if not length:
        return 0.0
    rates = [abs(p.tangent(chord / length, 1.0)[2]) for p in (a, b)]
    by_rate = length * (max(rates) if np.isfinite(rates).all() else 1.0)  # |t| = 1 at most
    return max(by_rate, abs(float(chord[2])))


#: The steps in the parameter alone that ``Walk._natural_step`` tries (in z: 1e-5 f_n0 is
#: 0.015 Hz on the paper's model), how far the orbit may move in one (in z), and how many
#: a walk may take.
_NATURAL_DF = (1e-5, 3e-5, 1e-4)
#: (The steps that went on along the branch at 0.15 Q moved the orbit by 0.0028 at most;
#: two that went back onto the walk's own points at 0.17 Q, by 0.015 and 0.029.)
_NATURAL_REACH = 5e-3
_NATURAL_STEPS = 100
#: How many of the walk's last points a step in f alone must not land near (within half
#: the distance it moved from the last one).
_NATURAL_BEHIND = 400
_E_F = np.array([0.0, 0.0, 1.0])

#: Points that one compiled call walks at most, so that the progress bar moves (and
#: Ctrl-C is heard) between calls; _PLAIN says that a call kept only plain points.
CHUNK = 256
_PLAIN = object()


#: Two walks that end within this distance (in z) of each other end at the same corner of
#: the branch, from its two sides: they are one branch.
_MEET = 1e-2


def join_walks(walks: list[Walk]) -> list[tuple[list[Point], list[Mark], Status, str]]:
    """Each branch's points (in the order of the walk up), marks, status and message: a
    walk down that ends where the walk up ended is the same branch, joined to it (with a
    fold where f turns back at the joint)."""
    parts = [(w.points, w.marks, w.status, w.message, w.tangents) for w in walks]
    if len(walks) == 2:
        up, down = walks
        n_up, n_down = len(up.points), len(down.points)
        # The down walk's marks, indexed in its own points reversed (the order of f up).
        down_marks = [m._replace(index=n_down - 1 - m.index) for m in reversed(down.marks)]
        parts[1] = (down.points[::-1], down_marks, down.status, down.message, None)
        if n_up and n_down and np.abs(up.points[-1].z - down.points[-1].z).max() < _MEET:
            # Walked in opposite directions: f turns back at the joint when the two
            # walks ended moving the same way in f (a fold between their ends, not
            # located: Newton could not pass there).
            marks = list(up.marks)
            if up.tangents[-1][2] * down.tangents[-1][2] > 0:
                marks.append(Mark(n_up - 1, "fold", False,
                                   _reach(up.points[-1], down.points[-1])))
            joined = [m._replace(index=n_up + m.index) for m in down_marks]
            return [(up.points + down.points[::-1], marks + joined, Status.SUCCESS, "")]
    # A walk with no point is kept (as an empty branch): its status says why.
    return [part[:4] for part in parts]


def _unstable_count(point: Point) -> int:
    return int((np.abs(point.multipliers) > 1.0).sum())


#: A turn of f along a branch is a fold only if f moves back by more than this share of
#: f_n0 (0.15 Hz on the paper's model) before it turns again: the fixed-step map is only
#: piecewise smooth through loss of contact, and at its corners f zigzags by some 1e-3 Hz.
_FOLD_PROMINENCE = 1e-4


def _fold_test(point: Point, t: np.ndarray) -> float:
    """The test function of a fold: the parameter's component of the tangent."""
    return t[2]


def _turns(f: np.ndarray) -> np.ndarray:
    """The indices where f turns and then follows the turn by ``_FOLD_PROMINENCE``."""
    return np.concatenate([find_peaks(sign * f, prominence=_FOLD_PROMINENCE)[0]
                           for sign in (1.0, -1.0)])


def _near(f: np.ndarray, index: int) -> slice:
    """The run of points about ``index`` whose f stays within ``_FOLD_PROMINENCE`` of f
    there: where turns of f are not told apart from a turn at ``index``."""
    far = np.flatnonzero(np.abs(f - f[index]) > _FOLD_PROMINENCE)
    return slice(far[far < index].max(initial=-1) + 1, far[far > index].min(initial=f.size))


def _tail(f: np.ndarray) -> np.ndarray:
    """The indices of the last run of points whose f stays within ``_FOLD_PROMINENCE`` of
    the last point's."""
    return np.arange(f.size)[_near(f, f.size - 1)]


def _significant_folds(points: list[Point], marks: list[Mark]) -> list[Mark]:
    """``marks`` with the folds that are significant turns of f (``_FOLD_PROMINENCE``):
    per turn, the fold marked nearest to it, or the turning point itself (not located:
    within a step either side)."""
    f = np.array([p.z[2] for p in points])
    turns = _turns(f)
    folds = [m for m in marks if m.kind == "fold"]
    at = np.array([m.index for m in folds], dtype=int)
    chosen = [folds[np.argmin(np.abs(at - k))] if at.size and np.abs(at - k).min() <= 2
              else Mark(int(k), "fold", False, max(_reach(points[k - 1], points[k]),
                                                    _reach(points[k], points[k + 1])))
              for k in turns]
    chosen = [m._replace(reach=max(m.reach, _FOLD_PROMINENCE)) if _zigzags(f, k) else m
              for m, k in zip(chosen, turns)]
    return sorted(set([m for m in marks if m.kind != "fold"] + chosen))


def _zigzags(f: np.ndarray, turn: int) -> bool:
    """Whether f turns again about the significant turn at index ``turn``: within the run
    of points about it whose f stays within ``_FOLD_PROMINENCE`` of f there.

    Near a fold of a bouncing orbit the fixed-step map's corners make f zigzag: the
    branch turns back and forth, each turn a fold of the discrete map (at 0.15 Q,
    N = 1024, f turns 55 times within 352.36-353.98 Hz, 17 of them within
    ``_FOLD_PROMINENCE`` of the fold at 352.36 Hz; 2026-11-24). Turns closer than
    ``_FOLD_PROMINENCE`` are not told apart as folds, and which of them a walk locates
    depends on its steps: such a fold is known to that resolution, not to Brent's.
    """
    moves = np.diff(f[_near(f, turn)])
    moves = moves[moves != 0.0]  # a point repeated (a located fold beside its step)
    return bool((np.sign(moves[1:]) != np.sign(moves[:-1])).sum() > 1)


def branch_results(shoot: PeriodMap, model, branches):
    """The branches' columns (App of all points in one batched recording) and the
    bifurcations, in the order of the branches."""
    z = np.array([p.z for points, *_ in branches for p in points]).reshape(-1, 3)
    y, v, parameter = (z * shoot.scale).T
    f, p_a = shoot.drives(parameter)
    pa_frac = p_a / model.parameters.Q_n
    app = _app(model, shoot, y, v, f, p_a)
    all_multipliers = floquet_multipliers(_monodromies(shoot, y, v, f, p_a))
    out, marks, first = [], [], 0
    for points, branch_marks, status, message in branches:
        branch_marks = _significant_folds(points, branch_marks)
        part = slice(first, first + len(points))
        multipliers = all_multipliers[part]
        stable = np.abs(multipliers).max(axis=1, initial=0.0) < 1.0
        out.append(ContinuedBranch(frequency_hz=f[part], pa_frac=pa_frac[part], app_m=app[part],
                                   stable=stable, period=shoot.period, multipliers=multipliers,
                                   y_start_m=y[part], v_start_m_s=v[part], status=int(status),
                                   message=message))
        marks += [m._replace(index=first + m.index) for m in branch_marks]
        first += len(points)
    return out, [_bifurcation(shoot, model, m, f, app, pa_frac, parameter) for m in marks]


def _bifurcation(shoot: PeriodMap, model, mark: Mark, f, app, pa_frac, parameter):
    """The ``Bifurcation`` of a mark, at its point of the branches' columns, with its
    reach turned into tolerances of f_e and P_a / Q (0 in the one the walk held)."""
    i = mark.index
    (f_far,), (p_a_far,) = shoot.drives([parameter[i] + mark.reach * shoot.scale[2]])
    return Bifurcation(kind=mark.kind, frequency_hz=float(f[i]), app_m=float(app[i]),
                       pa_frac=float(pa_frac[i]), located=mark.located,
                       frequency_tol_hz=abs(float(f_far - f[i])),
                       pa_frac_tol=abs(float(p_a_far / model.parameters.Q_n - pa_frac[i])))


def _monodromies(shoot: PeriodMap, y, v, f, p_a) -> np.ndarray:
    """The monodromy matrix of each point's orbit at the point itself, all points as lanes
    of one kernel call (``shoot_periods``): the walk's points keep the one where Newton
    last evaluated R, a step before the point where ``near_enough`` stopped it. Measured
    (2026-11-23): at 0.15 Q their multipliers differ from those at the points by up to
    4.3e-6 (a corner between); against the orbits of the series' roots
    (``tests/test_series_stability.py``) the multipliers at the points differ by 2.7e-11
    at most (0.05 Q; 6.3e-13 at 0.3 Q, 650-850 Hz), those of the walk's points by up to
    3.3e-9 (0.3 Q, 650-850 Hz), and before ``near_enough`` by 1.8e-10 (0.05 Q) and
    1.9e-11 (0.3 Q). At 0.15 Q (2493 points then, N = 1024) the call took 10 ms."""
    monodromy = np.empty((f.size, 2, 2))
    if f.size:
        shoot.kernels.shoot_periods(y.copy(), v.copy(), 1.0 / (shoot.steps * f), p_a,
                                    shoot.drive, shoot.period, monodromy)
    return monodromy


def _app(model, shoot: PeriodMap, y, v, f, p_a) -> np.ndarray:
    """App over one orbit period from each point's start, all points in one kernel call."""
    if not f.size:
        return np.empty(0)
    lanes = Lanes(model, f, p_a, shoot.steps)
    rec = lanes.record(y.copy(), v.copy(), shoot.period, np.full(f.size, -1, dtype=np.int64))
    return rec.ymax - rec.ymin
