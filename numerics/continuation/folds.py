"""Fold curves of period-1 orbits continued in the (f_e, P_a) plane, with their cusps.

Where a resonance peak bends, a band of f_e holds two stable orbits (the paper's
bi-stability, Section 3.3) bounded by two folds. As P_a changes the folds move;
here they are followed as curves of the (f_e, P_a) plane.

- **Unknowns.** w = (y / y0, v / (omega0 y0), f / f_n0, a), a = P_a / Q: the scaled
  unknowns of ``period_map`` plus the force amplitude.
- **Equations** (the minimally augmented system of a fold, 3 equations in 4
  unknowns, so a curve):

      R(x, f, a) = Phi(x, f, a) - x = 0         (2: a period-1 orbit, Eq. 2.4)
      g(x, f, a) = det(M - I) = (1 - mu1)(1 - mu2) = 0   (1: the fold test)

  Phi is one period of the simulator's RK4 map at a fixed N steps per period and M
  its monodromy matrix (the compiled tangent kernel ``shoot_periods``).
- **Why g = 0 is a fold.** Along a branch at fixed a, the tangent (dx, df) solves
  (M - I) dx + R_f df = 0; f turns back (df = 0) exactly where M - I is singular,
  i.e. a Floquet multiplier passes +1 (and R_f is not in the range of M - I, which
  holds at the folds continued here: Newton converges quadratically on them). The
  model has no symmetry, so no pitchfork shares that condition.
- **Derivatives.** R_x = M - I is the tangent kernel's; R_f, R_a and the gradient
  of g are central differences (relative step 1e-7, ``_H_OUTER``),
  all from one kernel call of nine lanes (w and w +- h e_i).
- **Continuation.** Pseudo-arclength in w, with the predictor, the corrector
  (Newton with a line search, to 1e-10 in w) and the step control of
  ``continue_orbits`` (``period_map.PeriodMap.correct``), starting from a fold
  that ``continue_orbits`` located at a seed P_a (corrected onto g = 0 at that a),
  walked both ways until the curve leaves the box [fmin, fmax] x [pa_min, pa_max].
- **Cusps.** The two folds of one resonance are the two sides of one smooth curve
  in w; where they meet, the curve's a has a minimum (its projection onto the
  (f, a) plane is a cusp): the least P_a at which the bistable region exists. It
  is located where the a-component of the curve's tangent changes sign from - to +,
  by Brent's method on the arclength to ``LOCATE_TOL`` (1e-8 in w; a is then
  exact to rounding, as it is stationary there).
- **Resonance.** A curve with a cusp is labelled with the m of the resonance
  f_n0 / m nearest (in ratio) to the cusp's f_e: 1 the primary, 2 and 3 the 1/2 and
  1/3 superharmonics; one without a cusp in the box gets 0 (unknown: the primary's
  upper fold reaches 745 Hz at 0.1 Q, next to the 1/2 superharmonic).

Through loss of contact the fixed-step map is only piecewise smooth (see
``walk``): there g has corners and Newton may not pass them; a curve ends
there with its status and message.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np

from perturb import ContactModel
from perturb.common import Result, Status, check_positive, progress, result

from ..kernels.lanes import Lanes
from ..simulation.rk4 import check_model
from .options import WalkOptions
from .period_map import PeriodMap, Point
from .walk import DEFAULTS as _CONTINUATION_DEFAULTS
from .walk import (
    ArclengthWalk,
    Bifurcation,
    check_options,
    check_walk,
    continue_orbits,
)

__all__ = ["Cusp", "FoldCurve", "FoldCurves", "fold_curves", "DEFAULTS"]

#: The step control of ``continue_orbits`` (its first and least step, growth and shrink,
#: Newton's easy count), over a curve of at most 500 points.
DEFAULTS = _CONTINUATION_DEFAULTS | {"max_points": 500}
#: A seed fold within this distance (in w) of a curve already traced lies on it: the
#: chords of a curve (ds <= ds_max = 0.02, curvature some 10 in w) stray by ~5e-4 from it,
#: while the two folds of one peak at one P_a lie 0.3 or more apart (App differs).
_ON_CURVE = 2e-3
#: Seeds are searched at these shares of [pa_min, pa_max] when none are given.
_SEED_SHARES = (1.0, 0.5)
#: The relative step of the central differences in w (R_f, R_a and the gradient of g).
#: Their error, the truncation (h^2: 1e-14) plus the round-off of one period over h
#: (1e-13 / h: 1e-6), only slows Newton by that factor: the fold it converges to does not
#: move. Small, so that it rarely straddles a corner of the map (1e-3 was tried and
#: reached less far into loss of contact).
_H_OUTER = 1e-7
#: A least a along a curve is a cusp only if the curve rises by this much (in P_a / Q) on
#: both sides of it: at a corner of the map in loss of contact, t_a was seen to turn over
#: 1e-4 Q (0.0991 Q, 755 Hz) with no second fold behind it.
_CUSP_RISE = 1e-3
#: How far (relative) the f_e of a fold that ``FoldCurves.folds_at`` corrects may lie from
#: the fold of the N-step map: its ``frequency_tol_hz`` over f_e. Newton on the fold system
#: converges quadratically there (3 iterations), so once its step is below newton_tol
#: (1e-10 in w, 1.5e-7 Hz) the point is a root to the round-off of R and g, which then
#: bounds f_e. Measured on the paper's model (tests/test_folds.py): within 4.2e-15 f_e of
#: ``continue_orbits``' located folds (another route: Brent on the tangent, 15 folds of
#: the three resonances, N = 512 and 2048); Newton started 1e-6 away in (y, v, f) landed
#: within a spread of 7.5e-15 f_e (a one-off check, not in the tests: the primary's folds
#: from 0.07 % above its cusp to 0.045 Q). Stated: 2e-14, some 3 times the largest.
FOLD_F_RTOL = 2e-14
#: Two corrected points closer than this (in w) are one fold: Newton from two guesses
#: lands on one fold within 1e-14, while two folds at one P_a lie 0.3 or more apart.
_SAME_FOLD = 1e-9
_E_A = np.array([0.0, 0.0, 0.0, 1.0])  # the row that fixes a
_E_F = np.array([0.0, 0.0, 1.0, 0.0])  # the row that fixes f


@result
class FoldCurve(Result):
    """One fold curve: the folds of period-1 orbits, point by point along its arclength.

    Attributes
    ----------
    resonance : int
        m of the resonance f_n0 / m it bounds (1 the primary, 2 the 1/2 superharmonic),
        told from the f_e of its cusp; 0 when it has no cusp in the box.
    frequency_hz, pa_frac : ndarray
        The fold's f_e [Hz] and P_a / Q at each point.
    app_m : ndarray
        App of the orbit at the fold [m].
    multipliers : ndarray, shape (points, 2), complex
        Its Floquet multipliers (one of them is 1).
    y_start_m, v_start_m_s : ndarray
        Its state at phase 0 [m, m/s].
    status : int
        Success when both ends reached the box's edge.
    message : str
        Why an end stopped inside the box.
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    resonance: int
    frequency_hz: np.ndarray
    pa_frac: np.ndarray
    app_m: np.ndarray
    multipliers: np.ndarray
    y_start_m: np.ndarray
    v_start_m_s: np.ndarray
    status: int = int(Status.SUCCESS)
    message: str = ""

    def summary(self) -> str:
        return (f"FoldCurve: {resonance_name(self.resonance)}, {self.frequency_hz.size} points, "
                f"f_e {self.frequency_hz.min(initial=np.inf):.6g}-"
                f"{self.frequency_hz.max(initial=-np.inf):.6g} Hz, P_a "
                f"{self.pa_frac.min(initial=np.inf):.4g}-{self.pa_frac.max(initial=-np.inf):.4g}"
                f" Q, {Status(self.status).name.lower()}"
                + (f": {self.message}" if self.message else ""))


