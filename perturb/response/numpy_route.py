"""The analytic response in numpy: the route of an order whose compiled kernels are not built.

The residual of Eq. 2.7 on the whole grid of omega at once (the lambdified
``CompiledSeries``), sign changes refined by the Illinois method and dips
followed by a golden-section search, vectorised over lanes, and the waveforms
sampled in numpy. It was the only route before the frequency equation was
compiled (``codegen.py``, ``template.py``), and it stays:
the compiled kernels of an order take 10-20 s to build the first time, while this
route answers a first call in under a second. ``frequency_response(engine="auto")``
takes the compiled route where its kernels are built, and this one otherwise;
the two give the same branches, roots (within 1e-13) and validity flags
(``tests/test_perturb_response.py``).
"""

from __future__ import annotations

import numpy as np

from ..series.formulas import SeriesFormulas, compile_series
from ..series.truncation import (
    PAPER_TRUNCATION,
    Truncation,
    measures_model_distance,
    truncation_for,
)
from .frequency import RESONANCE_OFFSETS, match_distance

__all__ = ["solve_chunk", "harmonics_in_drive_frame", "sample_waveform", "refined_at"]

_CHUNK = 4096


def _residual(formulas: SeriesFormulas, values, G, omega, Omega):
    """omega^2 - omega0^2 - sum b_n, with A0 = G H_1(omega) (Eq. 2.7, 2.8)."""
    out = np.empty(np.broadcast(G, omega, Omega).shape)
    G, omega, Omega = (np.broadcast_to(a, out.shape).ravel() for a in (G, omega, Omega))
    flat = out.reshape(-1)
    for start in range(0, flat.size, _CHUNK):
        part = slice(start, start + _CHUNK)
        w, W = omega[part], Omega[part]
        a0 = G[part] / np.hypot(w**2 - W**2, 2 * values.c_per_s * W)
        shift = formulas.frequency_shift(a0, w, W, *series_arguments(formulas, values))
        flat[part] = w**2 - values.omega0_rad_s**2 - shift
    return out


def series_arguments(formulas, values) -> tuple[float, ...]:
    """c and the equation's coefficients that ``formulas`` take (h first)."""
    return (values.c_per_s, *values.coefficients(formulas.coefficients))


def _omega_grid(Omega, order, values, omega_range, points):
    """Candidate omega per frequency: uniform, plus dense around each k Omega."""
    lo, hi = omega_range[0] * values.omega0_rad_s, omega_range[1] * values.omega0_rad_s
    uniform = np.broadcast_to(np.linspace(lo, hi, points), (Omega.size, points))
    k = np.arange(1, order + 2)
    offsets = values.c_per_s * RESONANCE_OFFSETS[None, None, :]
    near = (k[None, :, None] * Omega[:, None, None]) + offsets
    grid = np.concatenate([uniform, near.reshape(Omega.size, -1)], axis=1)
    return np.sort(np.clip(grid, lo, hi), axis=1)


def _dip_brackets(grid, f):
    """(row, lo, mid, hi) where |residual| dips between neighbours of the same sign.

    Two roots closer than the grid spacing (both sides of a fold) leave no sign
    change on the grid, only a local minimum of |residual| at the middle of
    three same-signed neighbours.
    """
    s, a = np.signbit(f), np.abs(f)
    dip = (s[:, :-2] == s[:, 1:-1]) & (s[:, 1:-1] == s[:, 2:])
    dip &= (a[:, 1:-1] < a[:, :-2]) & (a[:, 1:-1] <= a[:, 2:])
    rows, cols = np.nonzero(dip)
    return rows, cols, cols + 1, cols + 2


_GOLDEN = (3 - np.sqrt(5)) / 2


