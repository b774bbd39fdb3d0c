"""The compiled kernels of the analytic response, as a template.

``perturb.response.codegen`` appends this file's text to the generated
``residual_lanes``, ``residual_lanes_next`` and ``harmonics_lanes`` of one
order N and one truncation of the series and compiles the result with numba; so
this file is never imported on its own, and those three are defined by the
generated part. ``k_d`` is the array of the coefficients k_j, d_j of the
equation in contact that the series keeps (h alone for Eq. 2.6), in the order of
the generated module's ``COEFFICIENTS``: they reach the compiled code at run time.

The frequency equation of Eq. 2.7, with A0 = G H_1(omega) (Eq. 2.8), is

    residual(omega) = omega^2 - omega0^2 - sum_n b_n(A0, omega, Omega) = 0.

The roots are found as ``frequency.frequency_response`` describes: the
residual on a grid of omega per frequency (uniform, plus points around each
k Omega where a transfer resonates), each sign change refined by the Illinois
method, and each dip of |residual| between neighbours of the same sign (two
roots closer than the grid: both sides of a fold) followed by a golden-section
search until it crosses zero, whose two brackets are then refined too. Each
lane (grid point, bracket, dip) follows the steps of the numpy route that this
replaces; the iterations move all lanes in step, and every batch of residuals
is one call of the generated loop, which has no branch and runs in SIMD.
"""

import math

import numba
import numpy as np

# fmt: off
_GOLDEN = (3 - math.sqrt(5)) / 2
_GRID_ROWS = 64  # frequencies whose grids are evaluated together (300 kB of buffers)
_JIT = {"cache": True, "error_model": "numpy"}  # numpy's rules: x / 0 is inf, no exception
# fmt: on


@numba.njit(**_JIT)
def _fill_grid(Omega, uniform, offsets, resonances, lo, hi, near, grid):
    """The sorted candidate omega of one frequency: ``uniform`` (sorted), and
    k Omega + offsets for k = 1..resonances, clipped to [lo, hi].

    The points near each k Omega are sorted (offsets increase), and so is their
    sequence over k but where neighbouring resonances overlap (Omega < 24 c):
    an insertion sort puts them in order in few moves, then a merge with
    ``uniform`` (numba's general sort costs seconds to compile).
    """
    n = 0
    for k in range(1, resonances + 1):
        for j in range(offsets.size):
            near[n] = min(max(k * Omega + offsets[j], lo), hi)
            n += 1
    for j in range(1, n):
        value, i = near[j], j - 1
        while i >= 0 and near[i] > value:
            near[i + 1] = near[i]
            i -= 1
        near[i + 1] = value
    a = b = 0
    for j in range(grid.size):
        if b == n or (a < uniform.size and uniform[a] <= near[b]):
            grid[j] = uniform[a]
            a += 1
        else:
            grid[j] = near[b]
            b += 1


@numba.njit(inline="always", **_JIT)
def _grid_residual(G, Omega, uniform, offsets, resonances, lo, hi, c, k_d, omega0, first,
                   grid, lanes, lane_Omega, values, near, f):
    """The grid and its residual for the frequencies Omega[first:first + rows], one
    row after another in the flat buffers (rows = grid.size // points).

    Points clipped to an end of the range make a run of equal points at each end of
    a row: the residual is evaluated once per run, at all the other points in one
    SIMD loop, and copied along the runs.
    """
    points = uniform.size + resonances * offsets.size
    rows = grid.size // points
    n = 0
    for row in range(rows):
        W, start = Omega[first + row], row * points
        _fill_grid(W, uniform, offsets, resonances, lo, hi, near, grid[start:start + points])
        a, b = _inner(grid, start, start + points - 1)
        for j in range(a, b + 1):
            lanes[n], lane_Omega[n] = grid[j], W
            n += 1
    residual_lanes(G, lanes[:n], lane_Omega[:n], c, k_d, omega0, values[:n])  # noqa: F821
    n = 0
    for row in range(rows):
        start, end = row * points, row * points + points - 1
        a, b = _inner(grid, start, end)
        for j in range(a, b + 1):
            f[j] = values[n]
            n += 1
        for j in range(start, a):
            f[j] = f[a]
        for j in range(b + 1, end + 1):
            f[j] = f[b]


