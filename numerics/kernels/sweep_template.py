"""A whole frequency sweep as one compiled call, as a template.

``numerics.kernels.codegen`` appends this file's text after ``kernel_template.py``, so
the functions here call that file's batched kernels (``shoot_periods``,
``strobe_periods``, ``record_periods``) and the generated ``acceleration``; the
file is never imported on its own.

``sweep_lanes`` does, point after point, what ``numerics.steady.shooting.steady_states``
does for the lanes of one point (continuation Newton with the reach test and the
stability check, the short march that confirms it, the settling march, polish,
recording of the extrema and the least period, the half-step error estimate with
the stiffness test, the refinement passes with doubled steps, the statuses), in
the same order and with the same batches of lanes, and seeds the next point as
``numerics.steady.sweeps.sweep_points`` does. Every constant comes from ``steady.shooting``, every
engine decision from ``steady.options``' defaults.

A point's state is held in a float table ``fl`` and an integer table ``it`` with
one row per lane and the columns named below, plus the multipliers and the
extrema: several passes (a step count each) are merged row by row.
"""

import math

import numba
import numpy as np

# The steady-state engine's constants and its default options: read by both routes. The
# compiled sweep is built with the default engine decisions (steady.sweep_compiled.supported).
from numerics.steady.options import SteadyOptions
from numerics.steady.shooting import (
    CAP_PERIODS,
    CHUNK,
    LANE_STEP_BUDGET,
    LONGEST_CHUNK,
    PERIODS_TRIED,
    ROUNDOFF,
    SPAN_FLOOR,
)
from numerics.steady.shooting import (
    RANK as STATUS_RANK,
)
from perturb.common import Status

_ENGINE = SteadyOptions()
NEWTON_ITERATIONS = _ENGINE.newton_iterations
REACH_CONTINUATION = _ENGINE.reach_continuation
REACH_POLISH = _ENGINE.reach_polish
DISTINCT_LAG = _ENGINE.distinct_lag
VERIFY_PERIODS = _ENGINE.verify_periods
VERIFY_SHRINK = _ENGINE.verify_shrink
VERIFY_FIRST = _ENGINE.verify_first
VERIFY_LINEAR = _ENGINE.verify_linear
VERIFY_EARLY_SHRINK = _ENGINE.early_shrink * _ENGINE.verify_shrink
SHARPEN_SLACK = _ENGINE.sharpen_slack
UNESTIMATED_SLACK = _ENGINE.unestimated_slack
RESOLVED_OMEGA_DT = _ENGINE.resolved_omega_dt
UNKNOWN_AMPLIFICATION = _ENGINE.unknown_amplification
ORDER_FACTOR = _ENGINE.order_factor
_SUCCESS = int(Status.SUCCESS)
_NOT_SETTLED = int(Status.NOT_SETTLED)
_FAILED = int(Status.FAILED)
_UNDER_RESOLVED = int(Status.UNDER_RESOLVED)
#: ``Orbits.method``, by code.
METHODS = ("none", "newton", "march+newton", "march")
_M_NONE, _M_NEWTON, _M_MARCH_NEWTON, _M_MARCH = 0, 1, 2, 3
#: How good each status is (``steady.shooting.RANK``), indexed by status + 1.
RANK = np.asarray(STATUS_RANK, dtype=np.int64)
_STATUS_OFFSET = -_FAILED
_KEEP_LAST = max(PERIODS_TRIED) + 3  # stroboscopic samples the period test looks at
_LARGEST_PERIOD = max(PERIODS_TRIED)
_CAP_FIRST = CAP_PERIODS[0]
_LARGEST_FLOAT = np.finfo(np.float64).max
# The march keeps the last _KEEP_LAST samples of its last chunk only: every chunk is
# at least that long (the shortest is CHUNK).
assert CHUNK >= _KEEP_LAST

# Columns of a point's state tables.
F_YMIN, F_YMAX, F_Y, F_V, F_ERROR = 0, 1, 2, 3, 4
I_STATUS, I_PERIOD, I_METHOD, I_STEPS, I_RUN, I_FAILED_AT, I_CAP = 0, 1, 2, 3, 4, 5, 6
_FLOATS, _INTS = 5, 7

_jit = numba.njit(cache=True, error_model="numpy")
# Small helpers are inlined in numba's IR: a compiled function links in and optimises
# again the machine code of everything it calls, so that fewer levels of calls compile
# faster (measured: 37 s to compile with every function apart, 25 s so, 70 s with all
# inlined into the driver).
_inline = numba.njit(cache=True, error_model="numpy", inline="always")


@_inline
def _nanmax(a, b):
    """np.maximum of two numbers: NaN if either is."""
    if a != a or b != b:
        return np.nan
    return a if a >= b else b