def _cross_dips(formulas, values, G, Omega, lo, mid, hi, g_lo, g_mid, g_hi, iterations=48):
    """Golden-section search of each dip towards zero, all at once.

    ``g`` is the residual times the sign of the three grid values, so it is
    positive at ``lo``, ``mid`` and ``hi`` and ``mid`` is lowest. The search
    narrows the bracket around the minimum of g until g < 0 somewhere (a
    crossing: a root pair lies in [lo, x] and [x, hi]) or the bracket is
    below 1e-9 omega (no root pair wider than that there). Returns
    (lane, x, g(x), lo, g(lo), hi, g(hi)) for the crossings.
    """
    sign = np.where(g_mid < 0, -1.0, 1.0)
    lo, mid, hi = (np.array(a, dtype=float) for a in (lo, mid, hi))
    g_lo, g_mid, g_hi = (np.array(a, dtype=float) * sign for a in (g_lo, g_mid, g_hi))
    active = np.ones(lo.shape, dtype=bool)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        # Probe the larger side of mid at the golden fraction.
        right = (hi[idx] - mid[idx]) > (mid[idx] - lo[idx])
        x = np.where(right, mid[idx] + _GOLDEN * (hi[idx] - mid[idx]),
                     mid[idx] - _GOLDEN * (mid[idx] - lo[idx]))
        gx = sign[idx] * _residual(formulas, values, G[idx], x, Omega[idx])
        better = gx < g_mid[idx]
        # A better probe becomes mid, the old mid an end; otherwise the probe is an end.
        new_lo = np.where(better, np.where(right, mid[idx], lo[idx]),
                          np.where(right, lo[idx], x))
        new_hi = np.where(better, np.where(right, hi[idx], mid[idx]),
                          np.where(right, x, hi[idx]))
        new_glo = np.where(better, np.where(right, g_mid[idx], g_lo[idx]),
                           np.where(right, g_lo[idx], gx))
        new_ghi = np.where(better, np.where(right, g_hi[idx], g_mid[idx]),
                           np.where(right, gx, g_hi[idx]))
        lo[idx], hi[idx], g_lo[idx], g_hi[idx] = new_lo, new_hi, new_glo, new_ghi
        mid[idx] = np.where(better, x, mid[idx])
        g_mid[idx] = np.where(better, gx, g_mid[idx])
        crossed = gx < 0
        active[idx[crossed | (hi[idx] - lo[idx] <= 1e-9 * hi[idx])]] = False
    crossing = np.flatnonzero(g_mid < 0)
    return (crossing, mid[crossing], sign[crossing] * g_mid[crossing], lo[crossing],
            sign[crossing] * g_lo[crossing], hi[crossing], sign[crossing] * g_hi[crossing])


def _illinois(formulas, values, G, Omega, lo, hi, f_lo, f_hi, iterations=80):
    """Refine brackets [lo, hi] with a sign change of the residual, all at once."""
    lo, hi, f_lo, f_hi = (np.array(a, dtype=float) for a in (lo, hi, f_lo, f_hi))
    side = np.zeros(lo.shape, dtype=int)
    active = np.ones(lo.shape, dtype=bool)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        x = (lo[idx] * f_hi[idx] - hi[idx] * f_lo[idx]) / (f_hi[idx] - f_lo[idx])
        fx = _residual(formulas, values, G[idx], x, Omega[idx])
        left = np.sign(fx) == np.sign(f_lo[idx])
        # Replace the end with the same sign; halve the other end's value when the
        # same end is kept twice in a row (Illinois), so that both ends move.
        keep_hi = left
        lo[idx[keep_hi]], f_lo[idx[keep_hi]] = x[keep_hi], fx[keep_hi]
        hi[idx[~keep_hi]], f_hi[idx[~keep_hi]] = x[~keep_hi], fx[~keep_hi]
        f_hi[idx[keep_hi & (side[idx] == -1)]] /= 2
        f_lo[idx[~keep_hi & (side[idx] == 1)]] /= 2
        side[idx] = np.where(keep_hi, -1, 1)
        done = (np.abs(hi[idx] - lo[idx]) <= 1e-13 * hi[idx]) | (fx == 0)
        active[idx[done]] = False
    return np.where(np.abs(f_lo) < np.abs(f_hi), lo, hi)


def harmonics_in_drive_frame(formulas, values, a0, omega, Omega) -> np.ndarray:
    """H_k with u = sum_k Re(H_k exp(i k Omega t)), per lane (lanes, K + 1).

    Phases are those of the excitation P_a cos(Omega t) (Eq. 2.2), u0 = A0
    cos(Omega t + theta_1(omega)), so that waveforms of different omega (orders)
    can be subtracted, and the simulator's orbit (which starts at the drive's
    phase 0) can be started on them.
    """
    amplitudes = formulas.amplitudes(a0, omega, Omega, *series_arguments(formulas, values))
    per_harmonic = formulas.harmonics([np.broadcast_to(z, a0.shape) for z in amplitudes])
    theta_1 = -np.angle(omega**2 - Omega**2 + 2j * values.c_per_s * Omega)
    k = np.arange(per_harmonic.shape[-1])
    return per_harmonic * np.exp(1j * np.multiply.outer(theta_1, k))


def _waveform(formulas, values, a0, omega, Omega, samples):
    """The reconstructed u at ``samples`` phases Omega t over a period, per lane
    (phases of the excitation: ``harmonics_in_drive_frame``)."""
    return sample_waveform(harmonics_in_drive_frame(formulas, values, a0, omega, Omega),
                           samples)