@numba.njit(**_JIT)
def _inner(grid, start, end):
    """The last point of the run equal to grid[start] and the first of the run equal
    to grid[end] (the points between hold each value once at the ends)."""
    a, b = start, end
    while a < end and grid[a + 1] == grid[start]:
        a += 1
    while b > a and grid[b - 1] == grid[end]:
        b -= 1
    return a, b


@numba.njit(**_JIT)
def _take(values, index):
    """values[index]."""
    out = np.empty(index.size)
    for q in range(index.size):
        out[q] = values[index[q]]
    return out


@numba.njit(inline="always", **_JIT)
def _residual_at(G, omega, active, Omega, c, k_d, omega0, out):
    """out[q] = residual of order N's frequency equation at omega[q], Omega[active[q]]."""
    residual_lanes(G, omega, _take(Omega, active), c, k_d, omega0, out)  # noqa: F821


@numba.njit(**_JIT)
def _still(active, done):
    """The lanes of ``active`` that are not ``done``."""
    kept = 0
    for q in range(active.size):
        if not done[q]:
            active[kept] = active[q]
            kept += 1
    return active[:kept]


@numba.njit(inline="always", **_JIT)
def illinois(G, Omega, c, k_d, omega0, lo, hi, f_lo, f_hi, iterations=80):
    """The root in each bracket [lo, hi] (where the residual changes sign, at
    frequency Omega[i]) by the Illinois method, all brackets in step.

    The end with the sign of the new point is replaced; when the same end is kept
    twice in a row the other end's value is halved, so that both ends move.
    A bracket stops at |hi - lo| <= 1e-13 hi; the root is the end with the
    smaller |residual|.
    """
    side = np.zeros(lo.size, dtype=np.int64)
    active = np.arange(lo.size)
    x, fx, done = np.empty(lo.size), np.empty(lo.size), np.empty(lo.size, dtype=np.bool_)
    for _ in range(iterations):
        if active.size == 0:
            break
        for q, i in enumerate(active):
            x[q] = (lo[i] * f_hi[i] - hi[i] * f_lo[i]) / (f_hi[i] - f_lo[i])
        _residual_at(G, x[:active.size], active, Omega, c, k_d, omega0, fx)
        for q, i in enumerate(active):
            if np.sign(fx[q]) == np.sign(f_lo[i]):
                lo[i], f_lo[i] = x[q], fx[q]
                if side[i] == -1:
                    f_hi[i] /= 2
                side[i] = -1
            else:
                hi[i], f_hi[i] = x[q], fx[q]
                if side[i] == 1:
                    f_lo[i] /= 2
                side[i] = 1
            done[q] = abs(hi[i] - lo[i]) <= 1e-13 * hi[i] or fx[q] == 0
        active = _still(active, done)
    root = np.empty(lo.size)
    for i in range(lo.size):
        root[i] = lo[i] if abs(f_lo[i]) < abs(f_hi[i]) else hi[i]
    return root


