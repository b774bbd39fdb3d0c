"""Steady states: Newton shooting on the period map, with time marching as fallback.

The paper's method (Section 2, end) excites the slider at f_e, waits for the
steady state, and notes the extrema of one period. Here a lane is settled when
its stroboscopic (once-per-period) state repeats within a relative tolerance
after p periods, p from 1 to 8. Two routes reach that state:

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

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import Status, lane_array, result

from ..kernels.lanes import Lanes
from ..simulation.rk4 import check_model, initial_lanes
from .options import ACCURACY_FIELDS, LONGEST_PERIOD, MAX_STEPS, SteadyOptions, steady_options
from .orbits import Orbits

__all__ = ["SteadyStates", "steady_states", "DEFAULTS"]

#: The accuracy fields' defaults, by name (``SteadyOptions``): the verbs' keyword defaults.
DEFAULTS = {name: getattr(SteadyOptions, name) for name in ACCURACY_FIELDS if name != "method"}
PERIODS_TRIED = tuple(range(1, LONGEST_PERIOD + 1))  # 1 to 8
CHUNK = 16  # periods marched between settling checks
LONGEST_CHUNK = 4096  # ... and at most this many, far past the default cap
#: The settling cap, in decay times 1/c of the linearised contact (Eq. 2.6): a linear
#: transient falls by e^-30 = 1e-13 in it. By default a lane marches for this long, but
#: at least CAP_PERIODS[0] periods (bouncing orbits dissipate little in short impacts)
#: and at most CAP_PERIODS[1] (with next to no damping: bounded time, not a hang).
_DECAY_TIMES = 30
CAP_PERIODS = (1200, 120_000)
#: Steps per period follow f_e by default: at least 128, and enough that rate * dt is at
#: most this, the rate being the contact's fastest (Eq26Numbers.fastest_rate_per_s: a
#: period at low f_e holds many natural oscillations), but at most
#: _AUTO_MAX_STEPS (beyond, a lane may fail or be under-resolved, and says so).
_AUTO_RATE_DT = 0.5
_AUTO_MAX_STEPS = 2**16
#: The most RK4 steps a lane marches in one pass (some 1-5 s for one lane): the cap in
#: periods is lowered where a period takes many steps, so that no case hangs.
LANE_STEP_BUDGET = 2 * 10**8
SPAN_FLOOR = 1e-3  # of y0: the smallest length scale of the settling test
_EXTREMA_PER_PERIOD = 64  # room for local extrema per period of the response
ROUNDOFF = 1e-14  # of y0: App changes below this are round-off (about 100 ulp of y0)
#: The engine's decisions (how far Newton may move a guess, the approach check, when an
#: error estimate is trusted) are fields of ``SteadyOptions``, with their reasons there
#: and in the tuning log (docs/tuning.md).


@result
class SteadyStates(Orbits):
    """Steady states found per lane, and how (the columns of ``Orbits``).

    Attributes
    ----------
    model : dict
        The model that made them (``ContactModel.as_dict()``).
    settings : dict
        steps_per_period, tol, app_rtol, max_periods, method, refinements.
    elapsed_s : float
    """

    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return f"{super().summary()}, {self.elapsed_s:.3g} s"

    def table(self) -> str:
        return _lane_table(self)


def _lane_table(points: Orbits, rows: int = 20) -> str:
    """One row per lane (the first ``rows``): f_e, status, period, App, ymin, steps."""
    lines = [f"  {'f_e [Hz]':>10} {'status':<14} {'p':>2} {'App [nm]':>11} {'ymin [nm]':>11} "
             f"{'steps':>6}  message"]
    for i in range(min(points.status.size, rows)):
        lines.append(f"  {points.frequency_hz[i]:>10.6g} {Status(points.status[i]).name:<14} "
                     f"{points.period[i]:>2} {points.app_m[i] * 1e9:>11.4g} "
                     f"{points.ymin_m[i] * 1e9:>11.4g} {points.steps_used[i]:>6}  "
                     f"{points.message[i]}")
    if points.status.size > rows:
        lines.append(f"  ... {points.status.size - rows} more lanes")
    return "\n".join(lines)


class Batch(Lanes):
    """The lanes being solved (kernels, steps, drive, limits), with their scales."""

    def __init__(self, model, f_e, p_a, steps, options: SteadyOptions):
        super().__init__(model, f_e, p_a, steps)
        self.options, self.tol = options, options.tol
        self.length = eq26_numbers(model.parameters).y0_m or 1.0
        self.omega = 2 * np.pi * f_e
        self.periods_run = np.zeros(f_e.shape[0], dtype=np.int64)

    def scale(self, span):
        """The length that distances are measured against: the orbit's App, but at
        least a thousandth of y0 (so that a vanishing orbit does not divide by 0)."""
        return np.maximum(span, SPAN_FLOOR * self.length)

    def distance(self, lanes, dy, dv, scale):
        """Relative distance of two states: |dy|/L + |dv|/(Omega L)."""
        return np.abs(dy) / scale + np.abs(dv) / (self.omega[lanes] * scale)

    def newton(self, lanes, y, v, p, span, reach, monodromy=None):
        """Newton on Phi_p(x) = x from (y, v); returns converged, y, v, multipliers and the
        first shot Phi_p(y, v) (the approach check marches on from it).

        A result is kept only if it lies within ``reach`` of the start, relative
        to ``span`` (the size of the orbit the start lies on): Newton must follow
        the orbit it was started on, not jump to another one. A lane stops iterating
        once its step is below tol / 1000, or not finite. ``monodromy``, an
        array (lanes, 2, 2) if given, receives each lane's last monodromy matrix,
        d Phi_p / dx (rows and columns y, v) at its iterate before the last.
        """
        k, lanes = self.kernels, np.asarray(lanes)
        y_start, v_start = y, v
        y, v = y.copy(), v.copy()
        converged = np.zeros(lanes.shape[0], dtype=bool)
        if monodromy is None:
            monodromy = np.empty((lanes.shape[0], 2, 2))
        scale = self.length
        active = np.arange(lanes.shape[0])
        with np.errstate(all="ignore"):  # a lane may diverge: its values are inf or NaN
            for iteration in range(self.options.newton_iterations):
                idx = lanes[active]
                yp, vp, m = y[active], v[active], np.empty((active.size, 2, 2))
                k.shoot_periods(yp, vp, self.dt[idx], self.p_a[idx], self.drive, p, m)
                self.periods_run[idx] += p
                if not iteration:
                    shot = yp, vp
                monodromy[active] = m
                # (M - I) dx = -(Phi(x) - x), a 2x2 solve per lane.
                step_y, step_v = solve_2x2(m - np.eye(2), y[active] - yp, v[active] - vp)
                y[active], v[active] = y[active] + step_y, v[active] + step_v
                size = self.distance(idx, step_y, step_v, scale)
                converged[active] = np.isfinite(size) & (size < self.tol * 1e-3)
                active = active[np.isfinite(size) & ~converged[active]]
                if not active.size:
                    break
            multipliers = eigenvalues(monodromy)
            moved = self.distance(lanes, y - y_start, v - v_start, self.scale(span))
            near = np.isfinite(moved) & (moved < reach)
        return converged & near & _stable(multipliers), y, v, multipliers, shot

    def follows(self, lanes, y, v, y_orbit, v_orbit, p, span, monodromy, shot):
        """Whether time marching from (y, v) approaches the orbit through (y_orbit, v_orbit).

        Newton can continue a stable orbit whose basin no longer holds the
        previous point's state (bouncing orbits, near a fold); the paper's method
        would jump there. A short march decides, as the paper's method would: the
        distance to the orbit must shrink by ``verify_shrink`` in ``verify_periods``.
        Lanes whose first ``verify_first`` periods follow the orbit's linearisation
        (``monodromy``, Newton's, of p periods) are decided then, by its prediction
        of the distance at ``verify_periods`` (``SteadyOptions``; the reasoning is in
        the tuning log).
        The march's first p periods are ``shot``, Newton's first Phi_p(y, v): the same
        RK4 steps, not run twice.
        """
        lanes, o = np.asarray(lanes), self.options
        full = o.verify_periods - o.verify_periods % p
        first = max(o.verify_first - o.verify_first % p, p)
        scale = self.scale(span)
        dy, dv = y - y_orbit, v - v_orbit
        before = self.distance(lanes, dy, dv, scale)
        ym, vm = shot[0].copy(), shot[1].copy()
        marched = p
        early = np.zeros(lanes.size, dtype=bool)
        if first < full:
            self._march_verify(lanes, ym, vm, first - marched)
            marched = first
            with np.errstate(all="ignore"):  # a diverged lane's state is inf or NaN
                ey, ev = ym - y_orbit, vm - v_orbit
                ly, lv = _propagate(monodromy, dy, dv, first // p)
                linear = self.distance(lanes, ey - ly, ev - lv, scale) <= o.verify_linear * before
                py, pv = _propagate(monodromy, ey, ev, (full - first) // p)
                predicted = self.distance(lanes, py, pv, scale)
            early = linear & (predicted < o.early_shrink * o.verify_shrink * before)
        rest = np.flatnonzero(~early)
        ym_rest, vm_rest = ym[rest], vm[rest]
        self._march_verify(lanes[rest], ym_rest, vm_rest, full - marched)
        ym[rest], vm[rest] = ym_rest, vm_rest
        after = self.distance(lanes, ym - y_orbit, vm - v_orbit, scale)
        return early | (after < o.verify_shrink * before) | (after < self.tol)

    def _march_verify(self, lanes, y, v, periods):
        """Advance the approach check's lanes by ``periods`` in place (failures are not
        kept: a lane that diverges does not approach the orbit)."""
        self.advance(y, v, periods, np.full(lanes.size, -1, dtype=np.int64), lanes=lanes)
        self.periods_run[lanes] += periods

    def march(self, lanes, y, v, cap, failed_period, done: int = 0):
        """Time-march lanes until their stroboscopic state repeats; lanes stop when settled
        or at their ``cap`` of periods (one per lane), counted from ``done`` periods
        marched before (so that a march resumed goes on as one that was not stopped).

        Returns the period found (0: not settled), the states, and the last span."""
        k = self.kernels
        lanes = np.asarray(lanes)
        cap = np.broadcast_to(cap, lanes.shape)
        period = np.zeros(lanes.shape[0], dtype=np.int64)
        last_span = np.zeros(lanes.shape[0])
        y, v = y.copy(), v.copy()
        tail_y = np.full((lanes.shape[0], 0), np.nan)
        tail_v = tail_y.copy()
        active = np.arange(lanes.shape[0])
        while True:
            within = done < cap[active]
            active, tail_y, tail_v = active[within], tail_y[within], tail_v[within]
            if not active.size:
                break
            # 16 periods between checks; past the default cap, a quarter of the periods
            # run so far, so that a slow transient takes few calls.
            chunk = CHUNK if done < CAP_PERIODS[0] else min(done // 4, LONGEST_CHUNK)
            idx = lanes[active]
            sy, sv = np.empty((active.size, chunk)), np.empty((active.size, chunk))
            span = np.empty(active.size)
            ya, va, fp = y[active], v[active], failed_period[idx]
            k.strobe_periods(ya, va, self.dt[idx], self.p_a[idx], self.drive, chunk, sy, sv,
                             span, fp, done, self.limit[idx])
            y[active], v[active], failed_period[idx] = ya, va, fp
            last_span[active] = span
            self.periods_run[idx] += chunk
            done += chunk
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
        multiplier is near -1 as period 2. Every p is tested at once: d has the
        shape (lanes, p, j).
        """
        periods = np.array([p for p in PERIODS_TRIED if sy.shape[1] >= p + 3])
        if not periods.size:
            return np.zeros(lanes.shape[0], dtype=np.int64)
        last = np.array([-3, -2, -1]) + sy.shape[1]
        now, before = last[None, :], last[None, :] - periods[:, None]  # (p, j)
        scale = self.scale(span)[:, None, None]
        omega = self.omega[lanes][:, None, None]
        with np.errstate(all="ignore"):  # a diverged lane's samples are inf or NaN
            d = (np.abs(sy[:, now] - sy[:, before]) / scale
                 + np.abs(sv[:, now] - sv[:, before]) / (omega * scale))
            rho = np.maximum(d[..., 1] / d[..., 0], d[..., 2] / d[..., 1])
            left = d.max(axis=2) / (1 - rho)
        reached = (d.max(axis=2) < self.tol * 1e-3) | ((rho < 1) & (left < self.tol))
        # ... but only where the lag-q differences of every divisor q of p are clearly
        # not zero: else the lane may be converging to a q-periodic orbit, which repeats
        # after p periods too (near a period doubling a multiplier near -1 makes lag 2
        # repeat within tol while lag 1 is still at about 2 tol: a period-1 orbit was
        # passed as period 2). It marches on until q is reached, or its cap.
        distinct = d.min(axis=2) >= self.options.distinct_lag * self.tol
        for i, p in enumerate(periods):
            divides = (periods < p) & (p % periods == 0)
            reached[:, i] &= distinct[:, divides].all(axis=1)
        # The least p reached (argmax finds the first True); 0 where none is.
        return np.where(reached.any(axis=1), periods[np.argmax(reached, axis=1)], 0)


