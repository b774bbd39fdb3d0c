"""Steady states: Newton shooting on the period map, with time marching as fallback.

The paper's method (Section 2, end) excites the slider at f_e, waits for the
steady state, and notes the extrema of one period. Here a lane is settled when
its stroboscopic (once-per-period) state repeats within a relative tolerance
after p periods, p in 1, 2, 4, 8. Two routes reach that state:

- Newton shooting: solve Phi_p(x) = x for the state x at phase 0, where Phi_p is
  p periods of the very RK4 map the simulator iterates; the derivative of the
  RK4 step gives the 2x2 monodromy matrix, whose eigenvalues (the Floquet
  multipliers) say whether the orbit is stable. Only stable orbits are kept.
- Time marching (the paper's method), lanes stopping as soon as they settle, for
  lanes where Newton fails or finds an unstable orbit; a marched state is then
  polished by Newton. A lane that never settles is reported as not settled.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from perturb import ContactModel

from ._codegen import compiled_kernels
from ._simulate import divergence_limit, drive_table, static_deflection
from ._validate import finite_array, lane_array, positive_int

__all__ = ["SteadyStates", "steady_states", "DEFAULTS"]

#: Defaults chosen for 0.5 % accuracy of App (tests/test_steady.py shows it).
DEFAULTS = {"steps_per_period": 128, "tol": 1e-6, "max_periods": 1200, "refinements": 2}
PERIODS_TRIED = (1, 2, 4, 8)
_CHUNK = 16  # periods marched between settling checks
_NEWTON_ITERATIONS = 10
_SPAN_FLOOR = 1e-3  # of y0: the smallest length scale of the settling test
_REACH_CONTINUATION = 0.5  # how far (relative to App) Newton may move a sweep's guess
_REACH_POLISH = 1e-2  # how far it may move a marched, settled state
_VERIFY_PERIODS = 16  # march that confirms a continued orbit attracts the previous state
_VERIFY_SHRINK = 0.5  # by how much the distance to that orbit must shrink meanwhile
_EXTREMA_PER_PERIOD = 64  # room for local extrema per period of the response


@dataclass
class SteadyStates:
    """Steady states found per lane, and how.

    Attributes
    ----------
    settled : ndarray of bool
        Whether the stroboscopic state repeated within ``tol`` (else: not
        settled within ``max_periods``: quasi-periodic, chaotic or slow).
    period : ndarray of int
        p, the period of the orbit in excitation periods (0 if not settled).
    y_start, v_start : ndarray
        The state at phase 0 on the orbit [m, m/s].
    ymin, ymax : ndarray
        Extremes of y over one period of the response (p excitation periods).
    maxima, minima : list of ndarray
        Every local maximum and minimum of y over that period (Fig. 3).
    multipliers : ndarray, shape (lanes, 2), complex
        Floquet multipliers of the orbit (NaN where not computed).
    method : ndarray of str
        "newton", "march+newton", "march", or "none".
    periods_run : ndarray of int
        Excitation periods integrated for the lane (its cost).
    steps_used : ndarray of int
        Steps per period of the lane's result (see ``refinements``).
    """

    f_e_hz: np.ndarray
    p_a_n: np.ndarray
    model: str
    steps_per_period: int
    tol: float
    settled: np.ndarray
    period: np.ndarray
    y_start: np.ndarray
    v_start: np.ndarray
    ymin: np.ndarray
    ymax: np.ndarray
    maxima: list
    minima: list
    multipliers: np.ndarray
    method: np.ndarray
    periods_run: np.ndarray
    failed: np.ndarray
    steps_used: np.ndarray
    messages: list[str] = field(default_factory=list)
    elapsed_s: float = 0.0

    @property
    def app(self) -> np.ndarray:
        """A_pp = ymax - ymin [m] (Fig. 2)."""
        return self.ymax - self.ymin

    @property
    def contact_lost(self) -> np.ndarray:
        """ymin < 0: the slider leaves the slideway (Fig. 3b-j)."""
        return self.ymin < 0

    def __str__(self) -> str:
        counts = {m: int((self.method == m).sum()) for m in np.unique(self.method)}
        return (
            f"SteadyStates: {self.settled.sum()}/{len(self.settled)} settled, periods "
            f"{sorted(set(self.period.tolist()))}, {counts}, {self.elapsed_s:.3g} s"
        )


class _Batch:
    """The lanes being solved, with their compiled kernels and scales."""

    def __init__(self, model, f_e, p_a, steps, tol):
        self.kernels = compiled_kernels(model)
        self.p_a, self.tol = p_a, tol
        self.dt = 1.0 / (steps * f_e)
        self.drive = drive_table(steps)
        self.length = static_deflection(model) or 1.0
        self.omega = 2 * np.pi * f_e
        self.limit = divergence_limit(model, f_e)
        self.periods_run = np.zeros(f_e.shape[0], dtype=np.int64)

    def scale(self, span):
        """The length that distances are measured against: the orbit's App, but at
        least a thousandth of y0 (so that a vanishing orbit does not divide by 0)."""
        return np.maximum(span, _SPAN_FLOOR * self.length)

    def distance(self, lanes, dy, dv, scale):
        """Relative distance of two states: |dy|/L + |dv|/(Omega L)."""
        return np.abs(dy) / scale + np.abs(dv) / (self.omega[lanes] * scale)

    def newton(self, lanes, y, v, p, span, reach):
        """Newton on Phi_p(x) = x from (y, v); returns converged, y, v, multipliers.

        A result is kept only if it lies within ``reach`` of the start, relative
        to ``span`` (the size of the orbit the start lies on): Newton must follow
        the orbit it was started on, not jump to another one.
        """
        k, lanes = self.kernels, np.asarray(lanes)
        y_start, v_start = y, v
        y, v = y.copy(), v.copy()
        converged = np.zeros(lanes.shape[0], dtype=bool)
        monodromy = np.empty((lanes.shape[0], 2, 2))
        scale = self.length
        for _ in range(_NEWTON_ITERATIONS):
            yp, vp = y.copy(), v.copy()
            k.shoot_periods(yp, vp, self.dt[lanes], self.p_a[lanes], self.drive, p, monodromy)
            self.periods_run[lanes] += p
            # (M - I) dx = -(Phi(x) - x), a 2x2 solve per lane.
            step_y, step_v = _solve_2x2(monodromy - np.eye(2), y - yp, v - vp)
            y, v = y + step_y, v + step_v
            size = self.distance(lanes, step_y, step_v, scale)
            converged = np.isfinite(size) & (size < self.tol * 1e-3)
            if converged.all() or not np.isfinite(size).any():
                break
        multipliers = _eigenvalues(monodromy)
        moved = self.distance(lanes, y - y_start, v - v_start, self.scale(span))
        near = np.isfinite(moved) & (moved < reach)
        return converged & near & _stable(multipliers), y, v, multipliers

    def follows(self, lanes, y, v, y_orbit, v_orbit, p, span):
        """Whether time marching from (y, v) approaches the orbit through (y_orbit, v_orbit).

        Newton can continue a stable orbit whose basin no longer holds the
        previous point's state (bouncing orbits, near a fold); the paper's method
        would jump there. A short march decides, as the paper's method would.
        """
        n = len(lanes)
        periods = _VERIFY_PERIODS - _VERIFY_PERIODS % p
        sy, sv = np.empty((n, periods)), np.empty((n, periods))
        ym, vm, spans = y.copy(), v.copy(), np.empty(n)
        self.kernels.strobe_periods(ym, vm, self.dt[lanes], self.p_a[lanes], self.drive, periods,
                                    sy, sv, spans, np.full(n, -1, dtype=np.int64), 0,
                                    self.limit[lanes])
        self.periods_run[lanes] += periods
        scale = self.scale(span)
        before = self.distance(lanes, y - y_orbit, v - v_orbit, scale)
        after = self.distance(lanes, ym - y_orbit, vm - v_orbit, scale)
        return (after < _VERIFY_SHRINK * before) | (after < self.tol)

    def march(self, lanes, y, v, max_periods, failed_period):
        """Time-march lanes until their stroboscopic state repeats; lanes stop when settled.

        Returns the period found (0: not settled), the states, and the last span."""
        k = self.kernels
        lanes = np.asarray(lanes)
        period = np.zeros(lanes.shape[0], dtype=np.int64)
        last_span = np.zeros(lanes.shape[0])
        y, v = y.copy(), v.copy()
        tail_y = np.full((lanes.shape[0], 0), np.nan)
        tail_v = tail_y.copy()
        active = np.arange(lanes.shape[0])
        done = 0
        while active.size and done < max_periods:
            idx = lanes[active]
            sy, sv = np.empty((active.size, _CHUNK)), np.empty((active.size, _CHUNK))
            span = np.empty(active.size)
            ya, va, fp = y[active], v[active], failed_period[idx]
            k.strobe_periods(ya, va, self.dt[idx], self.p_a[idx], self.drive, _CHUNK, sy, sv,
                             span, fp, done, self.limit[idx])
            y[active], v[active], failed_period[idx] = ya, va, fp
            last_span[active] = span
            self.periods_run[idx] += _CHUNK
            done += _CHUNK
            # The last few stroboscopic samples of each active lane, aligned with `active`.
            keep_last = max(PERIODS_TRIED) + 3
            tail_y = np.concatenate([tail_y, sy], axis=1)[:, -keep_last:]
            tail_v = np.concatenate([tail_v, sv], axis=1)[:, -keep_last:]
            found = self._repeating_period(idx, tail_y, tail_v, span)
            found[fp >= 0] = -1
            period[active] = np.maximum(found, 0)
            moving = found == 0
            active, tail_y, tail_v = active[moving], tail_y[moving], tail_v[moving]
        return period, y, v, last_span

    def _repeating_period(self, lanes, sy, sv, span):
        """The least p whose orbit the lane has reached within tol; 0 if none.

        The lag-p differences d_j = |s_j - s_(j-p)| of the last three samples
        shrink by a factor rho per period while the transient decays; the
        distance left to the p-periodic orbit is then about max(d) / (1 - rho).
        A lag-p difference alone would accept a slowly decaying transient whose
        multiplier is near -1 as period 2.
        """
        scale = self.scale(span)
        found = np.zeros(lanes.shape[0], dtype=np.int64)
        for p in reversed(PERIODS_TRIED):
            if sy.shape[1] < p + 3:
                continue
            d = np.stack([
                self.distance(lanes, sy[:, j] - sy[:, j - p], sv[:, j] - sv[:, j - p], scale)
                for j in (-3, -2, -1)
            ])
            with np.errstate(all="ignore"):
                rho = np.maximum(d[1] / d[0], d[2] / d[1])
                left = d.max(axis=0) / (1 - rho)
            at_roundoff = d.max(axis=0) < self.tol * 1e-3
            found[at_roundoff | ((rho < 1) & (left < self.tol))] = p
        return found


def _solve_2x2(a: np.ndarray, b0: np.ndarray, b1: np.ndarray):
    """Solve a[i] x = (b0[i], b1[i]) per lane by Cramer's rule (NaN where singular)."""
    det = a[:, 0, 0] * a[:, 1, 1] - a[:, 0, 1] * a[:, 1, 0]
    with np.errstate(all="ignore"):
        x0 = (b0 * a[:, 1, 1] - a[:, 0, 1] * b1) / det
        x1 = (a[:, 0, 0] * b1 - a[:, 1, 0] * b0) / det
    return x0, x1


