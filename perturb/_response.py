"""The analytic frequency response of Eq. 2.6 from the compiled series.

For a force amplitude P_a and an excitation frequency f_e (Omega = 2 pi f_e),
a response of the series is a non-linear natural frequency omega with

    omega^2 = omega0^2 + sum_n b_n(A0, omega, Omega),  A0 = G H_1(omega)   (Eq. 2.7, 2.8)

The bent peaks have several such omega at one frequency: every root is found,
by sampling the left minus the right side on a grid of omega (dense where a
transfer 1/(omega^2 - k^2 Omega^2 + 2 i k c Omega) resonates, k = 1..N+1, which
is where the superharmonic peaks at f_n0/k live) and refining each sign change
by the Illinois method, all frequencies at once. Two roots closer than the grid
spacing (both sides of a fold) change no sign on the grid: where |residual|
has a local minimum between two neighbours of the same sign, a golden-section
search follows the residual towards zero and, if it crosses, the two roots on
either side are refined too. The peak-to-peak amplitude
App is max - min of the reconstructed u(t) = sum_n u_n(t).

Each point has a validity flag: false where the response would lose contact
(y0 + min u <= 0, Eq. 2.1) or where the next two orders move it: an
a-posteriori error estimate (``truncation_error``), the larger peak-to-peak
change of u(t) from order N to the orders N+1 and N+2 on their nearest root,
must be below ``tolerance`` (1 %) of App; a point with no root of those orders
nearby (near a fold that moves with the order) has no estimate (NaN) and is not
valid. Validity is about the truncation error and contact, not stability: the
middle root of a bent peak can be valid and is an unstable orbit.

Examples
--------
>>> import numpy as np
>>> res = frequency_response(np.array([800.0, 1420.0]), pa_frac=0.05, order=6)
>>> res.roots_per_frequency().tolist()  # 1420 Hz is on the bent primary peak
[1, 3]
>>> [round(float(b.app_m[-1]) * 1e9, 1) for b in res.branches]  # App [nm], 1420 Hz
[168.0, 206.2, 302.3]
"""

from __future__ import annotations

import time

import numpy as np
import numpy.typing as npt

from common import Result, check_int, check_pair, check_positive, lane_array, result

from ._compiled import CompiledSeries, compile_series
from ._effects import EQ_2_6
from ._eq26 import Eq26Numbers, eq26_numbers
from ._model import ContactModel
from ._parameters import PAPER, ContactParameters
from ._series_symbols import check_order

__all__ = ["frequency_response", "Response", "Branch"]

#: Offsets of the extra grid points around each resonance k Omega, in units of c.
_RESONANCE_OFFSETS = np.array([-12.0, -6.0, -3.0, -1.5, -0.75, 0.0, 0.75, 1.5, 3.0, 6.0, 12.0])
_CHUNK = 4096
#: Frequencies solved together: the residual grid (about 125 omega per frequency) and
#: the waveforms (``samples`` per root) of a chunk take some 30 MB at the defaults.
FREQUENCIES_PER_CHUNK = 2048
#: The most frequencies one call takes: the result alone holds about 70 bytes per
#: root and branch (some 200 MB at this limit); a larger band is split by the caller.
MAX_FREQUENCIES = 1_000_000