@numba.njit(inline="always", **_JIT)
def golden_dips(G, Omega, c, k_d, omega0, lo, mid, hi, f_lo, f_mid, f_hi, iterations=48):
    """Golden-section search of each dip of |residual| towards zero, all in step.

    With g = residual times the sign of the three grid values (positive at lo,
    mid and hi, lowest at mid), the bracket narrows around the minimum of g
    until g < 0 at the probe (a crossing: a root pair lies in [lo, mid] and
    [mid, hi]) or the bracket is below 1e-9 omega (no root pair wider than
    that). Updates lo, mid, hi and f there; returns whether each dip crossed.
    """
    n = lo.size
    sign, g_lo, g_mid, g_hi = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        sign[i] = -1.0 if f_mid[i] < 0 else 1.0
        g_lo[i], g_mid[i], g_hi[i] = f_lo[i] * sign[i], f_mid[i] * sign[i], f_hi[i] * sign[i]
    active = np.arange(lo.size)
    x, gx = np.empty(lo.size), np.empty(lo.size)
    right, done = np.empty(lo.size, dtype=np.bool_), np.empty(lo.size, dtype=np.bool_)
    for _ in range(iterations):
        if active.size == 0:
            break
        for q, i in enumerate(active):  # probe the larger side of mid
            right[q] = (hi[i] - mid[i]) > (mid[i] - lo[i])
            x[q] = (mid[i] + _GOLDEN * (hi[i] - mid[i]) if right[q]
                    else mid[i] - _GOLDEN * (mid[i] - lo[i]))
        _residual_at(G, x[:active.size], active, Omega, c, k_d, omega0, gx)
        for q, i in enumerate(active):
            g = sign[i] * gx[q]
            if g < g_mid[i]:  # the probe becomes mid, the old mid an end
                if right[q]:
                    lo[i], g_lo[i] = mid[i], g_mid[i]
                else:
                    hi[i], g_hi[i] = mid[i], g_mid[i]
                mid[i], g_mid[i] = x[q], g
            elif right[q]:  # the probe is an end
                hi[i], g_hi[i] = x[q], g
            else:
                lo[i], g_lo[i] = x[q], g
            done[q] = g < 0 or hi[i] - lo[i] <= 1e-9 * hi[i]
        active = _still(active, done)
    crossed = np.empty(lo.size, dtype=np.bool_)
    for i in range(lo.size):
        f_lo[i], f_mid[i], f_hi[i] = sign[i] * g_lo[i], sign[i] * g_mid[i], sign[i] * g_hi[i]
        crossed[i] = g_mid[i] < 0
    return crossed


@numba.njit(**_JIT)
def _negative(x):
    """np.signbit(x)."""
    return math.copysign(1.0, x) < 0


@numba.njit(inline="always", **_JIT)
def _scan_grids(G, Omega, uniform, offsets, resonances, lo, hi, c, k_d, omega0, b_row, bracket,
                d_row, dip):
    """Evaluate every frequency's grid, ``_GRID_ROWS`` frequencies at a time in buffers
    that stay in the cache, and keep (returns their numbers):

    - each sign change of the residual: ``b_row``, ``bracket`` = (lo, hi, f(lo), f(hi));
    - each dip, |f| lowest at a point between two of the same sign: ``d_row``,
      ``dip`` = (lo, mid, hi, f(lo), f(mid), f(hi)).
    """
    points = uniform.size + resonances * offsets.size
    block = min(_GRID_ROWS, Omega.size) * points
    grid, f = np.empty(block), np.empty(block)
    lanes, lane_Omega, values = np.empty(block), np.empty(block), np.empty(block)
    near = np.empty(points - uniform.size)
    n = dips = 0
    for first in range(0, Omega.size, _GRID_ROWS):
        size = min(_GRID_ROWS, Omega.size - first) * points
        _grid_residual(G, Omega, uniform, offsets, resonances, lo, hi, c, k_d, omega0, first,
                       grid[:size], lanes, lane_Omega, values, near, f[:size])
        for start in range(0, size, points):
            row = first + start // points
            for j in range(start, start + points - 1):
                if _negative(f[j]) != _negative(f[j + 1]):
                    b_row[n] = row
                    bracket[0][n], bracket[1][n] = grid[j], grid[j + 1]
                    bracket[2][n], bracket[3][n] = f[j], f[j + 1]
                    n += 1
            for j in range(start, start + points - 2):
                one_sign = _negative(f[j]) == _negative(f[j + 1]) == _negative(f[j + 2])
                if one_sign and abs(f[j + 1]) < abs(f[j]) and abs(f[j + 1]) <= abs(f[j + 2]):
                    d_row[dips] = row
                    for k in range(3):
                        dip[k][dips], dip[3 + k][dips] = grid[j + k], f[j + k]
                    dips += 1
    return n, dips