@result
class Cusp(Result):
    """Where the two folds of one resonance meet: the least P_a of its bistable region."""

    resonance: int
    frequency_hz: float
    pa_frac: float
    app_m: float

    def summary(self) -> str:
        return (f"Cusp: {resonance_name(self.resonance)} at {self.frequency_hz:.6g} Hz, "
                f"P_a = {self.pa_frac:.6g} Q, App {self.app_m * 1e9:.4g} nm")


@result
class FoldCurves(Result):
    """Fold curves in the (f_e, P_a) plane, their cusps, and the folds they started from.

    Attributes
    ----------
    fold_curves : list of FoldCurve
    cusps : list of Cusp
    seeds : list of Bifurcation
        The folds ``continue_orbits`` located at the seed P_a's, each a curve's start
        (or lying on a curve started before).
    model, settings : dict
        The model; fmin_hz, fmax_hz, pa_min, pa_max, seed_pa_fracs, steps_per_period
        (the N used), ds_max, max_angle, max_points.
    elapsed_s : float
    """

    fold_curves: list[FoldCurve]
    cusps: list[Cusp]
    seeds: list[Bifurcation]
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return (f"FoldCurves: {len(self.fold_curves)} curve(s), "
                f"{sum(c.frequency_hz.size for c in self.fold_curves)} points, "
                f"{len(self.cusps)} cusp(s), {len(self.seeds)} seed fold(s), "
                f"{self.elapsed_s:.3g} s")

    def table(self) -> str:
        return "\n".join([f"  {c.summary()}" for c in self.fold_curves]
                         + [f"  {c.summary()}" for c in self.cusps])

    def folds_at(self, pa_frac: float) -> list[Bifurcation]:
        """The folds at one P_a / Q: each curve's crossings of that level, corrected by
        Newton on the fold system with a fixed (not interpolated), ordered by f_e; each
        f_e to the round-off of the period map (``frequency_tol_hz``: ``FOLD_F_RTOL``
        times f_e)."""
        pa_frac = check_positive("pa_frac", pa_frac)
        fold_map = FoldMap(ContactModel.from_dict(self.model),
                           self.settings["steps_per_period"],
                           WalkOptions.from_dict(self.settings.get("walk_options", {})))
        found = []
        for curve in self.fold_curves:
            w = fold_map.scaled(curve.y_start_m, curve.v_start_m_s, curve.frequency_hz,
                                curve.pa_frac)
            side = np.sign(curve.pa_frac - pa_frac)
            guesses = [w[i] + (pa_frac - w[i, 3]) / (w[i + 1, 3] - w[i, 3]) * (w[i + 1] - w[i])
                       for i in np.flatnonzero(side[:-1] * side[1:] < 0)]
            for guess in guesses + list(w[side == 0]):
                point = fold_map.correct(guess, _E_A, pa_frac)
                if point is not None:
                    found.append(point.z)
        if not found:
            return []
        y, v, f, a = fold_map.physical(_distinct(found))
        app = fold_map.app(y, v, f, a)
        return sorted((Bifurcation(kind="fold", frequency_hz=float(fi), app_m=float(ai),
                                   pa_frac=float(pa_frac), located=True,
                                   frequency_tol_hz=FOLD_F_RTOL * float(fi), pa_frac_tol=0.0)
                       for fi, ai in zip(f, app)), key=lambda b: b.frequency_hz)