def _eigenvalues(monodromy: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):
        finite = np.isfinite(monodromy).all(axis=(1, 2))
        out = np.full((monodromy.shape[0], 2), np.nan, dtype=complex)
        out[finite] = np.linalg.eigvals(monodromy[finite])
    return out


def _stable(multipliers: np.ndarray) -> np.ndarray:
    return np.nan_to_num(np.abs(multipliers), nan=np.inf).max(axis=1) < 1.0


def steady_states(
    f_e_hz,
    p_a_n,
    *,
    model: ContactModel | None = None,
    y_init=None,
    v_init=None,
    period_guess=1,
    span_guess=None,
    steps_per_period: int = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int = DEFAULTS["max_periods"],
    method: str = "newton",
    refinements: int = DEFAULTS["refinements"],
) -> SteadyStates:
    """Find the steady state reached from each lane's initial state.

    Parameters
    ----------
    f_e_hz, p_a_n : float or array_like, shape (lanes,)
        Excitation frequency [Hz] and force amplitude [N].
    model : ContactModel, optional
        The model (the paper's full model by default).
    y_init, v_init : float or array_like, optional
        Initial states (rest at y0 by default); for a sweep, the previous orbit.
    period_guess : int or array_like
        Period p of the orbit the initial states lie on (in a sweep, the
        previous point's).
    span_guess : float or array_like, optional
        App of that orbit [m]. When given, Newton shooting starts from the
        initial states and keeps a result only if it is stable and close to the
        start (continuation); other lanes are time-marched, then polished.
    steps_per_period : int
        RK4 steps per excitation period.
    tol : float
        Relative tolerance of the stroboscopic repeat.
    max_periods : int
        Cap of time marching per lane; lanes still moving are not settled.
    method : {"newton", "march"}
        Newton shooting with time marching as the fallback, or time marching only
        (the paper's method as it stands; for checks and baselines).
    refinements : int
        Lanes that fail, do not settle or settle with p > 1 are solved again from
        their initial states with 2, 4, ... times the steps, this many times: a
        short impact at a low f_e takes few steps, and an under-resolved impact
        can look like a period-4 orbit or never settle. ``steps_used`` says
        which step each result comes from.

    Examples
    --------
    >>> from perturb import PAPER
    >>> found = steady_states([1000.0, 1480.0], 0.05 * PAPER.weight_n)  # from rest
    >>> found.settled.tolist(), found.period.tolist()
    ([True, True], [1, 1])
    >>> [f"{a * 1e9:.2f} nm" for a in found.app]
    ['20.58 nm', '211.48 nm']
    """
    methods = ("newton", "march")
    if method not in methods:
        raise ValueError(f"`method` must be one of {methods}, got {method!r}.")
    model = ContactModel() if model is None else model
    steps = positive_int("steps_per_period", steps_per_period, minimum=4)
    max_periods = positive_int("max_periods", max_periods)
    tol = float(lane_array("tol", tol, positive=True)[0])
    f_e = lane_array("f_e_hz", f_e_hz, positive=True)
    p_a = lane_array("p_a_n", p_a_n)
    y_init = static_deflection(model) if y_init is None else y_init
    v_init = 0.0 if v_init is None else v_init
    arrays = np.broadcast_arrays(
        f_e, p_a, finite_array("y_init", y_init), finite_array("v_init", v_init),
        np.atleast_1d(np.asarray(period_guess, dtype=np.int64)),
        lane_array("span_guess", 0.0 if span_guess is None else span_guess),
    )
    f_e, p_a, y, v, guess, span = (np.array(a) for a in arrays)
    refinements = positive_int("refinements", refinements, minimum=0)
    start = time.perf_counter()
    solve = dict(model=model, tol=tol, max_periods=max_periods, method=method,
                 continuation=span_guess is not None)
    lanes = np.arange(f_e.shape[0])
    state = _solve(lanes, f_e, p_a, y, v, guess, span, steps=steps, **solve)
    for level in range(1, refinements + 1):
        # A lane that failed, did not settle or settled with p > 1 may be under-resolved
        # (a short impact takes few steps); it is solved again with twice the steps.
        redo = np.flatnonzero(~state.settled | (state.period > 1))
        if not redo.size:
            break
        finer = _solve(redo, f_e, p_a, y, v, guess, span, steps=steps * 2**level, **solve)
        state.merge(redo, finer)
    return SteadyStates(
        f_e_hz=f_e, p_a_n=p_a, model=repr(model), steps_per_period=steps, tol=tol,
        settled=state.settled, period=state.period, y_start=state.y_start,
        v_start=state.v_start, multipliers=state.multipliers, method=state.method,
        periods_run=state.periods_run, failed=state.failed_period >= 0,
        steps_used=state.steps_used, ymin=state.ymin, ymax=state.ymax,
        maxima=state.maxima, minima=state.minima,
        messages=[f"lane {i}: state became non-finite or diverged in period {p}"
                  for i, p in enumerate(state.failed_period) if p >= 0],
        elapsed_s=time.perf_counter() - start,
    )


