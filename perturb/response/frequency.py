"""The analytic frequency response of the series, Eq. 2.6's or the contact's own.

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

The frequency equation, the root search and the waveforms run in code compiled
for each order (``codegen.py``, ``template.py``) and kept
on disk: the first call of an order in a new cache compiles it, once.

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
>>> res = frequency_response(np.array([800.0, 1420.0]), pa_frac=0.05, order=6,
...                          truncation="paper")
>>> res.roots_per_frequency().tolist()  # 1420 Hz is on the bent primary peak
[1, 3]
>>> [round(float(b.app_m[-1]) * 1e9, 1) for b in res.branches]  # App [nm], 1420 Hz
[168.0, 206.2, 302.3]
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import partial

import numpy as np
import numpy.typing as npt

from perturb.common import (
    Result,
    check_choice,
    check_int,
    check_pair,
    check_positive,
    lane_array,
    result,
)

from ..model.contact_model import ContactModel
from ..model.effects import EQ_2_6, FULL
from ..model.numbers import Eq26Numbers
from ..model.parameters import PAPER, ContactParameters
from ..series.slow_orders import check_slow_order
from ..series.truncation import (
    SeriesValues,
    Truncation,
    measures_model_distance,
    series_values,
    truncation_for,
    truncation_settings,
)
from .codegen import NEXT_ORDERS, series_kernels, series_kernels_built

__all__ = ["frequency_response", "Response", "Branch"]

#: Offsets of the extra grid points around each resonance k Omega, in units of c.
RESONANCE_OFFSETS = np.array([-12.0, -6.0, -3.0, -1.5, -0.75, 0.0, 0.75, 1.5, 3.0, 6.0, 12.0])
#: Frequencies solved together: the grid of a chunk (about 125 omega per frequency)
#: and its brackets take some 20 MB at the defaults.
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
        (``truncation_error``) and, for Eq. 2.6's series off the paper's contact, its
        distance to the consistent series (``model_distance``); NaN where no root of
        those orders matches.
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

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


def match_distance(rows: np.ndarray, roots: np.ndarray, c: float) -> np.ndarray:
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


@dataclass(frozen=True)
class _Roots:
    """Roots of one order's frequency equation with what their waveforms need.

    ``real[m, k, i]`` and ``imag[m, k, i]``: sum_(n <= N+m) z_n_k at root i (in
    the frame of u0), m = 0, 1, 2; ``lag`` theta_1 = arg 1 / (omega^2 - Omega^2
    + 2 i c Omega), the phase of u0 behind the drive: together they give u(t) in
    the frame of the excitation, so that waveforms of different omega (orders)
    can be subtracted.
    """

    omega: np.ndarray
    a0: np.ndarray
    real: np.ndarray
    imag: np.ndarray
    lag: np.ndarray


def _at_roots(kernels, values: Eq26Numbers, G: float, omega, Omega) -> _Roots:
    """A0 = G H_1(omega) (Eq. 2.8), the harmonics of orders N, N+1, N+2 and the lag
    at the roots ``omega`` (``kernels``: the compiled kernels of one order)."""
    transfer = omega**2 - Omega**2 + 2j * values.c_per_s * Omega
    a0 = G / np.abs(transfer)
    shape = (1 + len(NEXT_ORDERS), kernels.TOP_HARMONIC + 1, omega.size)
    real, imag = np.empty(shape), np.empty(shape)
    kernels.harmonics_lanes(a0, omega, Omega, values.c_per_s, _k_d(kernels, values), real,
                            imag)
    return _Roots(omega, a0, real, imag, -np.angle(transfer))


def _phase_tables(harmonics: int, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """cos(k t_j) and sin(k t_j), k = 0..harmonics - 1, at ``samples`` phases t_j of a period."""
    k_t = np.outer(np.arange(harmonics), 2 * np.pi * np.arange(samples) / samples)
    return np.cos(k_t), np.sin(k_t)


def truncation_error(kernels, values, G, Omega, rows, base: _Roots, app, tables) -> np.ndarray:
    """An a-posteriori estimate of the relative error of the order-N response.

    max over k = 1, 2 of pp(u_(N+k) - u_N) / App_N, where u_M is the
    reconstructed u(t) of the order-M series (in the time frame of the
    excitation) on its root nearest to the order-N root (secant steps,
    ``nearby_roots`` of the compiled kernels; NaN where no root of order N+k
    lies within ``match_distance``), and pp is max - min over a period;
    ``base`` holds the order-N roots of frequencies ``Omega[rows]``. It bounds
    |App_(N+k) - App_N| / App_N. The term b_(N+1) left out of the frequency
    equation is what the resonance amplifies; at even N it is zero (b_n = 0 for
    odd n), so order N+1 has the frequency equation of order N and only order
    N+2 sees it, hence two orders. Orders with the same frequency equation
    (b_n = 0 for odd n) share their roots. The whole waveform is compared, not
    only App: near the 1/2 superharmonic peak at 0.15 Q (745 Hz) App changes by
    < 0.2 % from order 2 to 11 while it is 1.4 % off RK4 of Eq. 2.6, and the
    waveform still moves.
    """
    Omega_r, n = Omega[rows], base.omega.size
    later = None  # the roots of the frequency equation with every b_n up to N+2
    error = np.zeros(n)
    for m in NEXT_ORDERS:
        if kernels.B_ORDERS[m] == kernels.B_ORDERS[0]:
            other, matched = base, np.ones(n, dtype=bool)
        else:
            if later is None:
                omega, found = kernels.nearby_roots(
                    G, Omega_r, base.omega, match_distance(rows, base.omega, values.c_per_s),
                    values.c_per_s, _k_d(kernels, values), values.omega0_rad_s)
                later = _at_roots(kernels, values, G, omega, Omega_r), found
            other, matched = later
        change = np.empty(n)
        kernels.change_peak_to_peak(other.real[m], other.imag[m], other.lag, base.real[0],
                                    base.imag[0], base.lag, *tables, change)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = change / app
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
    engine: str = "auto",
    truncation: str = "consistent",
    allow_slow: bool = False,
    frequencies_per_chunk: int = FREQUENCIES_PER_CHUNK,
) -> Response:
    """Every response of the order-N series of the equation in contact at each frequency.

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
    engine : {"auto", "compiled", "numpy"}
        "compiled": the compiled kernels of the order and of the terms the series
        keeps (built once per cache: tens of seconds for Eq. 2.6's series, up to
        minutes for a consistent series that keeps every k_j and d_j; then some 10x
        faster than numpy); "numpy": the residual grid in numpy (no build); "auto", as
        everywhere, the compiled route where it is built or builds within seconds: so
        compiled where those kernels are built, numpy otherwise. They give the same
        branches, roots (within 1e-12) and validity. The numpy route evaluates
        Eq. 2.6's series by its lambdified closed forms, and any other series by the
        scheme compiled once for every order (``KernelSeries``) under "auto", or by
        the scheme in numpy (``NumericSeries``) under "numpy".
    truncation : {"consistent", "paper"}
        "consistent": every term k_j u^j and d_j u^j u' of the contact's equation up
        to eps^N (``derive``); "paper": Eq. 2.6 (h and linear damping). The error
        estimate of "paper" includes its distance to the contact's own equation
        (the consistent series of order N+2), except on the paper's contact itself
        (m2 = 2, l = 1), whose flags stay the paper's.
    allow_slow : bool
        Take an order above the one measured to take about a minute
        (``perturb.series.slow_orders``: 24); refused otherwise.
    frequencies_per_chunk : int
        Frequencies solved together: memory grows with it (some 20 MB at the
        default), the branches do not change.

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
    check_int("order", order, minimum=0)
    if not isinstance(parameters, ContactParameters):
        raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
    order = check_slow_order(order, "response", truncation, parameters,
                             allow_slow=allow_slow)
    omega_range = check_pair("omega_range", omega_range, positive=True)
    grid_points = check_int("grid_points", grid_points, minimum=2)
    samples = check_int("samples", samples, minimum=3)
    tolerance = check_positive("tolerance", tolerance)
    frequencies_per_chunk = check_int("frequencies_per_chunk", frequencies_per_chunk)
    check_choice("engine", engine, ENGINES)
    resolved = truncation_for(truncation, parameters)
    solve = _chunk_solver(engine, order, resolved)
    values = series_values(parameters)
    Omega = 2 * np.pi * freq
    G = pa_frac * values.Q_n * values.G_per_P_a
    if G == 0:
        branches = [_at_rest(freq, values.omega0_rad_s)]
    else:
        # Frequencies are independent: solved a chunk at a time, memory stays bounded.
        parts = [solve(values, G, Omega[chunk], order, omega_range, grid_points,
                       samples, tolerance, chunk.start)
                 for chunk in _chunks(freq.size, frequencies_per_chunk)]
        rows, roots, a0, u_min, u_max, valid, error = (np.concatenate(column)
                                                       for column in zip(*parts))
        branches = _branches(freq, rows, roots, a0, u_min, u_max, valid, error)
    return Response(
        order=order,
        pa_frac=pa_frac,
        frequency_hz=freq,
        branches=branches,
        model=_series_model(parameters, resolved),
        settings={"omega_range": list(omega_range), "grid_points": grid_points,
                  "samples": samples, "tolerance": tolerance,
                  **truncation_settings(resolved.name)},
        elapsed_s=time.perf_counter() - start,
    )