def _distinct(points: list[np.ndarray]) -> np.ndarray:
    """The points (rows of w) with those within ``_SAME_FOLD`` of an earlier one left out
    (a crossing at a point of a curve is found twice). Unrounded: rounding them to tell
    them apart cost f_e 7e-7 Hz, 1e5 times its round-off."""
    kept: list[np.ndarray] = []
    for z in points:
        if all(np.abs(z - k).max() > _SAME_FOLD for k in kept):
            kept.append(z)
    return np.array(kept)


def resonance_name(m: int) -> str:
    """"primary", "1/m superharmonic", or "resonance unknown" (m = 0: no cusp)."""
    return {0: "resonance unknown", 1: "primary"}.get(m, f"1/{m} superharmonic")


class FoldMap(PeriodMap):
    """The fold system [R; g] of period-1 orbits in w = (y/y0, v/(omega0 y0), f/f_n0, a)."""

    def __init__(self, model: ContactModel, steps: int,
                 options: WalkOptions | None = None) -> None:
        # Its residual, the fold system [R; g], is its own: Newton on it stays in Python
        # (the compiled walk's corrects R alone).
        super().__init__(model, 0.0, steps, period=1, engine="python", options=options)
        self.q_n = model.parameters.Q_n
        self.model = model

    def scaled(self, y, v, f, a) -> np.ndarray:
        """w of physical (y [m], v [m/s], f_e [Hz], P_a / Q), arrays stacked on the last axis."""
        return np.stack([np.asarray(y) / self.scale[0], np.asarray(v) / self.scale[1],
                         np.asarray(f) / self.scale[2], np.asarray(a, dtype=float)], axis=-1)

    def physical(self, w: np.ndarray):
        """(y [m], v [m/s], f_e [Hz], P_a / Q) of w (one point or rows of points)."""
        w = np.asarray(w)
        return (w[..., 0] * self.scale[0], w[..., 1] * self.scale[1],
                w[..., 2] * self.scale[2], w[..., 3])

    def residual(self, w: np.ndarray):
        """[R; g] (3,), its Jacobian (3, 4) and the monodromy matrix at w: one kernel call
        of 9 lanes, w and w +- h_i e_i."""
        h = _H_OUTER * np.maximum(np.abs(w), [1.0, 1.0, 0.0, 0.0])
        lanes = np.vstack([w, w + np.diag(h), w - np.diag(h)])
        y, v, f, a = self.physical(lanes)
        ys, vs = y.copy(), v.copy()
        monodromy = np.empty((lanes.shape[0], 2, 2))
        self.kernels.shoot_periods(ys, vs, 1.0 / (self.steps * f), a * self.q_n, self.drive, 1,
                                   monodromy)
        self.evaluations += 1
        d = self.scale[:2]
        r = np.stack([ys - y, vs - v], axis=1) / d  # R of every lane, scaled
        g = np.linalg.det(monodromy - np.eye(2))  # det(M - I): similarity-invariant
        jacobian = np.empty((3, 4))
        jacobian[:2, :2] = (monodromy[0] - np.eye(2)) * d[None, :] / d[:, None]
        jacobian[:2, 2:] = ((r[1:5] - r[5:9]) / (2 * h)[:, None]).T[:, 2:]
        jacobian[2, :] = (g[1:5] - g[5:9]) / (2 * h)
        return np.append(r[0], g[0]), jacobian, monodromy[0]

    def app(self, y, v, f, a) -> np.ndarray:
        """App over one period from each state, all in one kernel call."""
        f = np.atleast_1d(f)
        if not f.size:
            return np.empty(0)
        lanes = Lanes(self.model, f, np.atleast_1d(a) * self.q_n, self.steps)
        rec = lanes.record(np.atleast_1d(y).copy(), np.atleast_1d(v).copy(), 1,
                           np.full(f.size, -1, dtype=np.int64))
        return rec.ymax - rec.ymin