@result
class Branch(Result):
    """One root of the frequency equation per frequency where it exists.

    Branch j holds, at each frequency with more than j roots, the root with the
    (j+1)-th largest omega. Every field is an array over those frequencies.

    Attributes
    ----------
    frequency_hz : ndarray
        Excitation frequencies f_e [Hz] where the branch has a root.
    app_m : ndarray
        Peak-to-peak amplitude App = max u - min u of the reconstructed u(t) [m].
    a0_m : ndarray
        Amplitude A0 = G H_1(omega) of the fundamental u0 [m].
    omega_rad_s : ndarray
        The root: the non-linear natural frequency omega [rad/s] (Eq. 2.7).
    u_min_m, u_max_m : ndarray
        Least and largest u = y - y0 over a period [m].
    valid : ndarray of bool
        ``error_estimate < tolerance`` and contact kept (y0 + min u > 0). It says
        the series is accurate there, not that the orbit is stable: a valid root
        on the middle branch of a bent peak is an unstable orbit.
    error_estimate : ndarray
        Estimated relative error of App from the next two orders
        (``truncation_error``); NaN where no root of those orders matches.
    """

    frequency_hz: np.ndarray
    app_m: np.ndarray
    a0_m: np.ndarray
    omega_rad_s: np.ndarray
    u_min_m: np.ndarray
    u_max_m: np.ndarray
    valid: np.ndarray
    error_estimate: np.ndarray

    @classmethod
    def from_dict(cls, data: dict) -> Branch:
        branch = super().from_dict(data)
        branch.valid = np.asarray(branch.valid, dtype=bool)
        return branch

    def summary(self) -> str:
        return f"Branch: {self.describe()}"

    def describe(self) -> str:
        """Points, valid points, and where the largest valid App is, in words."""
        counts = f"{self.frequency_hz.size} points, {int(self.valid.sum())} valid"
        if not self.valid.any():
            return f"{counts}, no valid point"
        best = int(np.argmax(np.where(self.valid, self.app_m, -np.inf)))
        return (f"{counts}, largest valid App {self.app_m[best]:.4g} m at "
                f"{self.frequency_hz[best]:.6g} Hz")


@result
class Response(Result):
    """The analytic frequency response of the order-N series at one P_a.

    Attributes
    ----------
    order : int
        Order N of the series.
    pa_frac : float
        Force amplitude P_a / Q.
    frequency_hz : ndarray
        Every excitation frequency asked for [Hz] (a frequency with no root in
        ``omega_range`` is in no branch).
    branches : list of Branch
        Branch j: the root with the (j+1)-th largest omega, where there is one.
    model : dict
        The model whose equation the series solves: Eq. 2.6, i.e. the
        parameters with the effects ``EQ_2_6`` (``ContactModel.as_dict()``).
    settings : dict
        ``omega_range``, ``grid_points``, ``samples``, ``tolerance``.
    elapsed_s : float
        Wall time of the computation [s].
    """

    order: int
    pa_frac: float
    frequency_hz: np.ndarray
    branches: list[Branch]
    model: dict
    settings: dict
    elapsed_s: float

    def branch(self, j: int) -> Branch:
        """Branch ``j`` (the root with the (j+1)-th largest omega); a KeyError lists them."""
        if isinstance(j, (int, np.integer)) and 0 <= j < len(self.branches):
            return self.branches[j]
        raise KeyError(f"no branch {j!r}; available: {list(range(len(self.branches)))}")

    def roots_per_frequency(self) -> np.ndarray:
        """How many roots (responses) each frequency of ``frequency_hz`` has."""
        counts = np.zeros(self.frequency_hz.shape, dtype=int)
        for branch in self.branches:
            counts[np.searchsorted(self.frequency_hz, branch.frequency_hz)] += 1
        return counts

    def summary(self) -> str:
        n_valid = sum(int(b.valid.sum()) for b in self.branches)
        n_points = sum(b.valid.size for b in self.branches)
        return (
            f"Response: order {self.order}, pa_frac {self.pa_frac:g}, "
            f"{self.frequency_hz.size} frequencies, {len(self.branches)} branches, "
            f"{n_valid}/{n_points} points valid, {self.elapsed_s:.2f} s"
        )

    def table(self) -> str:
        return "\n".join(
            f"  branch {j}: {branch.describe()}"
            for j, branch in enumerate(self.branches)
        )


def _residual(formulas: CompiledSeries, values: Eq26Numbers, G, omega, Omega):
    """omega^2 - omega0^2 - sum b_n, with A0 = G H_1(omega) (Eq. 2.7, 2.8)."""
    out = np.empty(np.broadcast(G, omega, Omega).shape)
    G, omega, Omega = (np.broadcast_to(a, out.shape).ravel() for a in (G, omega, Omega))
    flat = out.reshape(-1)
    for start in range(0, flat.size, _CHUNK):
        part = slice(start, start + _CHUNK)
        w, W = omega[part], Omega[part]
        a0 = G[part] / np.hypot(w**2 - W**2, 2 * values.c_per_s * W)
        shift = formulas.frequency_shift(a0, w, W, values.c_per_s, values.h_per_m_s2)
        flat[part] = w**2 - values.omega0_rad_s**2 - shift
    return out