@_inline
def _scale(span, length):
    """Batch.scale: the orbit's App, at least SPAN_FLOOR of y0."""
    return _nanmax(span, SPAN_FLOOR * length)


@_inline
def _distance(dy, dv, omega, scale):
    """Batch.distance: |dy|/L + |dv|/(Omega L)."""
    return abs(dy) / scale + abs(dv) / (omega * scale)


@_inline
def _drive(tables, table_steps, table_offset, steps):
    """The drive table of ``steps`` per period (``lanes.drive_table``), from the flat store."""
    for i in range(table_steps.shape[0]):
        if table_steps[i] == steps:
            return tables[table_offset[i]:table_offset[i] + 2 * steps + 1]
    return tables[:0]  # never: Python stores a table for every step count a pass takes


@_inline
def _multipliers(m00, m01, m10, m11):
    """The eigenvalues of a 2x2 monodromy matrix (NaN where it is not finite)."""
    if not (math.isfinite(m00) and math.isfinite(m01) and math.isfinite(m10)
            and math.isfinite(m11)):
        return complex(np.nan, np.nan), complex(np.nan, np.nan)
    half_trace = 0.5 * (m00 + m11)
    disc = 0.25 * (m00 - m11) ** 2 + m01 * m10
    if disc >= 0.0:
        root = math.sqrt(disc)
        return complex(half_trace + root, 0.0), complex(half_trace - root, 0.0)
    root = math.sqrt(-disc)
    return complex(half_trace, root), complex(half_trace, -root)


@_inline
def _known(mu0, mu1):
    """np.isfinite(multipliers).all() of one lane."""
    return (math.isfinite(mu0.real) and math.isfinite(mu0.imag) and math.isfinite(mu1.real)
            and math.isfinite(mu1.imag))


@_inline
def _shoot_multipliers(y, v, dt, p_a, drive, periods):
    """The multipliers of the ``periods``-fold map at the orbit start (y, v), one lane."""
    monodromy = np.empty((1, 2, 2))
    shoot_periods(np.array([y]), np.array([v]), np.array([dt]), np.array([p_a]),  # noqa: F821
                  drive, periods, monodromy)
    return _multipliers(monodromy[0, 0, 0], monodromy[0, 0, 1], monodromy[0, 1, 0],
                        monodromy[0, 1, 1])


@_inline
def _largest_modulus(mu0, mu1):
    """np.abs(multipliers).max(): NaN if either is NaN."""
    return _nanmax(abs(mu0), abs(mu1))


@_jit
def _newton(idx, y_start, v_start, p, span, reach, dt, p_a, omega, drive, tol, length,
            periods_run):
    """Batch.newton on the lanes ``idx`` (one batch: the lanes still iterating iterate
    together); also returns the last monodromy matrices, which _follows takes, and the
    first shot Phi_p(y_start, v_start)."""
    n = idx.shape[0]
    y, v = y_start.copy(), v_start.copy()
    monodromy = np.empty((n, 2, 2))
    converged = np.zeros(n, dtype=np.bool_)
    shot_y, shot_v = np.empty(n), np.empty(n)
    active = np.arange(n)
    for iteration in range(NEWTON_ITERATIONS):
        lanes = idx[active]
        yp, vp, m = y[active], v[active], np.empty((active.shape[0], 2, 2))
        shoot_periods(yp, vp, dt[lanes], p_a[lanes], drive, p, m)  # noqa: F821
        iterating = np.zeros(active.shape[0], dtype=np.bool_)
        for j in range(active.shape[0]):
            i = active[j]
            periods_run[idx[i]] += p
            if not iteration:
                shot_y[i], shot_v[i] = yp[j], vp[j]
            copy_into(monodromy[i, 0], m[j, 0])  # noqa: F821 (the kernels')
            copy_into(monodromy[i, 1], m[j, 1])  # noqa: F821
            # (M - I) dx = -(Phi(x) - x), by Cramer's rule (steady.shooting.solve_2x2).
            a00, a01 = m[j, 0, 0] - 1.0, m[j, 0, 1]
            a10, a11 = m[j, 1, 0], m[j, 1, 1] - 1.0
            b0, b1 = y[i] - yp[j], v[i] - vp[j]
            det = a00 * a11 - a01 * a10
            step_y = (b0 * a11 - a01 * b1) / det
            step_v = (a00 * b1 - a10 * b0) / det
            y[i], v[i] = y[i] + step_y, v[i] + step_v
            size = _distance(step_y, step_v, omega[idx[i]], length)
            converged[i] = math.isfinite(size) and size < tol * 1e-3
            iterating[j] = math.isfinite(size) and not converged[i]
        active = active[iterating]
        if not active.size:
            break
    ok = np.zeros(n, dtype=np.bool_)
    mult = np.empty((n, 2), dtype=np.complex128)
    for i in range(n):
        mu0, mu1 = _multipliers(monodromy[i, 0, 0], monodromy[i, 0, 1], monodromy[i, 1, 0],
                                monodromy[i, 1, 1])
        mult[i, 0], mult[i, 1] = mu0, mu1
        moved = _distance(y[i] - y_start[i], v[i] - v_start[i], omega[idx[i]],
                          _scale(span[i], length))
        near = math.isfinite(moved) and moved < reach
        largest = _largest_modulus(mu0, mu1)
        stable = (largest if largest == largest else np.inf) < 1.0
        ok[i] = converged[i] and near and stable
    return ok, y, v, mult, monodromy, shot_y, shot_v