def fold_curves(
    fmin_hz: float,
    fmax_hz: float,
    pa_min: float,
    pa_max: float,
    *,
    model: ContactModel | None = None,
    seed_pa_fracs: Sequence[float] | None = None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    ds_max: float = DEFAULTS["ds_max"],
    max_angle: float = DEFAULTS["max_angle"],
    max_points: int = DEFAULTS["max_points"],
    quiet: bool = True,
    options: WalkOptions | None = None,
) -> FoldCurves:
    """Continue the folds of period-1 orbits in (f_e, P_a) over a box, with their cusps.

    Parameters
    ----------
    fmin_hz, fmax_hz : float
        The band of f_e [Hz].
    pa_min, pa_max : float
        The band of P_a / Q (0 < pa_min < pa_max).
    model : ContactModel, optional
        The paper's full model by default.
    seed_pa_fracs : sequence of float, optional
        The P_a / Q at which ``continue_orbits`` looks for folds to start curves from
        (each within [pa_min, pa_max]); by default pa_max and the band's middle.
    steps_per_period : int or "auto"
        N, fixed over the whole box; "auto" takes ``continue_orbits``' choice at the
        first seed.
    ds_max, max_angle, max_points
        The step control, as in ``continue_orbits`` (``max_points`` per walk).
    quiet : bool
        No progress bar on stderr.
    options : WalkOptions, optional
        The walks' tuning, as in ``continue_orbits``: the seeds' walks and the fold
        curves' (which take its steps and corrector, not its corners: they walk over
        none).

    Returns
    -------
    FoldCurves

    Examples
    --------
    >>> run = fold_curves(1300.0, 1500.0, 0.03, 0.05)
    >>> [(c.resonance, round(c.frequency_hz), round(c.pa_frac, 4)) for c in run.cusps]
    [(1, 1442, 0.0334)]
    """
    model = check_model(model)
    fmin_hz, fmax_hz = check_positive("fmin_hz", fmin_hz), check_positive("fmax_hz", fmax_hz)
    if not fmin_hz < fmax_hz:
        raise ValueError(f"`fmax_hz` must be above `fmin_hz`, got {fmin_hz!r} and {fmax_hz!r}.")
    pa_min, pa_max = check_positive("pa_min", pa_min), check_positive("pa_max", pa_max)
    if not pa_min < pa_max:
        raise ValueError(f"`pa_max` must be above `pa_min`, got {pa_min!r} and {pa_max!r}.")
    seeds = _seed_levels(seed_pa_fracs, pa_min, pa_max)
    ds_max, max_angle, max_points = check_walk(1, ds_max, max_angle, max_points)
    options = check_options(options)
    start = time.perf_counter()
    bar = progress(len(seeds), "folds", quiet=quiet)
    box = (fmin_hz, fmax_hz, pa_min, pa_max)
    fold_map, walks, seed_folds, cusps = None, [], [], []
    for pa_frac in seeds:
        # ValueError (a band out of the model's reach) comes from here, before any work.
        run = continue_orbits(pa_frac, fmin_hz, fmax_hz, model=model,
                              steps_per_period=steps_per_period, ds_max=ds_max,
                              max_angle=max_angle, quiet=True, options=options)
        if fold_map is None:
            fold_map = FoldMap(model, run.settings["steps_per_period"], options)
        for fold, w in _seed_points(fold_map, run):
            seed_folds.append(fold)
            if any(_distance_to(w, curve) < _ON_CURVE for curve, *_ in walks):
                continue
            traced = _trace(fold_map, w, box, ds_max, max_angle, max_points)
            if traced is not None:
                walks.append(traced)
        bar.update()
    bar.close()
    curves, cusps = [], []
    for walk in walks:
        curve, its_cusps = _curve(fold_map, *walk)
        curves.append(curve)
        cusps += its_cusps
    settings = {"fmin_hz": fmin_hz, "fmax_hz": fmax_hz, "pa_min": pa_min, "pa_max": pa_max,
                "seed_pa_fracs": list(seeds), "steps_per_period": fold_map.steps,
                "ds_max": ds_max, "max_angle": max_angle, "max_points": max_points,
                "walk_options": options.as_dict()}
    return FoldCurves(fold_curves=curves, cusps=cusps, seeds=seed_folds, model=model.as_dict(),
                      settings=settings, elapsed_s=time.perf_counter() - start)


