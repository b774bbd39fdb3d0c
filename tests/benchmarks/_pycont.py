"""Continuation packages from the package index on continue_orbits' own shooting
residual, over the same branch (issue 13): pycont-lite, and contique as a second.

Both are given ``continue_orbits``' residual, not a second one: ``PeriodMap.residual``
of the very period map ``continue_orbits`` builds (same model, P_a, N steps per period
and period p), R(z) = Phi_p(x, f) - x in the scaled unknowns z = (y / y0,
v / (omega0 y0), f / f_n0), split as u = z[:2] and the parameter p = z[2].

- pycont-lite (PyPI ``pycont_lite``, imported as ``pycont``) is a matrix-free
  pseudo-arclength continuation: it is given G(u, p) alone and takes every derivative
  by finite differences (a Newton-Krylov corrector, an L-GMRES tangent). Its entry
  point has no argument for a Jacobian, so the monodromy matrix from the compiled
  tangent kernel cannot be handed to it; each residual call still computes it (in
  the same run of the tangent kernel as R), unused.
- contique (PyPI ``contique``) continues by a control component (the unknown that
  moved most, switched as the branch turns) with a plain Newton, and takes the
  Jacobian: here dR/du (the monodromy) and dR/dp (the exact derivative in f) from
  that same residual call, the Jacobian ``continue_orbits`` uses.

The walks mirror ``continue_orbits``': from the stable orbit reached from rest at the
band's lower end (``first_point``, the same start point), up in f; if that walk does
not reach the band's upper end, a second from the orbit at the upper end, down. Where
a package has a knob that ``continue_orbits`` has, it gets ``continue_orbits``' value.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.metadata
import io
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from unittest import mock

import numpy as np

from numerics.continuation import WalkOptions
from numerics.continuation.period_map import PeriodMap, Point
from numerics.continuation.walk import DEFAULTS, first_point
from perturb import ContactModel

#: The walk's tuning, whose numbers the packages are given where they have the same.
_WALK = WalkOptions()

__all__ = ["INSTALL", "contique_walks", "installed_version", "period_map", "pycont_walks",
           "residual_calls", "residual_norms"]

INSTALL = "pip install .[bench]  (or: .venv/bin/pip install pycont_lite contique)"

#: How pycont-lite says a walk ended (the kind of its last event), in words.
PYCONT_ENDINGS = {
    "DSFLOOR": "step too small (DSFLOOR)",
    "PARAM_MAX": "reached the band's upper end (PARAM_MAX)",
    "PARAM_MIN": "reached the band's lower end (PARAM_MIN)",
    "MAXSTEPS": "n_steps taken (MAXSTEPS)",
    "BP": "a branch point (BP)",
}


def installed_version(distribution: str) -> str | None:
    """A distribution's version, or None when it is not installed. (Asked of the
    distribution, not of an import: an unrelated PyPI package also installs a module
    named ``pycont``.)"""
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return None


def period_map(model: ContactModel, pa_frac: float, steps: int, period: int = 1) -> PeriodMap:
    """The period map ``continue_orbits`` walks at ``pa_frac`` with N = ``steps``
    (``Continuation.settings["steps_per_period"]``)."""
    return PeriodMap(model, pa_frac * model.parameters.Q_n, steps, period)


@dataclass
class Walk:
    """One call of a package from one end of the band (``direction`` +1: up in f)."""

    start_hz: float
    direction: int
    points: int = 0
    f_range_hz: tuple[float, float] = (np.nan, np.nan)
    folds_z: list[np.ndarray] = field(default_factory=list)
    folds_are: str = "folds (LP)"  # what the package's fold list is
    segments_stable: list[bool] = field(default_factory=list)
    ending: str = ""
    ended_hz: float = np.nan
    reached_end: bool = False
    z: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))

    def describe(self, f_n0: float) -> str:
        walk = f"walk {'up' if self.direction > 0 else 'down'} from {self.start_hz:g} Hz"
        if not self.points:
            return f"{walk}: {self.ending} (its last residual at {self.ended_hz:.1f} Hz)"
        lo, hi = self.f_range_hz
        folds = ", ".join(f"{z[2] * f_n0:.3f}" for z in self.folds_z[:4]) or "none"
        if len(self.folds_z) > 4:
            folds += f" ... ({len(self.folds_z)} in all)"
        stability = ", ".join("stable" if s else "unstable" for s in self.segments_stable)
        return (f"{walk}: {self.points} points, f {lo:.3f}-{hi:.3f} Hz, {self.folds_are} at "
                f"{folds} Hz{', segments ' + stability if stability else ''}; ended: "
                f"{self.ending} at {self.ended_hz:.3f} Hz")


@dataclass
class PackageRun:
    walks: list[Walk]
    elapsed_s: float
    evaluations: int  # the package's residual calls (its start points' polish apart)

    @property
    def z(self) -> np.ndarray:
        """The points of its walks (pycont-lite's located folds apart)."""
        return np.vstack([np.empty((0, 3))] + [w.z for w in self.walks])

    @property
    def folds_z(self) -> np.ndarray:
        return np.array([z for w in self.walks for z in w.folds_z]).reshape(-1, 3)


def _walk_band(shoot: PeriodMap, model: ContactModel, fmin_hz: float, fmax_hz: float,
               walk_from: Callable[[Point, Walk], None]) -> list[Walk]:
    """Up from the orbit reached from rest at ``fmin_hz``; if that walk ends inside the
    band, down from the one at ``fmax_hz`` (``walk_from`` fills a walk from its start)."""
    walks = []
    for f_start, direction in ((fmin_hz, +1), (fmax_hz, -1)):
        walk = Walk(f_start, direction)
        walks.append(walk)
        first, reached = first_point(shoot, model, f_start)
        if first is None:
            walk.ending = f"no start: {reached}"
        else:
            walk_from(first, walk)
        if walk.reached_end:
            break
    return walks


# pycont-lite ------------------------------------------------------------------------

def pycont_settings(shoot: PeriodMap, fmin_hz: float, fmax_hz: float, direction: int,
                    bifurcation_detection: bool = False) -> dict:
    """pycont-lite's keyword arguments, spelled out; its steps are in the same scaled z
    as ``continue_orbits``'."""
    f_n0 = shoot.scale[2]
    return {
        "ds_min": _WALK.ds_min,  # continue_orbits gives up below the same step
        "ds_max": DEFAULTS["ds_max"],
        "ds_0": _WALK.ds_start,
        "n_steps": DEFAULTS["max_points"],
        "verbosity": "off",
        "solver_parameters": {
            # Newton-Krylov's aim, on |F| (continue_orbits' is on Newton's step). A step
            # is still accepted when |F| <= 10 max(tolerance, rdiff) = 6.6e-5: that is
            # how far from the branch its points may lie.
            "tolerance": _WALK.newton_tol,
            "nk_maxiter": _WALK.newton_iterations,
            "rdiff": 6.6e-6,  # pycont-lite's default finite-difference step
            "param_min": fmin_hz / f_n0,
            "param_max": fmax_hz / f_n0,
            "initial_directions": "increase_p" if direction > 0 else "decrease_p",
            # Its branch-point test, on by default in pycont-lite, is off here: the period
            # map has no branch point on this branch; left on, it reports one near 743 Hz
            # and pycont-lite 0.6.0's branch switching then raises UnboundLocalError.
            "bifurcation_detection": bifurcation_detection,
            "analyze_stability": True,  # Re of the rightmost eigenvalue of dG/du = M - I
            "hopf_detection": False,  # a map's residual has no Hopf point
            "seed": 12345,
        },
    }


class _CountedResidual:
    """G(u, p) for pycont-lite: the residual of ``shoot`` at z = (u, p); counts calls
    and keeps the last p, to say where a walk that raised was."""

    def __init__(self, shoot: PeriodMap) -> None:
        self.shoot, self.calls, self.last_p = shoot, 0, np.nan

    def __call__(self, u: np.ndarray, p: float) -> np.ndarray:
        self.calls += 1
        self.last_p = float(p)
        return self.shoot.residual(np.append(u, p))[0]


def pycont_walks(shoot: PeriodMap, model: ContactModel, fmin_hz: float, fmax_hz: float,
                 bifurcation_detection: bool = False) -> PackageRun:
    """pycont-lite on ``shoot``'s residual over the band, walked as ``continue_orbits``
    walks it."""
    pycont = importlib.import_module("pycont")
    residual = _CountedResidual(shoot)

    def walk_from(first: Point, walk: Walk) -> None:
        kwargs = pycont_settings(shoot, fmin_hz, fmax_hz, walk.direction,
                                 bifurcation_detection)
        u0, p0 = first.z[:2], first.z[2]
        try:
            result = pycont.arclengthContinuation(residual, u0, p0, **kwargs)
        except Exception as error:  # noqa: BLE001  (a failure of the package is a result)
            walk.ending = f"raised {type(error).__name__}: {error}"
            walk.ended_hz = residual.last_p * shoot.scale[2]
            return
        _fill_pycont(walk, result, shoot.scale[2])

    start = time.perf_counter()
    walks = _walk_band(shoot, model, fmin_hz, fmax_hz, walk_from)
    return PackageRun(walks, time.perf_counter() - start, residual.calls)


def _fill_pycont(walk: Walk, result, f_n0: float) -> None:
    """A walk's points, folds, stability and ending from pycont-lite's result: its
    branches are the segments between folds (each LP event starts the next)."""
    walk.folds_z = [np.append(e.u, e.p) for e in result.events if e.kind == "LP"]
    z = np.vstack([np.column_stack([b.u_path, b.p_path]) for b in result.branches])
    # An LP is inserted in the path where pycont-lite located it; it is kept apart here.
    located = np.zeros(len(z), dtype=bool)
    for fold in walk.folds_z:
        located |= (z == fold).all(axis=1)
    _fill_points(walk, z[~located], f_n0)
    walk.segments_stable = [bool(b.stable) for b in result.branches]
    last = result.events[-1]
    walk.ending = PYCONT_ENDINGS.get(last.kind, last.kind)
    walk.ended_hz = last.p * f_n0
    walk.reached_end = last.kind == ("PARAM_MAX" if walk.direction > 0 else "PARAM_MIN")


def _fill_points(walk: Walk, z: np.ndarray, f_n0: float) -> None:
    walk.z, walk.points = z, len(z)
    f = z[:, 2] * f_n0
    walk.f_range_hz = (float(f.min()), float(f.max()))


# contique ---------------------------------------------------------------------------

#: The start point lies on the band's edge to round-off (f / f_n0 to 1e-16).
_EDGE = 1e-12


class _ResidualAndJacobian:
    """contique's ``fun`` and ``jac`` = (dR/du, dR/dp) from one residual call per point:
    its Newton asks for R, then for the Jacobian, at the same point."""

    def __init__(self, shoot: PeriodMap) -> None:
        self.shoot, self.calls, self.key, self.value = shoot, 0, None, None

    def _at(self, u, p):
        key = (float(u[0]), float(u[1]), float(p))
        if key != self.key:
            self.calls += 1
            r, jacobian, _ = self.shoot.residual(np.array(key))
            self.key, self.value = key, (r, jacobian)
        return self.value

    def fun(self, u, p, *_):
        return self._at(u, p)[0]

    def jac(self):
        return (lambda u, p, *_: self._at(u, p)[1][:, :2],
                lambda u, p, *_: self._at(u, p)[1][:, 2])


def contique_settings(direction: int, step_max: float = DEFAULTS["ds_max"]) -> dict:
    """contique's keyword arguments, spelled out. Its step is a largest increment of
    each unknown of z (``step_max``), halved on a failed Newton and grown by up to 1.5
    after a converged one (less the more iterations it took: its experimental
    "rebalance"), much as ``continue_orbits``' ds is."""
    return {
        "dxmax": step_max,
        "dlpfmax": step_max,
        "control0": (-1, direction),  # start with f as the control component
        "maxsteps": DEFAULTS["max_points"],
        "maxcycles": 4,  # contique's example's value
        "maxiter": _WALK.newton_iterations,
        "tol": _WALK.newton_tol,  # on |R| here; continue_orbits' is on Newton's step
        "overshoot": 1.0,
        "rebalance": True,
        "increase": 0.5,  # x (1 + 0.5 (8 - iterations) / 8)
        "decrease": 2.0,
        "high": 1.0,  # never above step_max
        "low": _WALK.ds_min / step_max,  # continue_orbits gives up below the same step
        "minlastfailed": 1,
    }


def contique_walks(shoot: PeriodMap, model: ContactModel, fmin_hz: float, fmax_hz: float,
                   step_max: float = DEFAULTS["ds_max"]) -> PackageRun:
    """contique on ``shoot``'s residual and Jacobian over the band, walked as
    ``continue_orbits`` walks it."""
    contique = importlib.import_module("contique")
    residual = _ResidualAndJacobian(shoot)
    band = (fmin_hz / shoot.scale[2], fmax_hz / shoot.scale[2])

    def walk_from(first: Point, walk: Walk) -> None:
        settings = contique_settings(walk.direction, step_max)
        points = []
        with contextlib.redirect_stdout(io.StringIO()):  # it prints a line per step
            for result in contique.solve(residual.fun, first.z[:2].copy(), first.z[2],
                                         jac=residual.jac(), **settings):
                if not band[0] - _EDGE <= result.x[2] <= band[1] + _EDGE:
                    break
                points.append(result.x.copy())
            else:
                result = None  # it stopped by itself
        _fill_contique(walk, np.array(points), result, shoot.scale[2], settings["maxsteps"])

    start = time.perf_counter()
    walks = _walk_band(shoot, model, fmin_hz, fmax_hz, walk_from)
    return PackageRun(walks, time.perf_counter() - start, residual.calls)


def _fill_contique(walk: Walk, z: np.ndarray, outside, f_n0: float, maxsteps: int) -> None:
    """A walk's points, the turns of f among them and its ending; ``outside`` is its
    first result outside the band (None if it stopped inside)."""
    _fill_points(walk, z, f_n0)
    f = z[:, 2]
    walk.folds_are = "turns of f"  # contique reports no fold: f turning back between points
    walk.folds_z = list(z[1:-1][np.diff(np.sign(np.diff(f))) != 0])
    walk.ended_hz = f[-1] * f_n0
    if outside is not None:
        walk.reached_end = (outside.x[2] > f[-1]) == (walk.direction > 0)
        walk.ending = ("left the band at its far end" if walk.reached_end else
                       "turned back and left the band where it started")
    elif len(z) > maxsteps:
        walk.ending = "maxsteps taken"
    else:
        walk.ending = "Newton failed at its smallest step"


# Both ---------------------------------------------------------------------------------

def residual_norms(shoot: PeriodMap, z: np.ndarray) -> np.ndarray:
    """max |R| (in z) at each point: how close to the branch the points are."""
    return np.array([np.abs(shoot.residual(point)[0]).max() for point in z])


def residual_calls(function: Callable[[], object]) -> int:
    """How many times ``function()`` evaluates a ``PeriodMap``'s residual."""
    with mock.patch.object(PeriodMap, "residual", autospec=True,
                           side_effect=PeriodMap.residual) as spy:
        function()
    return spy.call_count