def _omega_grid(Omega, order, values, omega_range, points):
    """Candidate omega per frequency: uniform, plus dense around each k Omega."""
    lo, hi = omega_range[0] * values.omega0_rad_s, omega_range[1] * values.omega0_rad_s
    uniform = np.broadcast_to(np.linspace(lo, hi, points), (Omega.size, points))
    k = np.arange(1, order + 2)
    offsets = values.c_per_s * _RESONANCE_OFFSETS[None, None, :]
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


def _waveform(formulas, values, a0, omega, Omega, samples):
    """The reconstructed u at ``samples`` phases Omega t over a period, per lane.

    Phases are those of the excitation, u0 = A0 cos(Omega t + theta_1(omega)),
    so that waveforms of different omega (orders) can be subtracted.
    """
    amplitudes = formulas.amplitudes(a0, omega, Omega, values.c_per_s, values.h_per_m_s2)
    per_harmonic = formulas.harmonics([np.broadcast_to(z, a0.shape) for z in amplitudes])
    theta_1 = -np.angle(omega**2 - Omega**2 + 2j * values.c_per_s * Omega)
    k = np.arange(per_harmonic.shape[-1])
    per_harmonic *= np.exp(1j * np.multiply.outer(theta_1, k))
    # Re(z exp(i k theta)) = Re z cos(k theta) - Im z sin(k theta): two real products.
    k_theta = np.outer(k, 2 * np.pi * np.arange(samples) / samples)
    return per_harmonic.real @ np.cos(k_theta) - per_harmonic.imag @ np.sin(k_theta)