def _seed_levels(seed_pa_fracs, pa_min: float, pa_max: float) -> list[float]:
    if seed_pa_fracs is None:
        return [pa_min + share * (pa_max - pa_min) for share in _SEED_SHARES]
    levels = [check_positive("seed_pa_fracs", a) for a in np.atleast_1d(seed_pa_fracs)]
    if not levels or any(not pa_min <= a <= pa_max for a in levels):
        raise ValueError(f"`seed_pa_fracs` must be one or more values within [pa_min, pa_max] "
                         f"= [{pa_min!r}, {pa_max!r}], got {seed_pa_fracs!r}.")
    return levels


def _seed_points(fold_map: FoldMap, run) -> list[tuple[Bifurcation, np.ndarray]]:
    """Each fold of a ``Continuation`` (period 1) with its point w (the fold is a point of
    its branch: the same f_e and App)."""
    out = []
    for fold in run.folds():
        for branch in run.branches:
            at = np.flatnonzero((branch.frequency_hz == fold.frequency_hz)
                                & (branch.app_m == fold.app_m))
            if at.size:
                i = at[0]
                out.append((fold, fold_map.scaled(branch.y_start_m[i], branch.v_start_m_s[i],
                                                  branch.frequency_hz[i], run.pa_frac)))
                break
    return out