def solve_2x2(a: np.ndarray, b0: np.ndarray, b1: np.ndarray):
    """Solve a[i] x = (b0[i], b1[i]) per lane by Cramer's rule (NaN where singular)."""
    det = a[:, 0, 0] * a[:, 1, 1] - a[:, 0, 1] * a[:, 1, 0]
    with np.errstate(all="ignore"):
        x0 = (b0 * a[:, 1, 1] - a[:, 0, 1] * b1) / det
        x1 = (a[:, 0, 0] * b1 - a[:, 1, 0] * b0) / det
    return x0, x1


def eigenvalues(monodromy: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):
        finite = np.isfinite(monodromy).all(axis=(1, 2))
        out = np.full((monodromy.shape[0], 2), np.nan, dtype=complex)
        out[finite] = np.linalg.eigvals(monodromy[finite])
    return out


def _propagate(monodromy: np.ndarray, dy: np.ndarray, dv: np.ndarray, times: int):
    """M^times (dy, dv) per lane, M the monodromy matrix: the linearised period map
    applied to a deviation from the orbit (``kernels.sweep_template._propagate`` is its twin,
    with the same operations in the same order)."""
    for _ in range(times):
        dy, dv = (monodromy[:, 0, 0] * dy + monodromy[:, 0, 1] * dv,
                  monodromy[:, 1, 0] * dy + monodromy[:, 1, 1] * dv)
    return dy, dv