def _extrema(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """max and min of sampled waveforms u (lanes, samples) over a period."""
    return _refined_extreme(u, np.max), _refined_extreme(u, np.min)


def _refined_extreme(u: np.ndarray, which) -> np.ndarray:
    """The extreme of periodic samples, refined by a parabola through three samples."""
    j = np.argmax(u, axis=1) if which is np.max else np.argmin(u, axis=1)
    rows = np.arange(u.shape[0])
    y0, ym, yp = u[rows, j], u[rows, j - 1], u[rows, (j + 1) % u.shape[1]]
    curvature = ym - 2 * y0 + yp
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(curvature != 0, (ym - yp) / (2 * curvature), 0.0)
    return y0 - (ym - yp) * shift / 4


def _match_distance(rows: np.ndarray, roots: np.ndarray, c: float) -> np.ndarray:
    """How far a root of the next orders may lie from an order-N root and match it.

    At most c (the half-width of the linear resonance, rad/s) and less than
    half the gap to the next order-N root of the same frequency, so that a
    matched root is nearer to its own order-N root than to any other.
    """
    order = np.lexsort((roots, rows))
    r, w = rows[order], roots[order]
    gap = np.full(w.size + 1, np.inf)
    same = r[1:] == r[:-1]
    gap[1:-1] = np.where(same, np.diff(w), np.inf)
    distance = np.empty(w.size)
    distance[order] = np.minimum(c, np.minimum(gap[:-1], gap[1:]) / 2)
    return distance


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


def truncation_error(order, values, G, Omega, rows, roots, base, app) -> np.ndarray:
    """An a-posteriori estimate of the relative error of the order-N response.

    max over k = 1, 2 of pp(u_(N+k) - u_N) / App_N, where u_M is the
    reconstructed u(t) of the order-M series (in the time frame of the
    excitation) on its root nearest to the order-N root (``_nearby_root``;
    NaN where no root of order N+k lies within ``_match_distance``), and pp
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
    distance = _match_distance(rows, roots, values.c_per_s)
    solved = {compile_series(order).b_orders: (roots, np.ones(roots.size, dtype=bool))}
    error = np.zeros(roots.size)
    samples = base.shape[1]
    for k in (1, 2):
        formulas = compile_series(order + k)
        if formulas.b_orders not in solved:
            solved[formulas.b_orders] = _nearby_root(
                formulas, values, G_r, Omega_r, roots, distance
            )
        omega, matched = solved[formulas.b_orders]
        a0 = G / np.hypot(omega**2 - Omega_r**2, 2 * values.c_per_s * Omega_r)
        change = _waveform(formulas, values, a0, omega, Omega_r, samples) - base
        with np.errstate(divide="ignore", invalid="ignore"):
            step = (change.max(axis=1) - change.min(axis=1)) / app
        # np.maximum keeps a NaN: a lane unmatched at either order has no estimate.
        error = np.maximum(error, np.where(matched & np.isfinite(step), step, np.nan))
    return error


def _check_frequencies(frequency_hz) -> np.ndarray:
    freq = lane_array("frequency_hz", frequency_hz, positive=True)
    if freq.size > MAX_FREQUENCIES:
        raise ValueError(
            f"`frequency_hz` has {freq.size} points, more than the limit of {MAX_FREQUENCIES}: "
            "the result alone would take some 200 bytes per point; split the band.")
    step = np.diff(freq)
    if np.any(step <= 0):
        i = int(np.argmax(step <= 0))
        raise ValueError(f"`frequency_hz` must be strictly increasing, got {freq[i]!r} then "
                         f"{freq[i + 1]!r} at index {i + 1}.")
    return freq


def frequency_response(
    frequency_hz: npt.ArrayLike,
    pa_frac: float,
    order: int = 6,
    *,
    parameters: ContactParameters = PAPER,
    omega_range: tuple[float, float] = (0.6, 1.2),
    grid_points: int = 48,
    samples: int = 256,
    tolerance: float = 0.01,
) -> Response:
    """Every response of the order-N series of Eq. 2.6 at each frequency.

    Parameters
    ----------
    frequency_hz : array_like, shape (m,)
        Excitation frequencies f_e [Hz], > 0 and strictly increasing.
    pa_frac : float
        Force amplitude P_a as a fraction of the weight Q (>= 0; at 0 the one
        response is rest: App = 0, omega = omega0, valid).
    order : int
        Order N of the series (>= 0).
    parameters : ContactParameters
        The physical parameters (the paper's by default).
    omega_range : (float, float)
        Where to look for the non-linear natural frequency omega, in units of
        omega0 (0 < lo < hi).
    grid_points : int
        Uniform grid points in ``omega_range``, >= 2 (more points are added
        around every k Omega, k = 1..N+1).
    samples : int
        Samples per period of the reconstructed u(t) for its extrema, >= 3.
    tolerance : float
        A point is valid only if its estimated relative error is below
        ``tolerance``: the peak-to-peak change of u(t) when orders N+1 and
        N+2 are added (each on its root nearest to this one, within the
        linear half-width c and half the gap to the next root), divided by
        App (``truncation_error``). It bounds the change of App; and the
        response must keep contact (y0 + min u > 0, Eq. 2.1).

    Returns
    -------
    Response
        Branches with f_e, App, A0, omega, min and max of u, the error
        estimate and validity. A frequency where no omega in ``omega_range``
        solves the equation (the truncated series has no bounded response
        there) has no point.

    Notes
    -----
    ``valid`` is about the series, not about stability: a valid root is a
    periodic solution of Eq. 2.6 that the series gives to within ``tolerance``,
    and it may be an unstable orbit. On a bent peak the roots alternate stable,
    unstable, stable by decreasing omega (branches 0, 1, 2); the middle one is
    the unstable orbit between the two attractors, which no time marching
    settles on.
    """
    start = time.perf_counter()
    freq = _check_frequencies(frequency_hz)
    pa_frac = check_positive("pa_frac", pa_frac, allow_zero=True)
    order = check_order(order)
    if not isinstance(parameters, ContactParameters):
        raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
    omega_range = check_pair("omega_range", omega_range, positive=True)
    grid_points = check_int("grid_points", grid_points, minimum=2)
    samples = check_int("samples", samples, minimum=3)
    tolerance = check_positive("tolerance", tolerance)
    values = eq26_numbers(parameters)
    formulas = compile_series(order)
    Omega = 2 * np.pi * freq
    G = pa_frac * values.Q_n * values.G_per_P_a
    if G == 0:
        branches = [_at_rest(freq, values.omega0_rad_s)]
    else:
        # Frequencies are independent: solved a chunk at a time, memory stays bounded.
        parts = [_solve_chunk(formulas, values, G, Omega[chunk], order, omega_range,
                              grid_points, samples, tolerance, chunk.start)
                 for chunk in _chunks(freq.size, FREQUENCIES_PER_CHUNK)]
        rows, roots, a0, u_min, u_max, valid, error = (np.concatenate(column)
                                                       for column in zip(*parts))
        branches = _branches(freq, rows, roots, a0, u_min, u_max, valid, error)
    return Response(
        order=order,
        pa_frac=pa_frac,
        frequency_hz=freq,
        branches=branches,
        model=_eq26_model(parameters),
        settings={"omega_range": list(omega_range), "grid_points": grid_points,
                  "samples": samples, "tolerance": tolerance},
        elapsed_s=time.perf_counter() - start,
    )


def _chunks(size: int, chunk: int) -> list[slice]:
    return [slice(start, min(start + chunk, size)) for start in range(0, size, chunk)]


def _solve_chunk(formulas, values, G, Omega, order, omega_range, grid_points, samples,
                 tolerance, offset: int) -> tuple[np.ndarray, ...]:
    """Every root of the frequencies ``Omega``, with App, extrema, validity and error;
    rows count from ``offset``."""
    rows, roots = _roots(formulas, values, G, Omega, order, omega_range, grid_points)
    a0 = G / np.hypot(roots**2 - Omega[rows] ** 2, 2 * values.c_per_s * Omega[rows])
    u = _waveform(formulas, values, a0, roots, Omega[rows], samples)  # order N, once
    u_max, u_min = _extrema(u)
    error = truncation_error(order, values, G, Omega, rows, roots, u, u_max - u_min)
    valid = (values.y0_m + u_min > 0) & (error < tolerance)
    return rows + offset, roots, a0, u_min, u_max, valid, error


def _eq26_model(parameters: ContactParameters) -> dict:
    """The model whose equation the series solves (Eq. 2.6), as data."""
    return ContactModel(parameters, EQ_2_6).as_dict()


def _at_rest(freq: np.ndarray, omega0: float) -> Branch:
    """P_a = 0: the one response is rest (u = 0, omega = omega0), exact at every order.

    b_n is written with a division by A0 (Eq. 2.10), so the frequency equation
    cannot be evaluated there; it is not needed.
    """
    def zero():
        return np.zeros(freq.size)

    return Branch(frequency_hz=freq.copy(), app_m=zero(), a0_m=zero(),
                  omega_rad_s=np.full(freq.size, omega0), u_min_m=zero(), u_max_m=zero(),
                  valid=np.ones(freq.size, dtype=bool), error_estimate=zero())


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


def _branches(freq, rows, roots, a0, u_min, u_max, valid, error) -> list[Branch]:
    """Sort the roots of each frequency by decreasing omega; branch j = j-th root."""
    order = np.lexsort((-roots, rows))
    rows, roots, a0, u_min, u_max, valid, error = (
        a[order] for a in (rows, roots, a0, u_min, u_max, valid, error)
    )
    rank = np.arange(rows.size) - np.searchsorted(rows, rows)
    branches = []
    for j in range(int(rank.max()) + 1 if rank.size else 0):
        pick = rank == j
        branches.append(
            Branch(
                frequency_hz=freq[rows[pick]],
                app_m=u_max[pick] - u_min[pick],
                a0_m=a0[pick],
                omega_rad_s=roots[pick],
                u_min_m=u_min[pick],
                u_max_m=u_max[pick],
                valid=valid[pick],
                error_estimate=error[pick],
            )
        )
    return branches