def _distance_to(w: np.ndarray, points: list[Point]) -> float:
    """Distance (in w) from w to the polyline of a traced curve's points."""
    z = np.array([p.z for p in points])
    a, b = z[:-1], z[1:]
    ab = b - a
    share = np.clip(np.einsum("ij,ij->i", w - a, ab) / np.maximum(
        np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
    return float(np.linalg.norm(a + share[:, None] * ab - w, axis=1).min(initial=np.inf))


def _trace(fold_map: FoldMap, w, box, ds_max, max_angle, max_points):
    """The curve through a seed fold, walked both ways: (points, cusp marks, status,
    message), or None when the seed does not correct onto g = 0."""
    first = fold_map.correct(w, _E_A, w[3])
    if first is None:
        return None
    walks = [FoldWalk(fold_map, box, ds_max, max_angle, max_points) for _ in (0, 1)]
    for walk, direction in zip(walks, (-1.0, 1.0)):
        walk.run(first, direction)
    down, up = walks
    points = down.points[::-1] + up.points[1:]
    n_down = len(down.points)
    # Index in ``points``: down's k-th point is n_down - 1 - k, up's is n_down - 1 + k.
    cusps = [n_down - 1 - k for k in down.cusps] + [n_down - 1 + k for k in up.cusps]
    messages = [w.message for w in walks if w.status != Status.SUCCESS]
    status = Status.SUCCESS if not messages else Status.FAILED
    return points, cusps, status, "; ".join(messages)


class FoldWalk(ArclengthWalk):
    """One direction of a fold curve from its seed, step by step on the walks' one engine
    (``walk.ArclengthWalk``, with ``WalkOptions.for_fold_curves``: patient Newton, no
    corners), with the cusps met, until the curve leaves the box."""

    def __init__(self, fold_map: FoldMap, box, ds_max, max_angle, max_points):
        super().__init__(fold_map, ds_max, max_angle, max_points,
                         fold_map.options.for_fold_curves())
        fmin, fmax, self.a_lo, self.a_hi = box
        self.f_lo, self.f_hi = fmin / fold_map.scale[2], fmax / fold_map.scale[2]
        self.cusps: list[int] = []  # the indices of the cusps in ``points``

    def run(self, first: Point, direction: float) -> None:
        """From ``first``, a growing (direction +1) or falling (-1) at the start, until the
        curve leaves the box."""
        along_a = direction * _E_A
        self.orientation = first.orientation(first.tangent(_E_A, 1.0) * direction) or 1.0
        self._keep(first, first.tangent(along_a, self.orientation))
        ds = self.options.ds_start
        while len(self.points) < self.max_points:
            step, ds = self._step(ds)
            if step is None:
                _, _, f, a = self.shoot.physical(self.points[-1].z)
                self.end(Status.FAILED, f"step below {self.options.ds_min:g} at f_e = "
                         f"{f:.6g} Hz, P_a = {a:.6g} Q: Newton does not converge there")
                return
            point, t, ds = step
            if self._outside(point.z):
                self._clip(point)
                return
            if self.tangents[-1][3] < 0 <= t[3]:  # a turns from falling to rising
                self._cusp(point)
            self._keep(point, t)
        self.end(Status.FAILED, f"gave up after {self.max_points} points (max_points)")

    def _outside(self, w) -> bool:
        return not (self.f_lo <= w[2] <= self.f_hi and self.a_lo <= w[3] <= self.a_hi)

    def _cusp(self, point: Point) -> None:
        """Locate the cusp (t_a = 0) between the last point and ``point`` by Brent's method
        on the arclength, and keep it as a point of the curve."""
        located = self.locate(self.points[-1], self.tangents[-1], point,
                              lambda p, t: t[3], self.orientation)
        if located is not None:
            _, cusp, t_cusp = located
            self.cusps.append(len(self.points))
            self._keep(cusp, t_cusp)

    def _clip(self, point: Point) -> None:
        """The last point exactly on the box's edge that ``point`` crossed."""
        w = point.z
        if not self.a_lo <= w[3] <= self.a_hi:
            row, edge = _E_A, (self.a_hi if w[3] > self.a_hi else self.a_lo)
        else:
            row, edge = _E_F, (self.f_hi if w[2] > self.f_hi else self.f_lo)
        self.clip(point, row, edge, self.tangents[-1])




def _curve(fold_map: FoldMap, points, cusps, status, message) -> tuple[FoldCurve, list[Cusp]]:
    """A traced curve's columns (App of all points in one batched recording) and its
    cusps."""
    w = np.array([p.z for p in points])
    y, v, f, a = fold_map.physical(w)
    app = fold_map.app(y, v, f, a)
    cusps = [i for i in cusps if min(a[:i].max(initial=0.0), a[i + 1:].max(initial=0.0))
             - a[i] > _CUSP_RISE]
    resonance = _resonance(fold_map, f[cusps[0]]) if cusps else 0
    curve = FoldCurve(resonance=resonance, frequency_hz=f, pa_frac=a, app_m=app,
                      multipliers=np.array([p.multipliers for p in points]), y_start_m=y,
                      v_start_m_s=v, status=int(status), message=message)
    return curve, [Cusp(resonance=resonance, frequency_hz=float(f[i]), pa_frac=float(a[i]),
                        app_m=float(app[i])) for i in cusps]


def _resonance(fold_map: FoldMap, f_hz: float) -> int:
    """The m whose f_n0 / m is nearest to f_hz in ratio."""
    ratio = fold_map.scale[2] / f_hz
    below = max(int(np.floor(ratio)), 1)
    return below if ratio / below < (below + 1) / ratio else below + 1