def _stable(multipliers: np.ndarray) -> np.ndarray:
    return np.nan_to_num(np.abs(multipliers), nan=np.inf).max(axis=1) < 1.0


def steady_states(
    frequency_hz,
    p_a_n,
    *,
    model: ContactModel | None = None,
    y_init_m=None,
    v_init_m_s=None,
    period_guess=1,
    app_guess_m=None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    app_rtol: float | None = DEFAULTS["app_rtol"],
    max_periods: int | None = DEFAULTS["max_periods"],
    method: str = "newton",
    refinements: int = DEFAULTS["refinements"],
    keep_orbits: bool = False,
    options: SteadyOptions | None = None,
) -> SteadyStates:
    """Find the steady state reached from each lane's initial state.

    Parameters
    ----------
    frequency_hz, p_a_n : float or array_like, shape (lanes,)
        Excitation frequency f_e [Hz] and force amplitude P_a [N].
    model : ContactModel, optional
        The model (the paper's full model by default).
    y_init_m, v_init_m_s : float or array_like, optional
        Initial states [m, m/s] (rest at y0 by default); for a sweep, the
        previous orbit.
    period_guess : int or array_like
        Period p (1 to 8) of the orbit the initial states lie on (in a sweep, the
        previous point's).
    app_guess_m : float or array_like, optional
        App of that orbit [m]. When given, Newton shooting starts from the
        initial states and keeps a result only if it is stable and close to the
        start (continuation); other lanes are time-marched, try Newton after 16
        periods (kept where the march approaches its orbit), or march on until they
        repeat and are polished.
    steps_per_period : int or "auto"
        RK4 steps per excitation period; "auto" (the default) follows f_e: at least
        128, and a power of two large enough that rate * dt <= 0.5, the rate being the
        contact's fastest, omega0 or its overdamped decay (a period at a low f_e holds
        many natural oscillations: 32768 steps at 1 Hz), up to 2^16.
    tol : float
        Relative tolerance of the stroboscopic repeat.
    app_rtol : float or None
        Bound on App's estimated relative error from the step (``error_estimate``).
        A settled lane above it is solved again with more steps (``refinements``)
        and, if still above, has the status ``Status.UNDER_RESOLVED`` and a message.
        None: no estimate is made (``error_estimate`` is NaN: not estimated).
    max_periods : int or None
        Cap of time marching per lane, in periods. None (the default): a time, 30
        decay times 1/c of the linearised contact (a transient lasts many periods at
        a high f_e), but at least 1,200 and at most 120,000 periods. Lanes still
        moving at the cap are not settled. With Newton, a lane still moving after 16
        periods (a cap above that) tries Newton from there, kept where the march
        approaches the orbit found (``method`` "march+newton").
    method : {"newton", "march"}
        Newton shooting with time marching as the fallback, or time marching only
        (the paper's method as it stands; for checks and baselines).
    refinements : int
        Lanes that fail, do not settle, settle with p > 1 or whose error estimate
        exceeds ``app_rtol`` are solved again from their initial states with 2, 4,
        ... times the steps, this many times: a short impact at a low f_e takes few
        steps, and an under-resolved impact can look like a period-4 orbit or never
        settle. ``steps_used`` says which step each result comes from.
    keep_orbits : bool
        Also keep y after every step of each orbit (``orbit_y_m``).
    options : SteadyOptions, optional
        All of the settings above but ``keep_orbits``, and the engine's own decisions,
        as one object (then none of those keywords may be given beside it).

    Returns
    -------
    SteadyStates
        One row per lane; ``status`` and ``message`` say which lanes settled.

    Examples
    --------
    >>> from perturb import PAPER
    >>> found = steady_states([1000.0, 1480.0], 0.05 * PAPER.Q_n)  # from rest
    >>> found.settled.tolist(), found.period.tolist()
    ([True, True], [1, 1])
    >>> [f"{a * 1e9:.2f} nm" for a in found.app_m]
    ['20.58 nm', '211.48 nm']
    """
    model = check_model(model)
    options = steady_options(options, steps_per_period=steps_per_period, tol=tol,
                             app_rtol=app_rtol, max_periods=max_periods, method=method,
                             refinements=refinements)
    guesses = check_period_guess(period_guess)
    f_e, p_a, y, v, guess, span = initial_lanes(
        frequency_hz, p_a_n, y_init_m, v_init_m_s, model, period_guess=guesses.astype(np.int64),
        app_guess_m=lane_array("app_guess_m", 0.0 if app_guess_m is None else app_guess_m))
    start = time.perf_counter()
    numbers = eq26_numbers(model.parameters)
    steps = lane_steps(options.steps_per_period, f_e, numbers.fastest_rate_per_s)
    cap = settling_cap(f_e, numbers, options.max_periods)
    solve = dict(model=model, options=options, cap=cap,
                 continuation=app_guess_m is not None, keep_orbits=keep_orbits)
    lanes = np.arange(f_e.shape[0])
    state = _solve_by_steps(lanes, steps, f_e, p_a, y, v, guess, span, **solve)
    for level in range(1, options.refinements + 1):
        # A lane that failed, did not settle, settled with p > 1 or too coarsely may be
        # under-resolved (a short impact takes few steps): solved again with twice the steps.
        redo = np.flatnonzero(~state.settled | (state.period > 1)
                              | (state.status == Status.UNDER_RESOLVED))
        if not redo.size:
            break
        finer_steps = np.minimum(steps * 2**level, MAX_STEPS)
        if options.method == "newton":
            redo = _sharpen(state, redo, finer_steps, f_e, p_a, solve)
        if redo.size:
            finer = _solve_by_steps(redo, finer_steps, f_e, p_a, y, v, guess, span, **solve)
            _merge(state, redo, finer)
    settings = steady_settings(options)
    return SteadyStates(**state.columns(), model=model.as_dict(), settings=settings,
                        elapsed_s=time.perf_counter() - start)