@_inline
def _propagate(m, dy, dv, times):
    """steady.shooting._propagate of one lane: M^times (dy, dv), the same operations in order."""
    for _ in range(times):
        dy, dv = m[0, 0] * dy + m[0, 1] * dv, m[1, 0] * dy + m[1, 1] * dv
    return dy, dv


@_jit
def _follows(idx, y, v, y_orbit, v_orbit, p, span, monodromy, shot_y, shot_v, dt, p_a, omega,
             limit, drive, tol, length, periods_run):
    """Batch.follows: whether a short march from (y, v) approaches the orbit, decided
    after VERIFY_FIRST periods where the march follows the orbit's linearisation; its
    first p periods are Newton's first shot (shot_y, shot_v)."""
    n = idx.shape[0]
    full = VERIFY_PERIODS - VERIFY_PERIODS % p
    first = max(VERIFY_FIRST - VERIFY_FIRST % p, p)
    ym, vm = shot_y.copy(), shot_v.copy()
    marched = p
    before, scale = np.empty(n), np.empty(n)
    for i in range(n):
        scale[i] = _scale(span[i], length)
        before[i] = _distance(y[i] - y_orbit[i], v[i] - v_orbit[i], omega[idx[i]], scale[i])
    early = np.zeros(n, dtype=np.bool_)
    if first < full:
        _advance_verify(idx, ym, vm, first - marched, dt, p_a, limit, drive, periods_run)
        marched = first
        for i in range(n):
            ey, ev = ym[i] - y_orbit[i], vm[i] - v_orbit[i]
            ly, lv = _propagate(monodromy[i], y[i] - y_orbit[i], v[i] - v_orbit[i], first // p)
            linear = (_distance(ey - ly, ev - lv, omega[idx[i]], scale[i])
                      <= VERIFY_LINEAR * before[i])
            py, pv = _propagate(monodromy[i], ey, ev, (full - first) // p)
            predicted = _distance(py, pv, omega[idx[i]], scale[i])
            early[i] = linear and predicted < VERIFY_EARLY_SHRINK * before[i]
    rest = np.flatnonzero(~early)
    ym_rest, vm_rest = ym[rest], vm[rest]
    _advance_verify(idx[rest], ym_rest, vm_rest, full - marched, dt, p_a, limit, drive,
                    periods_run)
    _scatter(ym, rest, ym_rest)
    _scatter(vm, rest, vm_rest)
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        after = _distance(ym[i] - y_orbit[i], vm[i] - v_orbit[i], omega[idx[i]], scale[i])
        out[i] = early[i] or (after < VERIFY_SHRINK * before[i]) or (after < tol)
    return out


@_inline
def _newton_from(group, y, v, p, span, reach, method, check, fl, it, mult, dt, p_a, omega,
                 limit, drive, tol, length, periods_run):
    """steady.shooting._newton_from: Newton from (y, v) on the lanes ``group``, the approach
    check if ``check``, and the accepted orbits written to their rows; which were."""
    ok, yn, vn, mu, monodromy, shot_y, shot_v = _newton(group, y, v, p, span, reach, dt, p_a,
                                                        omega, drive, tol, length, periods_run)
    if check:
        chosen = np.flatnonzero(ok)
        follows = _follows(group[chosen], y[chosen], v[chosen], yn[chosen], vn[chosen], p,
                           span[chosen], monodromy[chosen], shot_y[chosen], shot_v[chosen], dt,
                           p_a, omega, limit, drive, tol, length, periods_run)
        ok[chosen[~follows]] = False
    _accept(fl, it, mult, group[ok], yn[ok], vn[ok], p, mu[ok], method)
    return ok


@_inline
def _advance_verify(lanes, y, v, periods, dt, p_a, limit, drive, periods_run):
    """Batch._march_verify: advance the lanes in place (failures are not kept)."""
    advance_periods(y, v, dt[lanes], p_a[lanes], drive, periods,  # noqa: F821
                    np.full(lanes.shape[0], -1, dtype=np.int64), limit[lanes])
    for lane in lanes:
        periods_run[lane] += periods


@_inline
def _repeating_period(strobe_y, strobe_v, span, omega, tol, length):
    """Batch._repeating_period of one lane, from the last _KEEP_LAST samples of a chunk."""
    last = strobe_y.shape[0] - 1
    scale = _scale(span, length)
    smallest = np.empty(_LARGEST_PERIOD + 1)  # the least lag-p difference of the samples
    for p in range(1, _LARGEST_PERIOD + 1):
        d = np.empty(3)
        for j in range(3):
            now = last - 2 + j
            d[j] = _distance(strobe_y[now] - strobe_y[now - p], strobe_v[now] - strobe_v[now - p],
                             omega, scale)
        rho = _nanmax(d[1] / d[0], d[2] / d[1])
        smallest[p] = -_nanmax(_nanmax(-d[0], -d[1]), -d[2])
        biggest = _nanmax(_nanmax(d[0], d[1]), d[2])
        left = biggest / (1 - rho)
        if biggest < tol * 1e-3 or (rho < 1 and left < tol):
            distinct = True  # every divisor's lag differences clearly not zero
            for q in range(1, p):
                if p % q == 0 and not smallest[q] >= DISTINCT_LAG * tol:
                    distinct = False
            if distinct:
                return p
    return 0


@_jit
def _march(idx, y, v, cap, failed_at, done, dt, p_a, omega, limit, drive, tol, length,
           periods_run):
    """Batch.march: lanes march until their stroboscopic state repeats or their cap,
    counted from ``done`` periods marched before."""
    n = idx.shape[0]
    period = np.zeros(n, dtype=np.int64)
    last_span = np.zeros(n)
    y, v = y.copy(), v.copy()
    active = np.arange(n)
    while True:
        active = active[done < cap[active]]
        if not active.size:
            break
        chunk = CHUNK if done < _CAP_FIRST else min(done // 4, LONGEST_CHUNK)
        lanes = idx[active]
        strobe_y, strobe_v = np.empty((active.size, chunk)), np.empty((active.size, chunk))
        span = np.empty(active.size)
        ya, va, fp = y[active], v[active], failed_at[lanes]
        strobe_periods(ya, va, dt[lanes], p_a[lanes], drive, chunk, strobe_y, strobe_v,  # noqa
                       span, fp, done, limit[lanes])
        moving = np.zeros(active.size, dtype=np.bool_)
        for i in range(active.size):
            y[active[i]], v[active[i]] = ya[i], va[i]
            failed_at[lanes[i]] = fp[i]
            last_span[active[i]] = span[i]
            periods_run[lanes[i]] += chunk
            found = _repeating_period(strobe_y[i], strobe_v[i], span[i], omega[lanes[i]], tol,
                                      length)
            if fp[i] >= 0:
                found = -1
            period[active[i]] = max(found, 0)
            moving[i] = found == 0
        done += chunk
        active = active[moving]
    return period, y, v, last_span


@_jit
def _march_lanes(rest, y, v, guess, cap, failed_at, use_newton, fl, it, mult, dt, p_a, omega,
                 limit, drive, tol, length, periods_run):
    """steady.shooting._march: the lanes ``rest`` march from (y, v); with Newton, those still moving
    after CHUNK periods try Newton and the approach check from there, the others march
    on; lanes that repeat are polished."""
    period, ym, vm, span = _march(rest, y, v, np.minimum(cap, CHUNK) if use_newton else cap,
                                  failed_at, np.int64(0), dt, p_a, omega, limit, drive, tol,
                                  length, periods_run)
    if use_newton:
        moving = np.flatnonzero((period == 0) & (failed_at[rest] < 0) & (cap > CHUNK))
        for p in range(1, _LARGEST_PERIOD + 1):
            chosen = moving[guess[moving] == p]
            if chosen.size:
                _newton_from(rest[chosen], ym[chosen], vm[chosen], p, span[chosen],
                             REACH_CONTINUATION, _M_MARCH_NEWTON, True, fl, it, mult, dt, p_a,
                             omega, limit, drive, tol, length, periods_run)
        on = moving[it[rest[moving], I_STATUS] != _SUCCESS]
        period_on, ym_on, vm_on, span_on = _march(rest[on], ym[on], vm[on], cap[on], failed_at,
                                                  np.int64(CHUNK), dt, p_a, omega, limit,
                                                  drive, tol, length, periods_run)
        _scatter(period, on, period_on)
        _scatter(ym, on, ym_on)
        _scatter(vm, on, vm_on)
        _scatter(span, on, span_on)
    still_open = it[rest, I_STATUS] != _SUCCESS
    for i in range(rest.size):
        if still_open[i]:
            fl[rest[i], F_Y], fl[rest[i], F_V] = ym[i], vm[i]
    no_multipliers = np.empty((0, 2), dtype=np.complex128)
    for p in range(1, _LARGEST_PERIOD + 1):
        chosen = still_open & (period == p)
        group, marched_y, marched_v = rest[chosen], ym[chosen], vm[chosen]
        if not group.size:
            continue
        if use_newton:  # polish: the marched state is within about tol of the orbit
            ok = _newton_from(group, marched_y, marched_v, p, span[chosen], REACH_POLISH,
                              _M_MARCH_NEWTON, False, fl, it, mult, dt, p_a, omega, limit,
                              drive, tol, length, periods_run)
            group, marched_y, marched_v = group[~ok], marched_y[~ok], marched_v[~ok]
        _accept(fl, it, mult, group, marched_y, marched_v, p, no_multipliers, _M_MARCH)


@_inline
def _accept(fl, it, mult, lanes, y, v, p, multipliers, method):
    for i in range(lanes.shape[0]):
        lane = lanes[i]
        it[lane, I_STATUS], it[lane, I_PERIOD], it[lane, I_METHOD] = _SUCCESS, p, method
        fl[lane, F_Y], fl[lane, F_V] = y[i], v[i]
        if multipliers.shape[0]:
            mult[lane, 0], mult[lane, 1] = multipliers[i, 0], multipliers[i, 1]


@_inline
def _least_period(strobe_y, strobe_v, y_start, v_start, p, span, omega, tol, length):
    """steady.shooting._least_period of one lane: the least d dividing p whose state after d
    periods is the start, within tol."""
    scale = _scale(span, length)
    for d in range(1, p):
        if p % d == 0:
            gap = _distance(strobe_y[d - 1] - y_start, strobe_v[d - 1] - v_start, omega, scale)
            if gap < tol:
                return d
    return p


@_jit
def _record_orbits(lanes, steps, fl, it, mult, maxima, minima, dt, p_a, omega, limit, drive,
                   tol, length, periods_run):
    """steady.shooting._record_orbits: one period of the response from each orbit's start."""
    for p in range(1, _LARGEST_PERIOD + 1):
        group = lanes[it[lanes, I_PERIOD] == p]
        n = group.shape[0]
        if not n:
            continue
        width = steps * p  # room for one extremum per step, the most there can be
        first = p - p  # 0, typed int64 (a literal 0 would compile the kernel once more)
        y, v = fl[group, F_Y].copy(), fl[group, F_V].copy()
        ymin, ymax = np.empty(n), np.empty(n)
        value, phase = np.empty((n, width)), np.empty((n, width))
        kind, count = np.empty((n, width), dtype=np.int8), np.zeros(n, dtype=np.int64)
        history_y, history_v = np.empty((n, width)), np.empty((n, width))
        record_periods(y, v, dt[group], p_a[group], drive, p,  # noqa: F821
                       np.full(n, -1, dtype=np.int64), first, ymin, ymax, value, phase, kind,
                       count, history_y, history_v, limit[group])
        for i in range(n):
            lane = group[i]
            periods_run[lane] += p
            strobe_y = history_y[i, steps - 1::steps]
            strobe_v = history_v[i, steps - 1::steps]
            least = _least_period(strobe_y, strobe_v, fl[lane, F_Y], fl[lane, F_V], p,
                                  ymax[i] - ymin[i], omega[lane], tol, length)
            it[lane, I_PERIOD] = least
            if least < p and _known(mult[lane, 0], mult[lane, 1]):  # _least_period_multipliers
                mult[lane, 0], mult[lane, 1] = _shoot_multipliers(
                    fl[lane, F_Y], fl[lane, F_V], dt[lane], p_a[lane], drive, least)
                periods_run[lane] += least
            within = phase[i, :count[i]] < least
            values, kinds = value[i, :count[i]][within], kind[i, :count[i]][within]
            maxima[lane] = values[kinds > 0]
            minima[lane] = values[kinds < 0]
            ends = history_y[i, :least * steps]
            low = min(values.min() if values.size else np.inf, ends.min())
            high = max(values.max() if values.size else -np.inf, ends.max())
            fl[lane, F_YMIN] = min(low, fl[lane, F_Y])
            fl[lane, F_YMAX] = max(high, fl[lane, F_Y])


@_inline
def _stiffest_omega_dt(ymin, ymax, dt, length):
    """steady.shooting._stiffest_omega_dt of one lane."""
    worst = 0.0
    for y in (ymin, ymax):
        h = 1e-6 * _nanmax(abs(y), length)
        slope = (acceleration(y + h, 0.0, 0.0) - acceleration(y - h, 0.0, 0.0)) / (2 * h)  # noqa
        worst = _nanmax(worst, math.sqrt(_nanmax(-slope, 0.0)))
    return worst * dt


@_jit
def _estimate_step_error(lanes, steps, fl, it, mult, f_e, p_a, limit, tables, table_steps,
                         table_offset, dt, length, periods_run):
    """steady.shooting._estimate_step_error: App's relative error from the step, per lane."""
    half_steps = max(steps // 2, 2)
    half_drive = _drive(tables, table_steps, table_offset, half_steps)
    floor = ROUNDOFF * length
    for p in range(1, _LARGEST_PERIOD + 1):
        group = np.empty(lanes.shape[0], dtype=np.int64)
        n = 0
        for lane in lanes:
            if it[lane, I_STATUS] != _SUCCESS or it[lane, I_PERIOD] != p:
                continue
            stiff = _stiffest_omega_dt(fl[lane, F_YMIN], fl[lane, F_YMAX], dt[lane], length)
            if stiff <= RESOLVED_OMEGA_DT:
                group[n] = lane
                n += 1
            else:
                fl[lane, F_ERROR] = np.inf  # too coarse to estimate
        if not n:
            continue
        group = group[:n]
        first = p - p  # 0, typed int64 (a literal 0 would compile the kernel once more)
        y, v = fl[group, F_Y].copy(), fl[group, F_V].copy()
        ymin, ymax = np.empty(n), np.empty(n)
        record_periods(y, v, 1.0 / (half_steps * f_e[group]), p_a[group], half_drive, p,  # noqa
                       np.full(n, -1, dtype=np.int64), first, ymin, ymax, np.empty((n, 0)),
                       np.empty((n, 0)), np.empty((n, 0), dtype=np.int8),
                       np.zeros(n, dtype=np.int64), np.empty((n, 0)), np.empty((n, 0)),
                       limit[group])
        for i in range(n):
            lane = group[i]
            periods_run[lane] += p
            app = fl[lane, F_YMAX] - fl[lane, F_YMIN]
            largest = _largest_modulus(mult[lane, 0], mult[lane, 1])
            amplification = 1 / (1 - largest) if largest < 1 else UNKNOWN_AMPLIFICATION
            change = (_nanmax(abs(app - (ymax[i] - ymin[i])), floor) * amplification
                      / ORDER_FACTOR)
            estimate = 0.0 if app <= floor else change / app
            if estimate != estimate:  # np.nan_to_num(estimate, nan=np.inf)
                estimate = np.inf
            elif estimate == np.inf:
                estimate = _LARGEST_FLOAT
            elif estimate == -np.inf:
                estimate = -_LARGEST_FLOAT
            fl[lane, F_ERROR] = estimate


@_jit
def _solve(lanes, steps, f_e, p_a, y, v, guess, span, cap, limit, continuation, use_newton,
           tol, app_rtol, length, tables, table_steps, table_offset, fl, it, mult, maxima,
           minima, polish_only):
    """steady.shooting._solve: one pass at one step count over ``lanes``; writes their rows
    (``polish_only``: Newton alone, within REACH_POLISH, as steady.shooting._sharpen asks)."""
    lane_count = f_e.shape[0]
    drive = _drive(tables, table_steps, table_offset, steps)
    dt = 1.0 / (steps * f_e)
    omega = 2 * np.pi * f_e
    periods_run = np.zeros(lane_count, dtype=np.int64)
    failed_at = np.full(lane_count, -1, dtype=np.int64)
    for lane in lanes:  # Orbits.empty
        fl[lane, :] = np.nan
        it[lane, I_STATUS], it[lane, I_PERIOD], it[lane, I_METHOD] = _NOT_SETTLED, 0, _M_NONE
        it[lane, I_STEPS] = steps
        it[lane, I_CAP] = min(cap[lane], max(LANE_STEP_BUDGET // steps, CHUNK))
        mult[lane, 0] = complex(np.nan, np.nan)
        mult[lane, 1] = complex(np.nan, np.nan)
        maxima[lane] = np.empty(0)
        minima[lane] = np.empty(0)
    if use_newton and continuation:
        for p in range(1, _LARGEST_PERIOD + 1):
            group = lanes[guess[lanes] == p]
            if group.size:
                _newton_from(group, y[group], v[group], p, span[group],
                             REACH_POLISH if polish_only else REACH_CONTINUATION, _M_NEWTON,
                             not polish_only, fl, it, mult, dt, p_a, omega, limit, drive, tol,
                             length, periods_run)
    rest = lanes[it[lanes, I_STATUS] != _SUCCESS]
    if rest.size and not polish_only:
        _march_lanes(rest, y[rest], v[rest], guess[rest], it[rest, I_CAP], failed_at,
                     use_newton, fl, it, mult, dt, p_a, omega, limit, drive, tol, length,
                     periods_run)
    _record_orbits(lanes, steps, fl, it, mult, maxima, minima, dt, p_a, omega, limit, drive,
                   tol, length, periods_run)
    if app_rtol > 0:
        _estimate_step_error(lanes, steps, fl, it, mult, f_e, p_a, limit, tables, table_steps,
                             table_offset, dt, length, periods_run)
    for lane in lanes:  # steady.shooting._fate (the messages are written in Python)
        it[lane, I_RUN] = periods_run[lane]
        it[lane, I_FAILED_AT] = failed_at[lane]
        if app_rtol > 0 and it[lane, I_STATUS] == _SUCCESS and not fl[lane, F_ERROR] <= app_rtol:
            it[lane, I_STATUS] = _UNDER_RESOLVED
        if failed_at[lane] >= 0:
            it[lane, I_STATUS] = _FAILED


@_inline
def _solve_by_steps(lanes, steps, f_e, p_a, y, v, guess, span, cap, limit, continuation,
                    use_newton, tol, app_rtol, length, tables, table_steps, table_offset, fl, it,
                    mult, maxima, minima, polish_only):
    """steady.shooting._solve_by_steps: a pass per step count, in increasing order."""
    pending = steps[lanes]
    while pending.size:
        count = pending.min()
        pending = pending[pending != count]
        _solve(lanes[steps[lanes] == count], count, f_e, p_a, y, v, guess, span, cap, limit,
               continuation, use_newton, tol, app_rtol, length, tables, table_steps,
               table_offset, fl, it, mult, maxima, minima, polish_only)


@_inline
def _point_tables(n):
    """A point's state tables for n lanes: floats, integers, multipliers, maxima, minima."""
    return (np.empty((n, _FLOATS)), np.empty((n, _INTS), dtype=np.int64),
            np.empty((n, 2), dtype=np.complex128), [np.empty(0)] * n, [np.empty(0)] * n)


@_inline
def _steady_states(steps, f_e, p_a, y, v, guess, span, cap, limit, continuation, use_newton,
                   tol, app_rtol, refinements, max_steps, length, tables, table_steps,
                   table_offset):
    """steady.shooting.steady_states for the lanes of one point; their state tables.

    Pass 0 solves every lane; pass k (a refinement) solves again, with 2^k times the
    steps, the lanes that failed, did not settle, or settled with p > 1 or too coarsely,
    into the fine tables, and keeps its result where it is at least as good."""
    n = f_e.shape[0]
    # Booleans of no literal type: with True/False, numba would compile _solve once more
    # for each combination of literals it meets (bench_sweep's cold start row).
    true, false = np.bool_(True), np.bool_(False)
    fl, it, mult, maxima, minima = _point_tables(n)
    fine_fl, fine_it, fine_mult, fine_maxima, fine_minima = _point_tables(n)
    lanes = np.arange(n)
    for level in range(refinements + 1):
        redo = lanes
        if level:
            redo = lanes[(it[:, I_STATUS] != _SUCCESS) | (it[:, I_PERIOD] > 1)
                         | (it[:, I_STATUS] == _UNDER_RESOLVED)]
            if not redo.size:
                break
        fine = level > 0
        level_steps = np.minimum(steps * 2**level, max_steps)
        if fine and use_newton:  # steady.shooting._sharpen
            coarse = redo[(it[redo, I_STATUS] == _UNDER_RESOLVED)
                          & (it[redo, I_METHOD] == _M_NEWTON)]
            if coarse.size:
                _solve_by_steps(coarse, level_steps, f_e, p_a, fl[:, F_Y].copy(),
                                fl[:, F_V].copy(), it[:, I_PERIOD].copy(),
                                fl[:, F_YMAX] - fl[:, F_YMIN], cap, limit, true, use_newton,
                                tol, app_rtol, length, tables, table_steps, table_offset,
                                fine_fl, fine_it, fine_mult, fine_maxima, fine_minima, true)
                found = np.zeros(coarse.size, dtype=np.bool_)
                for i in range(coarse.size):
                    found[i] = _sharpened(fl[coarse[i]], fine_fl[coarse[i]],
                                          fine_it[coarse[i], I_STATUS])
                _merge(coarse[found], fl, it, mult, maxima, minima, fine_fl, fine_it,
                       fine_mult, fine_maxima, fine_minima)
                for lane in coarse[~found]:
                    it[lane, I_RUN] += fine_it[lane, I_RUN]
                sharpened = np.zeros(n, dtype=np.bool_)
                sharpened[coarse[found]] = True
                redo = redo[~sharpened[redo]]
        if fine and not redo.size:
            continue
        _solve_by_steps(redo, level_steps, f_e, p_a, y, v, guess, span, cap, limit,
                        continuation, use_newton, tol, app_rtol, length, tables, table_steps,
                        table_offset, fine_fl if fine else fl, fine_it if fine else it,
                        fine_mult if fine else mult, fine_maxima if fine else maxima,
                        fine_minima if fine else minima, false)
        if fine:
            _merge(redo, fl, it, mult, maxima, minima, fine_fl, fine_it, fine_mult,
                   fine_maxima, fine_minima)
    return fl, it, mult, maxima, minima


@_jit
def _scatter(target, index, values):
    """target[index] = values, in a loop (see the kernels' ``copy_into``)."""
    for k in range(index.shape[0]):
        target[index[k]] = values[k]


@_inline
def _sharpened(coarse, fine, fine_status):
    """steady.shooting._sharpen's test of one lane (its rows of floats at the coarse and the fine
    step): the fine pass settled, or under-resolved, and moved App by at most its slack."""
    app = coarse[F_YMAX] - coarse[F_YMIN]
    moved = abs((fine[F_YMAX] - fine[F_YMIN]) - app)
    estimate = coarse[F_ERROR]
    slack = SHARPEN_SLACK * estimate if math.isfinite(estimate) else UNESTIMATED_SLACK
    return (fine_status == _SUCCESS or fine_status == _UNDER_RESOLVED) and moved <= slack * app


@_inline
def _merge(lanes, fl, it, mult, maxima, minima, fine_fl, fine_it, fine_mult, fine_maxima,
           fine_minima):
    """steady.shooting._merge: the finer result of ``lanes`` where it is at least as good."""
    for lane in lanes:
        cost = it[lane, I_RUN] + fine_it[lane, I_RUN]
        if (RANK[fine_it[lane, I_STATUS] + _STATUS_OFFSET]
                <= RANK[it[lane, I_STATUS] + _STATUS_OFFSET]):
            copy_into(fl[lane], fine_fl[lane])  # noqa: F821 (the kernels')
            copy_into(it[lane], fine_it[lane])  # noqa: F821
            copy_into(mult[lane], fine_mult[lane])  # noqa: F821
            maxima[lane], minima[lane] = fine_maxima[lane], fine_minima[lane]
        it[lane, I_RUN] = cost


# nogil: groups of lanes are swept at once, in threads (numerics.steady.sweep_compiled).
@numba.njit(cache=True, error_model="numpy", nogil=True)
def sweep_lanes(freq, p_a, steps, cap, limit, y, v, app, period, continued, use_newton, tol,
                app_rtol, refinements, max_steps, length, tables, table_steps, table_offset):
    """Walk every lane through its frequencies (``numerics.steady.sweeps.sweep_points``).

    freq, steps, cap, limit : (lanes, points): f_e, the first pass's steps per period,
        the settling cap and the divergence limit of every point.
    y, v, app, period : (lanes,): the state the lanes start from, and its orbit's App
        and period; ``continued``: whether that is an orbit to continue.
    tables, table_steps, table_offset : the drive tables of every step count used.
    app_rtol : <= 0 for no error estimate.

    Returns the state tables (lanes, points, columns), the multipliers, and the
    extrema: maxima then minima of each point, lane after lane, with their counts.
    """
    lanes, points = freq.shape
    y, v, app, period = y.copy(), v.copy(), app.copy(), period.copy()
    fl = np.empty((lanes, points, _FLOATS))
    it = np.empty((lanes, points, _INTS), dtype=np.int64)
    mult = np.empty((lanes, points, 2), dtype=np.complex128)
    counts = np.zeros((lanes, points, 2), dtype=np.int64)
    found_max = [np.empty(0)] * (lanes * points)  # lane-major
    found_min = [np.empty(0)] * (lanes * points)
    for j in range(points):
        f_fl, f_it, f_mult, maxima, minima = _steady_states(
            steps[:, j].copy(), freq[:, j].copy(), p_a, y, v, period, app, cap[:, j].copy(),
            limit[:, j].copy(), continued, use_newton, tol, app_rtol, refinements, max_steps,
            length, tables, table_steps, table_offset)
        for lane in range(lanes):
            copy_into(fl[lane, j], f_fl[lane])  # noqa: F821 (the kernels')
            copy_into(it[lane, j], f_it[lane])  # noqa: F821
            copy_into(mult[lane, j], f_mult[lane])  # noqa: F821
        for lane in range(lanes):
            found_max[lane * points + j], found_min[lane * points + j] = maxima[lane], minima[lane]
            counts[lane, j, 0], counts[lane, j, 1] = maxima[lane].size, minima[lane].size
            # A settled or under-resolved orbit seeds the next point; nothing else does.
            status = f_it[lane, I_STATUS]
            if status == _SUCCESS or status == _UNDER_RESOLVED:
                y[lane], v[lane] = f_fl[lane, F_Y], f_fl[lane, F_V]
                app[lane] = f_fl[lane, F_YMAX] - f_fl[lane, F_YMIN]
                period[lane] = f_it[lane, I_PERIOD]
        continued = True
    extrema = np.empty(counts.sum())
    at = 0
    for k in range(lanes * points):
        extrema[at:at + found_max[k].size] = found_max[k]
        at += found_max[k].size
        extrema[at:at + found_min[k].size] = found_min[k]
        at += found_min[k].size
    return fl, it, mult, extrema, counts