def _solve(lanes, f_e, p_a, y, v, guess, span, *, model, steps, tol, max_periods, method,
           continuation) -> "_Solution":
    """One pass at a fixed step: Newton continuation, then marching and polishing."""
    f_e, p_a, y, v, guess, span = (a[lanes] for a in (f_e, p_a, y, v, guess, span))
    batch = _Batch(model, f_e, p_a, steps, tol)
    state = _Solution(lanes.size, steps)
    if method == "newton" and continuation:
        # Continuation: follow the orbit the initial states lie on.
        for p in np.unique(guess):
            group = np.flatnonzero(guess == p)
            ok, yn, vn, mult = batch.newton(group, y[group], v[group], int(p), span[group],
                                            _REACH_CONTINUATION)
            ok[ok] = batch.follows(group[ok], y[group][ok], v[group][ok], yn[ok], vn[ok], int(p),
                                   span[group][ok])
            state.accept(group[ok], yn[ok], vn[ok], int(p), mult[ok], "newton")
    rest = np.flatnonzero(~state.settled)
    if rest.size:
        period, ym, vm, span_m = batch.march(rest, y[rest], v[rest], max_periods,
                                             state.failed_period)
        state.y_start[rest], state.v_start[rest] = ym, vm
        for p in np.unique(period[period > 0]):
            chosen = period == p
            group, marched_y, marched_v = rest[chosen], ym[chosen], vm[chosen]
            if method == "newton":
                # Polish: the marched state is within about tol of the orbit.
                ok, yn, vn, mult = batch.newton(group, marched_y, marched_v, int(p),
                                                span_m[chosen], _REACH_POLISH)
                state.accept(group[ok], yn[ok], vn[ok], int(p), mult[ok], "march+newton")
                group, marched_y, marched_v = group[~ok], marched_y[~ok], marched_v[~ok]
            state.accept(group, marched_y, marched_v, int(p), None, "march")
    state.record(batch)
    return state