def steady_settings(options: SteadyOptions) -> dict:
    """A result's ``settings`` of these options: the accuracy fields, and the engine's
    decisions that differ from the defaults (``"steady_options"``), if any."""
    changes = options.engine_changes()
    return options.accuracy() | ({"steady_options": changes} if changes else {})


def check_period_guess(period_guess) -> np.ndarray:
    """The periods to try first, each one of PERIODS_TRIED, or a ValueError (an orbit that
    did not settle, period 0, cannot seed a steady state)."""
    guesses = np.atleast_1d(np.asarray(period_guess))
    if not np.isin(guesses, PERIODS_TRIED).all():
        raise ValueError(f"`period_guess` must be one of {PERIODS_TRIED}, got {period_guess!r}.")
    return guesses


def settling_cap(frequency_hz: np.ndarray, numbers, max_periods: int | None) -> np.ndarray:
    """Each lane's cap of time marching in periods: ``max_periods``, or by default a
    time, _DECAY_TIMES decay times 1/c (``numbers``: Eq26Numbers), within CAP_PERIODS."""
    if max_periods is None:
        cap = np.clip(np.ceil(_DECAY_TIMES * frequency_hz / numbers.c_per_s), *CAP_PERIODS)
    else:
        cap = np.full(frequency_hz.shape, max_periods)
    return cap.astype(np.int64)