@numba.njit(**_JIT)
def find_roots(G, Omega, uniform, offsets, resonances, lo, hi, c, k_d, omega0):
    """Every root omega at the frequencies Omega: (rows, roots), rows indexing Omega.

    Sign changes of the residual on each frequency's grid are brackets; so are
    both sides of each dip (|residual| lowest at a point between two of the same
    sign) where the golden-section search crosses zero. All brackets are then
    refined together.
    """
    # A frequency has fewer brackets, and fewer dips, than grid points (pages of
    # these arrays that are never written cost nothing).
    most = Omega.size * (uniform.size + resonances * offsets.size)
    b_row, d_row = np.empty(most, dtype=np.int64), np.empty(most, dtype=np.int64)
    bracket = (np.empty(most), np.empty(most), np.empty(most), np.empty(most))
    dip = (np.empty(most), np.empty(most), np.empty(most), np.empty(most), np.empty(most),
           np.empty(most))
    n, dips = _scan_grids(G, Omega, uniform, offsets, resonances, lo, hi, c, k_d, omega0, b_row,
                          bracket, d_row, dip)
    crossed = golden_dips(G, _take(Omega, d_row[:dips]), c, k_d, omega0, dip[0][:dips],
                          dip[1][:dips], dip[2][:dips], dip[3][:dips], dip[4][:dips],
                          dip[5][:dips])
    for q in range(dips):  # a root pair, in [lo, mid] and [mid, hi]
        if crossed[q]:
            for side in range(2):
                b_row[n] = d_row[q]
                bracket[0][n], bracket[1][n] = dip[side][q], dip[side + 1][q]
                bracket[2][n], bracket[3][n] = dip[3 + side][q], dip[4 + side][q]
                n += 1
    roots = illinois(G, _take(Omega, b_row[:n]), c, k_d, omega0, bracket[0][:n],
                     bracket[1][:n], bracket[2][:n], bracket[3][:n])
    return b_row[:n].copy(), roots


@numba.njit(**_JIT)
def nearby_roots(G, Omega, start, distance, c, k_d, omega0, iterations=30):
    """The root of the frequency equation with every b_n up to N+2 reached by secant
    steps from each ``start`` (at frequency Omega[i]), all in step, and whether it
    was found within ``distance`` of it (a lane whose steps leave that window, or
    stall, is not)."""
    n = start.size
    x0, x1 = start.copy(), start + 1e-3 * distance
    f0, f1 = np.empty(n), np.empty(n)
    residual_lanes_next(G, x0, Omega, c, k_d, omega0, f0)  # noqa: F821
    residual_lanes_next(G, x1, Omega, c, k_d, omega0, f1)  # noqa: F821
    found = np.zeros(n, dtype=np.bool_)
    active = np.arange(n)
    x, fx, done = np.empty(n), np.empty(n), np.empty(n, dtype=np.bool_)
    outside = np.empty(n, dtype=np.bool_)
    for _ in range(iterations):
        if active.size == 0:
            break
        for q, i in enumerate(active):
            step = x1[i] - f1[i] * (x1[i] - x0[i]) / (f1[i] - f0[i])
            outside[q] = not np.isfinite(step) or abs(step - start[i]) > distance[i]
            x[q] = x1[i] if outside[q] else step
        W = _take(Omega, active)
        residual_lanes_next(G, x[:active.size], W, c, k_d, omega0, fx)  # noqa: F821
        for q, i in enumerate(active):
            x0[i], f0[i], x1[i], f1[i] = x1[i], f1[i], x[q], fx[q]
            converged = abs(x1[i] - x0[i]) <= 1e-12 * x1[i] or f1[i] == 0
            found[i] = converged and not outside[q]
            done[q] = converged or outside[q]
        active = _still(active, done)
    return x1, found