class _Solution:
    """Per-lane results as they are accepted."""

    def __init__(self, lanes: int, steps: int):
        self.settled = np.zeros(lanes, dtype=bool)
        self.period = np.zeros(lanes, dtype=np.int64)
        self.y_start = np.full(lanes, np.nan)
        self.v_start = np.full(lanes, np.nan)
        self.multipliers = np.full((lanes, 2), np.nan, dtype=complex)
        self.method = np.full(lanes, "none", dtype=object)
        self.failed_period = np.full(lanes, -1, dtype=np.int64)
        self.steps_used = np.full(lanes, steps, dtype=np.int64)
        self.periods_run = np.zeros(lanes, dtype=np.int64)

    def accept(self, lanes, y, v, p, multipliers, method):
        self.settled[lanes] = True
        self.period[lanes] = p
        self.y_start[lanes], self.v_start[lanes] = y, v
        if multipliers is not None:
            self.multipliers[lanes] = multipliers
        self.method[lanes] = method

    def record(self, batch: "_Batch") -> None:
        """Note the extremes of every settled orbit, and the cost."""
        extremes = _record_orbits(batch, self)
        self.ymin, self.ymax = extremes["ymin"], extremes["ymax"]
        self.maxima, self.minima = extremes["maxima"], extremes["minima"]
        self.periods_run += batch.periods_run

    def merge(self, lanes: np.ndarray, finer: "_Solution") -> None:
        """Take the finer pass's result for ``lanes``, unless it settled no better."""
        take = finer.settled | ~self.settled[lanes]
        self.periods_run[lanes] += finer.periods_run
        for name in ("settled", "period", "y_start", "v_start", "multipliers", "method",
                     "failed_period", "steps_used", "ymin", "ymax"):
            getattr(self, name)[lanes[take]] = getattr(finer, name)[take]
        for j in np.flatnonzero(take):
            self.maxima[lanes[j]], self.minima[lanes[j]] = finer.maxima[j], finer.minima[j]