def lane_steps(steps_per_period, frequency_hz: np.ndarray, rate_per_s: float) -> np.ndarray:
    """Steps per period of each lane: as given, or with "auto" at least 128 and a power
    of two large enough that rate * dt <= _AUTO_RATE_DT, the rate being the contact's
    fastest (omega0, or the overdamped rate; at 1 Hz, paper: 32768), up to
    _AUTO_MAX_STEPS."""
    if steps_per_period != "auto":
        return np.full(frequency_hz.shape, int(steps_per_period), dtype=np.int64)
    needed = rate_per_s / (_AUTO_RATE_DT * frequency_hz)
    return np.clip(2 ** np.ceil(np.log2(needed)), 128, _AUTO_MAX_STEPS).astype(np.int64)


def _solve_by_steps(lanes, steps, f_e, p_a, y, v, guess, span, **solve) -> Orbits:
    """``_solve`` for lanes whose steps per period differ: a pass per step count."""
    counts = np.unique(steps[lanes])
    if counts.size == 1:
        return _solve(lanes, f_e, p_a, y, v, guess, span, steps=int(counts[0]), **solve)
    state = Orbits.empty(f_e[lanes], p_a[lanes], 0)
    for n in counts:
        group = np.flatnonzero(steps[lanes] == n)
        state.put(group, _solve(lanes[group], f_e, p_a, y, v, guess, span, steps=int(n),
                                **solve))
    return state