#: The routes of the frequency equation (see ``frequency_response``'s ``engine``).
ENGINES = ("auto", "compiled", "numpy")


def _chunk_solver(engine: str, order: int, truncation: Truncation):
    """The chunk solver of ``engine``: "compiled", the kernels of the order and of the
    terms the truncation keeps (generated and compiled once, then cached); "numpy", the
    numpy route; "auto", the compiled kernels where they are built already, the numpy
    route otherwise. The numpy route of Eq. 2.6's series evaluates its lambdified closed
    forms; that of any other series, the scheme's numba kernel (``KernelSeries``,
    compiled once for every order and truncation) under "auto" and the scheme in numpy
    under "numpy"."""
    from .numpy_route import solve_chunk

    if engine == "auto":
        engine = "compiled" if series_kernels_built(order, truncation) else "auto"
    if engine == "compiled":
        return partial(_solve_chunk, truncation=truncation)
    if truncation.keeps_eq26_only(order + NEXT_ORDERS[-1]):
        return partial(solve_chunk, truncation=truncation)
    return partial(solve_chunk, truncation=truncation, compiled=engine == "auto")


def _chunks(size: int, chunk: int) -> list[slice]:
    return [slice(start, min(start + chunk, size)) for start in range(0, size, chunk)]


def _solve_chunk(values, G, Omega, order, omega_range, grid_points, samples, tolerance,
                 offset: int, truncation: Truncation) -> tuple[np.ndarray, ...]:
    """Every root of the frequencies ``Omega``, with App, extrema, validity and error;
    rows count from ``offset``."""
    kernels = series_kernels(order, truncation)
    rows, roots = _roots(kernels, values, G, Omega, omega_range, grid_points)
    base = _at_roots(kernels, values, G, roots, Omega[rows])
    tables = _phase_tables(kernels.TOP_HARMONIC + 1, samples)
    u_max, u_min = np.empty(roots.size), np.empty(roots.size)
    kernels.waveform_extrema(base.real[0], base.imag[0], base.lag, *tables, u_max, u_min)
    error = truncation_error(kernels, values, G, Omega, rows, base, u_max - u_min, tables)
    if truncation.name == "paper" and measures_model_distance(order, values.parameters):
        error = np.maximum(error, _model_distance(order, values, G, Omega, rows, base,
                                                  u_max - u_min, samples))
    valid = (values.y0_m + u_min > 0) & (error < tolerance)
    return rows + offset, roots, base.a0, u_min, u_max, valid, error