def sample_waveform(per_harmonic: np.ndarray, samples: int) -> np.ndarray:
    """u = sum_k Re(H_k exp(i k theta)) at ``samples`` phases theta of a period, per lane."""
    k = np.arange(per_harmonic.shape[-1])
    # Re(z exp(i k theta)) = Re z cos(k theta) - Im z sin(k theta): two real products.
    k_theta = np.outer(k, 2 * np.pi * np.arange(samples) / samples)
    return per_harmonic.real @ np.cos(k_theta) - per_harmonic.imag @ np.sin(k_theta)


def _extrema(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """max and min of sampled waveforms u (lanes, samples) over a period."""
    return _refined_extreme(u, np.max), _refined_extreme(u, np.min)


def _refined_extreme(u: np.ndarray, which) -> np.ndarray:
    """The extreme of periodic samples, refined by a parabola through three samples."""
    j = np.argmax(u, axis=1) if which is np.max else np.argmin(u, axis=1)
    return refined_at(u, np.arange(u.shape[0]), j)


def refined_at(u: np.ndarray, rows: np.ndarray, j: np.ndarray) -> np.ndarray:
    """The extreme of periodic samples u (lanes, samples) near sample ``j`` of lane
    ``rows``: the vertex of the parabola through samples j - 1, j and j + 1."""
    y0, ym, yp = u[rows, j], u[rows, j - 1], u[rows, (j + 1) % u.shape[1]]
    curvature = ym - 2 * y0 + yp
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(curvature != 0, (ym - yp) / (2 * curvature), 0.0)
    return y0 - (ym - yp) * shift / 4


def _nearby_root(formulas, values, G, Omega, start, distance, iterations=30):
    """The root of ``formulas``' frequency equation reached by secant steps from ``start``.

    Returns the root and whether it converged within ``distance`` of ``start``
    (a lane whose steps leave that window, or stall, has no matching root).
    """
    x0, x1 = np.array(start, dtype=float), start + 1e-3 * distance
    f0 = _residual(formulas, values, G, x0, Omega)
    f1 = _residual(formulas, values, G, x1, Omega)
    found = np.zeros(x0.shape, dtype=bool)
    active = np.ones(x0.shape, dtype=bool)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            x = x1[idx] - f1[idx] * (x1[idx] - x0[idx]) / (f1[idx] - f0[idx])
        out = ~np.isfinite(x) | (np.abs(x - start[idx]) > distance[idx])
        x = np.where(out, x1[idx], x)
        x0[idx], f0[idx] = x1[idx], f1[idx]
        x1[idx] = x
        f1[idx] = _residual(formulas, values, G[idx], x, Omega[idx])
        done = (np.abs(x1[idx] - x0[idx]) <= 1e-12 * x1[idx]) | (f1[idx] == 0)
        found[idx[done & ~out]] = True
        active[idx[done | out]] = False
    return x1, found


def truncation_error(order, values, G, Omega, rows, roots, base, app,
                     truncation: Truncation = PAPER_TRUNCATION, compiled: bool = True
                     ) -> np.ndarray:
    """An a-posteriori estimate of the relative error of the order-N response.

    max over k = 1, 2 of pp(u_(N+k) - u_N) / App_N, where u_M is the
    reconstructed u(t) of the order-M series (in the time frame of the
    excitation) on its root nearest to the order-N root (``_nearby_root``;
    NaN where no root of order N+k lies within ``match_distance``), and pp
    is max - min over a period; ``base`` is u_N sampled over a period (lanes,
    samples), as ``_waveform`` gives it. It bounds |App_(N+k) - App_N| / App_N. The
    term b_(N+1) left out of the frequency equation is what the resonance
    amplifies; at even N it is zero (b_n = 0 for odd n), so order N+1 has the
    frequency equation of order N and only order N+2 sees it, hence two
    orders. Orders with the same frequency equation (b_n = 0 for odd n) share
    their roots. The whole waveform is compared, not only App: near the 1/2
    superharmonic peak at 0.15 Q (745 Hz) App changes by < 0.2 % from order 2
    to 11 while it is 1.4 % off RK4 of Eq. 2.6, and the waveform still moves.
    """
    Omega_r, G_r = Omega[rows], np.full(rows.size, G)
    distance = match_distance(rows, roots, values.c_per_s)
    solved = {compile_series(order, truncation, compiled=compiled).b_orders:
              (roots, np.ones(roots.size, dtype=bool))}
    error = np.zeros(roots.size)
    for k in (1, 2):
        formulas = compile_series(order + k, truncation, compiled=compiled)
        if formulas.b_orders not in solved:
            solved[formulas.b_orders] = _nearby_root(
                formulas, values, G_r, Omega_r, roots, distance
            )
        omega, matched = solved[formulas.b_orders]
        step = _waveform_distance(formulas, values, G, Omega_r, omega, base, app)
        # np.maximum keeps a NaN: a lane unmatched at either order has no estimate.
        error = np.maximum(error, np.where(matched & np.isfinite(step), step, np.nan))
    return error


def _waveform_distance(formulas, values, G, Omega_r, omega, base, app) -> np.ndarray:
    """pp(u - base) / app, u the waveform of ``formulas`` at the roots ``omega``."""
    a0 = G / np.hypot(omega**2 - Omega_r**2, 2 * values.c_per_s * Omega_r)
    change = _waveform(formulas, values, a0, omega, Omega_r, base.shape[1]) - base
    with np.errstate(divide="ignore", invalid="ignore"):
        return (change.max(axis=1) - change.min(axis=1)) / app


def model_distance(order, values, G, Omega, rows, roots, base, app,
                   compiled: bool = True) -> np.ndarray:
    """How far the order-N series of Eq. 2.6 is from the contact's own equation:
    pp(u_C - u_N) / App_N, u_C the consistent series of order N+2 on its root nearest to
    the order-N root (NaN where none lies within ``match_distance``), ``base`` u_N
    sampled over a period. Zero on the paper's own contact (m2 = 2, l = 1), whose flags
    are the paper's, and where the consistent series is Eq. 2.6's (m2 = 2, l = 0).

    Eq. 2.6 leaves out k_3 u^3 (m2 != 2) and d_1 u u' (l != 0): its own next orders do not
    see what they change, which this does."""
    if not measures_model_distance(order, values.parameters):
        return np.zeros(roots.size)
    truncation = truncation_for("consistent", values.parameters)
    formulas = compile_series(order + 2, truncation, compiled=compiled)
    Omega_r, G_r = Omega[rows], np.full(rows.size, G)
    distance = match_distance(rows, roots, values.c_per_s)
    omega, matched = _nearby_root(formulas, values, G_r, Omega_r, roots, distance)
    step = _waveform_distance(formulas, values, G, Omega_r, omega, base, app)
    return np.where(matched & np.isfinite(step), step, np.nan)


def solve_chunk(values, G, Omega, order, omega_range, grid_points, samples, tolerance,
                offset: int, truncation: Truncation = PAPER_TRUNCATION,
                compiled: bool = False) -> tuple[np.ndarray, ...]:
    """Every root of the frequencies ``Omega``, with App, extrema, validity and error;
    rows count from ``offset`` (as ``frequency._solve_chunk``, in numpy). The error of
    the paper's truncation includes its distance to the contact's equation
    (``model_distance``). ``compiled``: a series other than Eq. 2.6's by its numba
    kernel (``KernelSeries``), not in numpy."""
    formulas = compile_series(order, truncation, compiled=compiled)
    rows, roots = _roots(formulas, values, G, Omega, order, omega_range, grid_points)
    a0 = G / np.hypot(roots**2 - Omega[rows] ** 2, 2 * values.c_per_s * Omega[rows])
    u = _waveform(formulas, values, a0, roots, Omega[rows], samples)  # order N, once
    u_max, u_min = _extrema(u)
    error = truncation_error(order, values, G, Omega, rows, roots, u, u_max - u_min,
                             truncation, compiled)
    if truncation.name == "paper":
        distance = model_distance(order, values, G, Omega, rows, roots, u, u_max - u_min,
                                  compiled)
        error = np.maximum(error, distance)
    valid = (values.y0_m + u_min > 0) & (error < tolerance)
    return rows + offset, roots, a0, u_min, u_max, valid, error




def _roots(formulas, values, G, Omega, order, omega_range, grid_points):
    """Every root omega of the frequency equation: (frequency index, omega) per root."""
    grid = _omega_grid(Omega, order, values, omega_range, grid_points)
    f = _residual(formulas, values, G, grid, Omega[:, None])
    rows, cols = np.nonzero(np.signbit(f[:, :-1]) != np.signbit(f[:, 1:]))
    brackets = [(rows, grid[rows, cols], grid[rows, cols + 1], f[rows, cols], f[rows, cols + 1])]
    d_rows, lo, mid, hi = _dip_brackets(grid, f)
    lane, x, fx, a, fa, b, fb = _cross_dips(
        formulas, values, np.full(d_rows.size, G), Omega[d_rows], grid[d_rows, lo],
        grid[d_rows, mid], grid[d_rows, hi], f[d_rows, lo], f[d_rows, mid], f[d_rows, hi],
    )
    brackets += [(d_rows[lane], a, x, fa, fx), (d_rows[lane], x, b, fx, fb)]
    rows, lo, hi, f_lo, f_hi = (np.concatenate(parts) for parts in zip(*brackets))
    roots = _illinois(formulas, values, np.full(rows.size, G), Omega[rows], lo, hi, f_lo, f_hi)
    return rows, roots