def _record_orbits(batch: _Batch, state: _Solution) -> dict:
    """Run one period of the response from each orbit start, noting every extremum.

    A p-periodic orbit is also 2p-, 4p-periodic; the stroboscopic samples of the
    recorded period give the least period, which is what is reported.
    """
    lanes = state.settled.shape[0]
    ymin, ymax = np.full(lanes, np.nan), np.full(lanes, np.nan)
    maxima = [np.empty(0)] * lanes
    minima = [np.empty(0)] * lanes
    steps = (batch.drive.shape[0] - 1) // 2
    for p in np.unique(state.period[state.period > 0]):
        group = np.flatnonzero(state.period == p)
        n, width = group.size, _EXTREMA_PER_PERIOD * int(p)
        y, v = state.y_start[group].copy(), state.v_start[group].copy()
        lo, hi = np.empty(n), np.empty(n)
        value, phase = np.empty((n, width)), np.empty((n, width))
        kind, count = np.empty((n, width), dtype=np.int8), np.zeros(n, dtype=np.int64)
        history_y, history_v = np.empty((n, int(p) * steps)), np.empty((n, int(p) * steps))
        batch.kernels.record_periods(
            y, v, batch.dt[group], batch.p_a[group], batch.drive, int(p),
            np.full(n, -1, dtype=np.int64), 0, lo, hi, value, phase, kind, count,
            history_y, history_v, batch.limit[group],
        )
        batch.periods_run[group] += p
        least = _least_period(batch, group, state, history_y[:, steps - 1 :: steps],
                              history_v[:, steps - 1 :: steps], hi - lo)
        state.period[group] = least
        if (count > width).any():
            raise RuntimeError(f"an orbit has {int(count.max())} local extrema in {p} "
                               f"period(s), more than the {width} recorded")
        for j, lane in enumerate(group):
            m = count[j]
            within = phase[j, :m] < least[j]
            values, kinds = value[j, :m][within], kind[j, :m][within]
            maxima[lane], minima[lane] = values[kinds > 0], values[kinds < 0]
            ends = history_y[j, : least[j] * steps]
            ymin[lane] = min(values.min(initial=np.inf), ends.min(), state.y_start[lane])
            ymax[lane] = max(values.max(initial=-np.inf), ends.max(), state.y_start[lane])
    return {"ymin": ymin, "ymax": ymax, "maxima": maxima, "minima": minima}


def _least_period(batch, group, state, strobe_y, strobe_v, span):
    """The least d (dividing p) with the state after d periods equal to the start, within tol."""
    p = strobe_y.shape[1]
    least = np.full(group.size, p, dtype=np.int64)
    scale = batch.scale(span)
    for d in reversed([d for d in PERIODS_TRIED if d < p and p % d == 0]):
        gap = batch.distance(group, strobe_y[:, d - 1] - state.y_start[group],
                             strobe_v[:, d - 1] - state.v_start[group], scale)
        least[gap < batch.tol] = d
    return least