def _model_distance(order, values, G, Omega, rows, base: _Roots, app, samples) -> np.ndarray:
    """``numpy_route.model_distance`` of the compiled roots (their waveforms sampled)."""
    from .numpy_route import model_distance, sample_waveform

    k = np.arange(base.real.shape[1])  # (model_distance: the consistent series compiled)
    per_harmonic = (base.real[0] + 1j * base.imag[0]).T * np.exp(1j * np.outer(base.lag, k))
    u = sample_waveform(per_harmonic, samples)
    return model_distance(order, values, G, Omega, rows, base.omega, u, app)


def _series_model(parameters: ContactParameters, truncation: Truncation) -> dict:
    """The model whose equation the series solves, as data: Eq. 2.6 (the effects
    ``EQ_2_6``) for the paper's truncation, the contact's own laws otherwise."""
    return ContactModel(parameters, EQ_2_6 if truncation.name == "paper" else FULL).as_dict()


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


def _roots(kernels, values, G, Omega, omega_range, grid_points):
    """Every root omega of the frequency equation: (frequency index, omega) per root.

    The grid of each frequency: ``grid_points`` uniform in ``omega_range``, and
    points at k Omega + ``RESONANCE_OFFSETS`` c for k = 1..N+1, clipped to the range.
    """
    lo, hi = omega_range[0] * values.omega0_rad_s, omega_range[1] * values.omega0_rad_s
    return kernels.find_roots(G, Omega, np.linspace(lo, hi, grid_points),
                              values.c_per_s * RESONANCE_OFFSETS, kernels.ORDER + 1, lo, hi,
                              values.c_per_s, _k_d(kernels, values), values.omega0_rad_s)


def _k_d(kernels, values: SeriesValues) -> np.ndarray:
    """The coefficients k_j, d_j of the contact that ``kernels`` take, in their order."""
    return np.array(values.coefficients(kernels.COEFFICIENTS), dtype=float)


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