def _solve(lanes, f_e, p_a, y, v, guess, span, *, model, steps, options: SteadyOptions, cap,
           continuation, keep_orbits, polish_only: bool = False) -> Orbits:
    """One pass at a fixed step: Newton continuation, then marching and polishing
    (``polish_only``: Newton from orbits found at fewer steps, within ``reach_polish``, and
    nothing else: ``_sharpen``).

    A sweep runs the compiled twin of this pass and of what it calls
    (``kernels.sweep_template._solve``): a change here is made there too, and
    tests/test_sweep_compiled.py holds the two equal."""
    f_e, p_a, y, v, guess, span, cap = (a[lanes] for a in (f_e, p_a, y, v, guess, span, cap))
    # A bounded time: no more than LANE_STEP_BUDGET steps per lane in this pass.
    cap = np.minimum(cap, max(LANE_STEP_BUDGET // steps, CHUNK))
    batch = Batch(model, f_e, p_a, steps, options)
    method, app_rtol = options.method, options.app_rtol
    state = Orbits.empty(f_e, p_a, steps)
    failed_period = np.full(lanes.size, -1, dtype=np.int64)
    if method == "newton" and continuation:
        # Continuation: follow the orbit the initial states lie on.
        for p in np.unique(guess):
            group = np.flatnonzero(guess == p)
            _newton_from(batch, state, group, y[group], v[group], int(p), span[group],
                         options.reach_polish if polish_only else options.reach_continuation,
                         "newton",
                         check=not polish_only)
    rest = np.flatnonzero(~state.settled)
    if rest.size and not polish_only:
        _march(batch, state, rest, y[rest], v[rest], guess[rest], cap[rest], failed_period,
               method)
    _record_orbits(batch, state, keep_orbits)
    if app_rtol is not None:
        _estimate_step_error(batch, state)
    state.periods_run += batch.periods_run
    _fate(state, batch, failed_period, cap, app_rtol)
    return state


def _newton_from(batch: Batch, state: Orbits, group, y, v, p: int, span, reach, method: str,
                 check: bool) -> np.ndarray:
    """Newton from (y, v) on the lanes ``group``: an orbit that converges within ``reach``,
    stable and (``check``) approached by a march from (y, v) is accepted; which were."""
    monodromy = np.empty((group.size, 2, 2))
    ok, yn, vn, mult, shot = batch.newton(group, y, v, p, span, reach, monodromy)
    if check:
        ok[ok] = batch.follows(group[ok], y[ok], v[ok], yn[ok], vn[ok], p, span[ok],
                               monodromy[ok], (shot[0][ok], shot[1][ok]))
    _accept(state, group[ok], yn[ok], vn[ok], p, mult[ok], method)
    return ok


def _march(batch: Batch, state: Orbits, rest, y, v, guess, cap, failed_period,
           method: str) -> None:
    """Time-march the lanes ``rest`` from (y, v) until they settle or reach their cap.

    With Newton, a lane still moving after the first CHUNK periods tries Newton from
    there, for the period it was guessed to have, and the approach check (a transient
    that decays by |mu| per period takes some 100 periods to come within tol: this one
    takes Newton's few and the check's 4 to 16); the others march on as if not stopped,
    and are polished by Newton when they repeat."""
    newton = method == "newton"
    period, ym, vm, span = batch.march(rest, y, v, np.minimum(cap, CHUNK) if newton else cap,
                                       failed_period)
    if newton:
        moving = np.flatnonzero((period == 0) & (failed_period[rest] < 0) & (cap > CHUNK))
        for p in np.unique(guess[moving]):
            chosen = moving[guess[moving] == p]
            _newton_from(batch, state, rest[chosen], ym[chosen], vm[chosen], int(p),
                         span[chosen], batch.options.reach_continuation, "march+newton",
                         check=True)
        on = moving[~state.settled[rest[moving]]]
        period[on], ym[on], vm[on], span[on] = batch.march(rest[on], ym[on], vm[on], cap[on],
                                                           failed_period, done=CHUNK)
    open_lanes = ~state.settled[rest]
    state.y_start_m[rest[open_lanes]] = ym[open_lanes]
    state.v_start_m_s[rest[open_lanes]] = vm[open_lanes]
    for p in np.unique(period[open_lanes & (period > 0)]):
        chosen = open_lanes & (period == p)
        group, marched_y, marched_v = rest[chosen], ym[chosen], vm[chosen]
        if newton:
            # Polish: the marched state is within about tol of the orbit.
            ok = _newton_from(batch, state, group, marched_y, marched_v, int(p), span[chosen],
                              batch.options.reach_polish, "march+newton", check=False)
            group, marched_y, marched_v = group[~ok], marched_y[~ok], marched_v[~ok]
        _accept(state, group, marched_y, marched_v, int(p), None, "march")


def _accept(state: Orbits, lanes, y, v, p, multipliers, method) -> None:
    state.status[lanes] = Status.SUCCESS
    state.period[lanes] = p
    state.y_start_m[lanes], state.v_start_m_s[lanes] = y, v
    if multipliers is not None:
        state.multipliers[lanes] = multipliers
    state.method[lanes] = method


def _fate(state: Orbits, batch: Batch, failed_period, cap: np.ndarray,
          app_rtol: float) -> None:
    """Status and message of the lanes that did not settle, or settled too coarsely."""
    too_coarse = (np.zeros(state.status.size, dtype=bool) if app_rtol is None
                  else ~(state.error_estimate <= app_rtol))
    coarse = np.flatnonzero(state.settled & too_coarse)
    state.status[coarse] = Status.UNDER_RESOLVED
    for lane in coarse:
        state.message[lane] = under_resolved_message(state.error_estimate[lane], app_rtol,
                                                     batch.steps, batch.options.resolved_omega_dt)
    failed = failed_period >= 0
    state.status[failed] = Status.FAILED
    if failed.any():
        for lane, message in enumerate(batch.failure_messages(failed_period)):
            if message:
                state.message[lane] = message
    for lane in np.flatnonzero((state.status == Status.NOT_SETTLED) & ~failed):
        state.message[lane] = not_settled_message(cap[lane])


def under_resolved_message(estimate: float, app_rtol: float, steps: int,
                           resolved_omega_dt: float = SteadyOptions.resolved_omega_dt) -> str:
    """Why a settled lane is under-resolved."""
    why = (f"App's estimated step error {estimate:.2g} exceeds app_rtol={app_rtol:g}"
           if np.isfinite(estimate) else
           f"the step is too coarse for the contact's stiffest point (omega*dt > "
           f"{resolved_omega_dt:g}), so App's error cannot be estimated")
    return (f"under-resolved: {why} at {steps} steps per period; "
            "raise steps_per_period or refinements")


def not_settled_message(cap: int) -> str:
    """Why a lane that did not fail did not settle within its ``cap`` of periods."""
    return (f"not settled within {cap} periods (quasi-periodic, chaotic, a period above "
            f"{max(PERIODS_TRIED)}, or a slow transient)")


#: How good each status is (0 best), indexed by status + 1: a finer pass replaces a
#: result only if it is at least as good (an under-resolved orbit beats no orbit).
RANK = np.array([3, 0, 2, 1])  # failed, success, not settled, under-resolved


def _rank(status: np.ndarray) -> np.ndarray:
    return RANK[status - int(Status.FAILED)]


def _sharpen(state: Orbits, redo: np.ndarray, steps: np.ndarray, f_e, p_a, solve: dict
             ) -> np.ndarray:
    """Newton at the finer ``steps`` from the orbit of each lane of ``redo`` that settled
    too coarsely; those it finds are merged into ``state``. The lanes left to solve
    again from their initial states: the others of ``redo``, and where Newton fails.

    Only orbits that Newton continued from the lane's initial state and that passed
    the approach check are refined so: the finer orbit is that orbit, moved by the
    step's error, so it needs neither the approach check nor a march, and Newton from
    it, within ``reach_polish``, is all it takes (tests/benchmarks/bench_sweep.py times
    the saving). An orbit the coarse pass marched to is solved again from the initial
    state: the coarse map's attractors can differ from the fine one's (a review found a
    32-step march at 0.1 Q, 755 Hz reaching a 34 nm orbit where the 128-step one
    reaches the 1854 nm bouncing orbit, and polishing it kept the wrong branch).
    """
    coarse = redo[(state.status[redo] == Status.UNDER_RESOLVED) & (state.method[redo] == "newton")]
    if not coarse.size:
        return redo
    sharp = _solve_by_steps(coarse, steps, f_e, p_a, state.y_start_m, state.v_start_m_s,
                            state.period, state.app_m, **(solve | {"continuation": True}),
                            polish_only=True)
    # The same orbit, refined: App moves by about the coarse estimate, not more. (Without
    # this, a 16-step down sweep at 0.3 Q left the bouncing branch for a small orbit whose
    # start lay within reach_polish of it: tests/test_hard_cases.py.)
    moved = np.abs(sharp.app_m - state.app_m[coarse])
    estimate = state.error_estimate[coarse]
    options = solve["options"]
    slack = np.where(np.isfinite(estimate), options.sharpen_slack * estimate,
                     options.unestimated_slack)
    found = ((sharp.settled | (sharp.status == Status.UNDER_RESOLVED))
             & (moved <= slack * state.app_m[coarse]))
    _merge(state, coarse[found], sharp.take(np.flatnonzero(found)))
    state.periods_run[coarse[~found]] += sharp.periods_run[~found]
    return np.setdiff1d(redo, coarse[found])


def _merge(state: Orbits, lanes: np.ndarray, finer: Orbits) -> None:
    """Take the finer pass's result for ``lanes`` where it is at least as good."""
    take = _rank(finer.status) <= _rank(state.status[lanes])
    cost = state.periods_run[lanes] + finer.periods_run
    state.put(lanes[take], finer.take(np.flatnonzero(take)))
    state.periods_run[lanes] = cost


def _record_orbits(batch: Batch, state: Orbits, keep_orbits: bool) -> None:
    """Run one period of the response from each orbit start, noting every extremum.

    A p-periodic orbit is also 2p-, 4p-periodic; the stroboscopic samples of the
    recorded period give the least period, which is what is reported. The run
    is kept as the orbit's history when ``keep_orbits`` (nothing simulates it again).
    """
    if keep_orbits:
        state.orbit_y_m = [np.empty(0)] * state.status.size
    steps = batch.steps
    for p in np.unique(state.period[state.period > 0]):
        group = np.flatnonzero(state.period == p)
        width = _EXTREMA_PER_PERIOD * int(p)
        y, v = state.y_start_m[group].copy(), state.v_start_m_s[group].copy()
        rec = batch.record(y, v, int(p), np.full(group.size, -1, dtype=np.int64),
                           extrema_width=width, history=True, lanes=group)
        batch.periods_run[group] += p
        if (rec.count > width).any():
            # Round-off ringing (a resting orbit) can change the sign of v at every
            # step: record again with room for one extremum per step, the most there is.
            y, v = state.y_start_m[group].copy(), state.v_start_m_s[group].copy()
            rec = batch.record(y, v, int(p), np.full(group.size, -1, dtype=np.int64),
                               extrema_width=steps * int(p), history=True, lanes=group)
        least = _least_period(batch, group, state, rec.history_y[:, steps - 1 :: steps],
                              rec.history_v[:, steps - 1 :: steps], rec.ymax - rec.ymin)
        state.period[group] = least
        shorter = least < p
        if shorter.any():
            _least_period_multipliers(batch, state, group[shorter], least[shorter])
        for j, lane in enumerate(group):
            n = rec.count[j]
            within = rec.phase[j, :n] < least[j]
            values, kinds = rec.value[j, :n][within], rec.kind[j, :n][within]
            state.maxima_m[lane], state.minima_m[lane] = values[kinds > 0], values[kinds < 0]
            ends = rec.history_y[j, : least[j] * steps]
            state.ymin_m[lane] = min(values.min(initial=np.inf), ends.min(),
                                     state.y_start_m[lane])
            state.ymax_m[lane] = max(values.max(initial=-np.inf), ends.max(),
                                     state.y_start_m[lane])
            if keep_orbits:
                state.orbit_y_m[lane] = ends.copy()


def _least_period_multipliers(batch: Batch, state: Orbits, lanes: np.ndarray,
                              least: np.ndarray) -> None:
    """The Floquet multipliers of the least period, where Newton ran on a multiple of it.

    A march finds an orbit of period p as repeating after some multiple k p, and the
    polish's Newton gives the multipliers of that k p-fold map, mu^k: at 0.5 Q,
    1050 Hz with 32 steps, |mu|^4 = 0.70 where the orbit's |mu| is 0.916 (a finite
    difference of the period map agrees), and the step-error estimate, amplified by
    1 / (1 - |mu|), came out 3.5 times too small. One shoot over the least period
    from the orbit's start gives them; lanes without multipliers (march alone) keep none.
    """
    known = np.isfinite(state.multipliers[lanes]).all(axis=1)
    lanes, least = lanes[known], least[known]
    for q in np.unique(least):
        group = lanes[least == q]
        y, v = state.y_start_m[group].copy(), state.v_start_m_s[group].copy()
        monodromy = np.empty((group.size, 2, 2))
        batch.kernels.shoot_periods(y, v, batch.dt[group], batch.p_a[group], batch.drive,
                                    int(q), monodromy)
        batch.periods_run[group] += q
        state.multipliers[group] = eigenvalues(monodromy)


def _estimate_step_error(batch: Batch, state: Orbits) -> None:
    """App's relative error from the step, estimated on each settled orbit.

    One orbit period from the orbit's start at half the steps gives App(N/2). With
    an error C dt^q, App(N) - App(N/2) = (2^q - 1) err(N). Through the kink of loss
    of contact RK4's order falls to 2: q = 2 is taken. One period sees the error made in one
    period; the periodic orbit itself moves by that error times 1 / (1 - |mu|), mu
    the largest Floquet multiplier (near a resonance, |mu| nears 1), so the change
    is scaled by it (by ``unknown_amplification`` where the multipliers are not known).
    A change below round-off of y (ROUNDOFF y0) is taken as that round-off: a tiny
    App is known only to it. The comparison holds only in RK4's asymptotic range:
    where omega * dt at the stiffest point of the orbit exceeds ``resolved_omega_dt``
    the error cannot be estimated, and the estimate is inf (the lane is refined).
    """
    settled = np.flatnonzero(state.settled)
    options = batch.options
    resolved = _stiffest_omega_dt(batch, state, settled) <= options.resolved_omega_dt
    state.error_estimate[settled[~resolved]] = np.inf  # no half-step run for these
    settled = settled[resolved]
    if not settled.size:
        return
    app = state.app_m[settled]
    half = _orbit_app(batch, state, settled, max(batch.steps // 2, 2))
    largest = np.abs(state.multipliers[settled]).max(axis=1)
    with np.errstate(all="ignore"):
        amplification = np.where(largest < 1, 1 / (1 - largest), options.unknown_amplification)
        floor = ROUNDOFF * batch.length
        change = np.maximum(np.abs(app - half), floor) * amplification / options.order_factor
        # An App at round-off itself is rest: there is nothing to resolve.
        estimate = np.where(app <= floor, 0.0, change / app)
    state.error_estimate[settled] = np.nan_to_num(estimate, nan=np.inf)


def _stiffest_omega_dt(batch: Batch, state: Orbits, lanes: np.ndarray) -> np.ndarray:
    """omega * dt with omega^2 = -da/dy, the contact's local stiffness over M, at the
    orbit's extremes (the stiffest points of a hardening or softening law), taken by
    a central difference of the model's own acceleration."""
    worst = np.zeros(lanes.size)
    zero = np.zeros(lanes.size)
    accel = batch.kernels.acceleration_batch
    for y in (state.ymin_m[lanes], state.ymax_m[lanes]):
        h = 1e-6 * np.maximum(np.abs(y), batch.length)
        slope = (accel(y + h, zero, zero) - accel(y - h, zero, zero)) / (2 * h)
        worst = np.maximum(worst, np.sqrt(np.maximum(-slope, 0.0)))
    return worst * batch.dt[lanes]


def _orbit_app(batch: Batch, state: Orbits, lanes: np.ndarray, steps: int) -> np.ndarray:
    """App over one orbit period from each orbit's start, at ``steps`` per period."""
    coarse = Lanes(batch.model, batch.frequency_hz[lanes], batch.p_a[lanes], steps)
    app = np.empty(lanes.size)
    for p in np.unique(state.period[lanes]):
        group = np.flatnonzero(state.period[lanes] == p)
        y = state.y_start_m[lanes[group]].copy()
        v = state.v_start_m_s[lanes[group]].copy()
        rec = coarse.record(y, v, int(p), np.full(group.size, -1, dtype=np.int64), lanes=group)
        batch.periods_run[lanes[group]] += p
        app[group] = rec.ymax - rec.ymin
    return app


def _least_period(batch, group, state, strobe_y, strobe_v, span):
    """The least d (dividing p) with the state after d periods equal to the start, within tol."""
    p = strobe_y.shape[1]
    least = np.full(group.size, p, dtype=np.int64)
    scale = batch.scale(span)
    for d in reversed([d for d in PERIODS_TRIED if d < p and p % d == 0]):
        gap = batch.distance(group, strobe_y[:, d - 1] - state.y_start_m[group],
                             strobe_v[:, d - 1] - state.v_start_m_s[group], scale)
        least[gap < batch.tol] = d
    return least