@numba.njit(**_JIT)
def _clear(coefficients):
    for k in range(coefficients.shape[0]):
        coefficients[k, 0] = coefficients[k, 1] = 0.0


@numba.njit(**_JIT)
def _rotate(real, imag, i, theta, out, sign):
    """out[k] += sign z_k exp(i k theta), z_k = real[k, i] + i imag[k, i]: harmonic k
    of lane i from the frame of u0 (z_0_1 = A0 real) to the phases of the
    excitation (u0 lags it by -theta). Plain loops and real arithmetic: numba
    compiles them in a fraction of the time of complex arithmetic or array methods."""
    for k in range(real.shape[0]):
        cos_k, sin_k = math.cos(k * theta), math.sin(k * theta)
        out[k, 0] += sign * (real[k, i] * cos_k - imag[k, i] * sin_k)
        out[k, 1] += sign * (real[k, i] * sin_k + imag[k, i] * cos_k)


@numba.njit(**_JIT)
def _sample(coefficients, cos_table, sin_table, u):
    """u[j] = sum_k Re(coefficients[k] exp(i k t_j)) at the phases t_j of the tables
    (coefficients[k] = (real part, imaginary part))."""
    for j in range(u.size):
        u[j] = 0.0
    for k in range(coefficients.shape[0]):
        a, b = coefficients[k, 0], coefficients[k, 1]
        if a == 0.0 and b == 0.0:  # harmonics past the order's
            continue
        for j in range(u.size):  # vectorised
            u[j] += a * cos_table[k, j] - b * sin_table[k, j]


@numba.njit(**_JIT)
def _refined(u, j):
    """The extreme at sample j, refined by a parabola through j - 1, j, j + 1 (periodic)."""
    y0, ym, yp = u[j], u[j - 1], u[(j + 1) % u.size]
    curvature = ym - 2 * y0 + yp
    step = (ym - yp) / (2 * curvature) if curvature != 0 else 0.0
    return y0 - (ym - yp) * step / 4


@numba.njit(**_JIT)
def waveform_extrema(real, imag, theta, cos_table, sin_table, u_max, u_min):
    """Largest and least u over a period at every lane: u sampled at the phases of
    the tables (from the harmonics real + i imag [k, lane] and the lag theta), then
    refined (the first sample of a tie, as np.argmax)."""
    u = np.empty(cos_table.shape[1])
    coefficients = np.empty((real.shape[0], 2))
    for i in range(theta.size):
        _clear(coefficients)
        _rotate(real, imag, i, theta[i], coefficients, 1.0)
        _sample(coefficients, cos_table, sin_table, u)
        top = bottom = 0
        for j in range(1, u.size):
            if u[j] > u[top]:
                top = j
            if u[j] < u[bottom]:
                bottom = j
        u_max[i], u_min[i] = _refined(u, top), _refined(u, bottom)


@numba.njit(**_JIT)
def change_peak_to_peak(real, imag, theta, real_base, imag_base, theta_base, cos_table,
                        sin_table, out):
    """max - min over a period of u - u_base at every lane, sampled at the phases of
    the tables (u from the harmonics real + i imag [k, lane] and the lag theta,
    u_base from the others): the difference of the harmonics, sampled once."""
    u = np.empty(cos_table.shape[1])
    coefficients = np.empty((max(real.shape[0], real_base.shape[0]), 2))
    for i in range(theta.size):
        _clear(coefficients)
        _rotate(real, imag, i, theta[i], coefficients, 1.0)
        _rotate(real_base, imag_base, i, theta_base[i], coefficients, -1.0)
        _sample(coefficients, cos_table, sin_table, u)
        top = bottom = u[0]
        for j in range(1, u.size):
            top, bottom = max(top, u[j]), min(bottom, u[j])
        out[i] = top - bottom
