"""The exact backbone: frequency of free, undamped oscillation against amplitude.

For the conservative part of Eq. 2.4 (no damping, no drive) every motion is
periodic, and its period is the integral over the energy level

    T = 2 * integral dy / sqrt(2 (E - V(y)) / M)   between the turning points.

In the scaled variables of ``restoring`` (sigma = y / y0 - 1, time in units
of sqrt(y0 / g)) the potential about the equilibrium is D(sigma), with
D' = r. Two turning points s- < 0 < s+ share the level, D(s-) = D(s+), and

    E - D(s) = (s+ - s)(s - s-) D[s-, s+, s],

where D[., ., .] is the second divided difference of D. With
s = c + r sin(theta) the inverse-square-root singularities cancel exactly:

    T = 2 * integral_{-pi/2}^{pi/2} dtheta / sqrt(2 D[s-, s+, s(theta)]).

Divided differences of D are means of r over segments, evaluated by
Gauss-Legendre quadrature of the cancellation-free r; nothing subtracts two
nearly equal energies, so the result holds down to tiny amplitudes. Once the
upper turning point y_min reaches y = 0 (s- = -1), the slider bounces: the
contact part of the period is integrated with s = s+ - (s+ + 1) w^2, which
removes the one remaining singularity, and the free flight under gravity is a
parabola, in closed form.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.optimize import brentq

from perturb import ContactModel
from perturb.common import Result, check_int, check_pair, lane_array, result

from . import chebyshev as cheb
from .restoring import Restoring, restoring_force

__all__ = ["Backbone", "exact_backbone", "contact_loss_compression", "MAX_POINTS"]

#: The most energy levels of one backbone: some 20 s and 400 MB for the whole command at
#: the default nodes (measured with ``numerics backbone --points 100000 --json``); a
#: finer curve is several calls.
MAX_POINTS = 100_000
#: Levels integrated together: each holds its quadrature nodes in memory (some 25 kB at
#: the default nodes), so that memory does not grow with the number of levels.
LEVELS_PER_CHUNK = 10_000

# Gauss-Legendre rule on [0, 1] for the means of r over segments.
_GAUSS_T, _GAUSS_W = np.polynomial.legendre.leggauss(16)
_GAUSS_T, _GAUSS_W = (_GAUSS_T + 1) / 2, _GAUSS_W / 2


@result
class Backbone(Result):
    """Frequency of free oscillation of the conservative model against amplitude.

    Attributes
    ----------
    u_max_m : ndarray, shape (points,)
        Largest compression beyond the static deflection, y_max - y0 [m]; the
        energy level.
    ymin_m, ymax_m : ndarray, shape (points,)
        Turning points of y [m]; y_min < 0 while the slider is in flight.
    app_m : ndarray, shape (points,)
        Peak-to-peak amplitude A_pp = y_max - y_min [m] (Section 3).
    a1_m : ndarray, shape (points,)
        Amplitude of the fundamental harmonic of y(t) [m].
    frequency_hz : ndarray, shape (points,)
        Frequency of the free oscillation [Hz].
    contact_lost : ndarray of bool, shape (points,)
        Whether the slider leaves the slideway (y_min < 0).
    y0_m, f_n0_hz : float
        Static deflection and the small-amplitude limit of the frequency.
    contact_loss_app_m : float
        A_pp at which contact is first lost (y_min = 0).
    model : dict
        The model the backbone belongs to (``ContactModel.as_dict()``).
    settings : dict
        ``points``, ``nodes`` (Chebyshev-Lobatto intervals per period
        integral) and ``app_range_m`` (None when the levels were given or
        defaulted).
    elapsed_s : float
        Wall time [s].
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    u_max_m: np.ndarray
    ymin_m: np.ndarray
    ymax_m: np.ndarray
    app_m: np.ndarray
    a1_m: np.ndarray
    frequency_hz: np.ndarray
    contact_lost: np.ndarray
    y0_m: float
    f_n0_hz: float
    contact_loss_app_m: float
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return (
            f"Backbone: {self.app_m.size} points, A_pp {self.app_m.min():.3g}..."
            f"{self.app_m.max():.3g} m, f {self.frequency_hz.min():.6g}..."
            f"{self.frequency_hz.max():.6g} Hz, contact lost above A_pp = "
            f"{self.contact_loss_app_m:.4g} m, {self.elapsed_s:.3g} s"
        )

    def table(self, rows: int = 12) -> str:
        """At most ``rows`` levels, evenly picked: A_pp, a1, frequency, contact lost.

        Examples
        --------
        >>> print(exact_backbone([1e-9, 4e-7]).table(rows=2))
              A_pp [nm]      a1 [nm]       f [Hz]  contact lost
                2.00148      1.00074     1485.588  no
                1606.29      737.992      801.872  yes
        """
        rows = check_int("rows", rows)
        picked = np.unique(np.linspace(0, self.app_m.size - 1, rows).round().astype(int))
        lines = [f"{'A_pp [nm]':>15}{'a1 [nm]':>13}{'f [Hz]':>13}  contact lost"]
        for i in picked:
            lines.append(
                f"{self.app_m[i] * 1e9:>15.6g}{self.a1_m[i] * 1e9:>13.6g}"
                f"{self.frequency_hz[i]:>13.3f}  {'yes' if self.contact_lost[i] else 'no'}"
            )
        return "\n".join(lines)


def _edge_mean(r: Restoring, edge: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Mean of r over [edge, b], smooth inside, with nodes crowded towards ``edge``.

    sigma = edge + (b - edge) t^2 turns (1 + sigma)^m2, whose derivatives blow
    up at the contact edge for a fractional m2, into the smoother t^(2 m2).
    """
    t = _GAUSS_T**2
    return r(edge[..., None] + t * (b - edge)[..., None]) @ (2 * _GAUSS_T * _GAUSS_W)


def _mean_force(r: Restoring, a, b) -> np.ndarray:
    """D[a, b]: the mean of r over the segment [a, b] (a first divided difference of D).

    The segment is split at the point nearest the contact edge sigma = -1, so
    that each part is smooth and the quadrature stays exact to rounding.
    """
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    edge = np.clip(-1.0, np.minimum(a, b), np.maximum(a, b))
    length = b - a
    share = np.divide(edge - a, length, out=np.zeros_like(length), where=length != 0)
    return share * _edge_mean(r, edge, a) + (1 - share) * _edge_mean(r, edge, b)


def _second_difference(r: Restoring, lower, upper, s) -> np.ndarray:
    """D[s-, s+, s] = (D[s-, s] - D[s+, s]) / (s- - s+), positive inside the well."""
    return (_mean_force(r, lower, s) - _mean_force(r, upper, s)) / (lower - upper)


def contact_loss_compression(r: Restoring) -> float:
    """s+ at which the other turning point reaches the contact edge, s- = -1.

    It solves D(s+) = D(-1), written as D[-1, s+] = 0 (the mean of r over
    [-1, s+] vanishes), for s+ > 0.
    """
    upper = 1.0
    while _mean_force(r, -1.0, upper) <= 0:
        upper *= 2
    return brentq(lambda s: float(_mean_force(r, -1.0, s)), 1e-12, upper, xtol=1e-16, rtol=1e-15)


def _lower_turning_point(r: Restoring, upper: np.ndarray) -> np.ndarray:
    """s- in [-1, 0) with D(s-) = D(s+), i.e. D[s-, s+] = 0, by bisection."""
    lo, hi = np.full_like(upper, -1.0), np.zeros_like(upper)
    for _ in range(200):
        mid = (lo + hi) / 2
        # D[mid, s+] > 0 means D(mid) < D(s+): the root lies below mid.
        above = _mean_force(r, mid, upper) > 0
        hi, lo = np.where(above, mid, hi), np.where(above, lo, mid)
        if np.all(hi - lo <= 4 * np.finfo(float).eps * np.abs(hi)):
            break
    return (lo + hi) / 2


def _fundamental(s, t, weight, half_period) -> np.ndarray:
    """(4/T) * integral over a half period of s cos(omega t) dt, per row."""
    omega = np.pi / half_period[:, None]
    return 4 / (2 * half_period) * cheb.integral(s * np.cos(omega * t) * weight)


def _arc(r: Restoring, lower, upper, theta_from, nodes: int) -> tuple[np.ndarray, ...]:
    """The motion from s+ down to s = c + h sin(theta_from), with c, h of [s-, s+].

    Returns s, the time since s+ and dt/dx at the nodes, and the time of the arc.
    """
    x = cheb.lobatto_points(nodes)
    c, h = ((upper + lower) / 2)[:, None], ((upper - lower) / 2)[:, None]
    # theta runs from theta_from (x = -1) to pi/2 (x = 1, the turning point s+).
    span = (np.pi / 2 - theta_from)[:, None] / 2
    s = c + h * np.sin(theta_from[:, None] + span * (x + 1))
    # dt/dtheta = 1 / sqrt(2 D[s-, s+, s]): E - D(s) = (s+ - s)(s - s-) D[s-, s+, s].
    rate = span / np.sqrt(2 * _second_difference(r, lower[:, None], upper[:, None], s))
    duration = cheb.integral(rate)
    return s, duration[:, None] - cheb.cumulative_integral(rate), rate, duration


def _in_contact(r: Restoring, upper: np.ndarray, nodes: int) -> tuple[np.ndarray, ...]:
    """Half period, fundamental and s- for levels that keep contact (s- >= -1)."""
    lower = _lower_turning_point(r, upper)
    s, elapsed, rate, half_period = _arc(r, lower, upper, np.full_like(upper, -np.pi / 2), nodes)
    return half_period, _fundamental(s, elapsed, rate, half_period), lower


def _take_off(r: Restoring, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Speed v0 at the contact edge and the top of the flight s- (for s+ past contact loss).

    The slider leaves the edge at v0, v0^2 / 2 = D(s+) - D(-1), and flies under
    its weight alone (sigma'' = 1) up to s- = -1 - v0^2 / 2.
    """
    v0 = np.sqrt(2 * (upper + 1) * _mean_force(r, -1.0, upper))
    return v0, -1 - v0**2 / 2


def _bouncing(r: Restoring, upper: np.ndarray, nodes: int) -> tuple[np.ndarray, ...]:
    """Half period, fundamental and s- for levels where the slider flies (s- < -1)."""
    v0, lower = _take_off(r, upper)
    edge = np.arcsin(np.clip((-1 - (upper + lower) / 2) / ((upper - lower) / 2), -1, 1))
    s, elapsed, rate, contact_time = _arc(r, lower, upper, edge, nodes)
    # Free flight from the edge up to s- and back: a parabola in closed form.
    tau = v0[:, None] * (cheb.lobatto_points(nodes) + 1) / 2  # time since leaving the edge
    s_flight = -1 - v0[:, None] * tau + tau**2 / 2
    half_period = contact_time + v0
    first = _fundamental(s, elapsed, rate, half_period)
    flight_rate = np.broadcast_to(v0[:, None] / 2, tau.shape)  # dt/dx
    second = _fundamental(s_flight, contact_time[:, None] + tau, flight_rate, half_period)
    return half_period, first + second, lower


def _peak_to_peak(r: Restoring, upper: float, loss: float) -> float:
    """A_pp / y0 = s+ - s- of the level s+: the turning points only, no period integral."""
    level = np.array([upper])
    lower = _take_off(r, level)[1] if upper > loss else _lower_turning_point(r, level)
    return float(upper - lower[0])


def _compression_for(r: Restoring, app: float, loss: float) -> float:
    """s+ whose A_pp / y0 is ``app``, by brentq on log A_pp against log s+.

    A_pp grows monotonically with the level, and A_pp > s+ (s- < 0), so the
    root lies below s+ = app; it is bracketed from below by halving.
    """
    def excess(log_upper: float) -> float:
        return math.log(_peak_to_peak(r, math.exp(log_upper), loss) / app)

    hi = math.log(app)
    lo = hi - math.log(2)
    while excess(lo) >= 0:
        lo -= math.log(2)
    return math.exp(brentq(excess, lo, hi, xtol=1e-15, rtol=1e-15))


def _compressions(r: Restoring, u_max_m, app_range_m, points: int) -> np.ndarray:
    """The levels u_max = y_max - y0 [m] asked for: given, defaulted or from an A_pp range."""
    y0 = r.y0_m
    if u_max_m is not None:
        if app_range_m is not None:
            raise ValueError(
                f"give `u_max_m` or `app_range_m`, not both; got `app_range_m` = {app_range_m!r}."
            )
        return lane_array("u_max_m", u_max_m, positive=True)
    if app_range_m is None:
        # From linear vibrations (1e-6 y0) up to bouncing of about 20 y0.
        return y0 * np.geomspace(1e-6, 3.0, points)
    lo, hi = check_pair("app_range_m", app_range_m, positive=True)
    loss = contact_loss_compression(r)
    ends = [_compression_for(r, app / y0, loss) for app in (lo, hi)]
    return y0 * (np.geomspace(*ends, points) if points > 1 else np.array(ends[:1]))


def exact_backbone(
    u_max_m=None,
    *,
    app_range_m: tuple[float, float] | None = None,
    model: ContactModel | None = None,
    points: int = 200,
    nodes: int = 48,
    levels_per_chunk: int = LEVELS_PER_CHUNK,
) -> Backbone:
    """Frequency of the free, undamped oscillation against its amplitude.

    Parameters
    ----------
    u_max_m : array_like, shape (points,), optional
        Energy levels, given as the largest compression beyond the static
        deflection, y_max - y0 [m] (> 0). By default ``points`` values,
        log-spaced from 1e-6 y0 to 3 y0 (A_pp from 0.45 pm to 4.8 um for the
        paper's model).
    app_range_m : (float, float), optional
        (lo, hi), 0 < lo < hi: instead of ``u_max_m``, ``points`` levels that
        run from A_pp = lo to A_pp = hi [m], log-spaced in u_max between the
        two compressions that give them (found by brentq on the exact A_pp,
        which grows monotonically with u_max). Covers the bouncing branches of
        Fig. 2 (A_pp up to 25 um and beyond).
    model : ContactModel, optional
        The model (power-law spring with gravity and contact loss; damping
        is dropped). The paper's by default.
    points : int
        Number of levels, >= 1 (ignored when ``u_max_m`` is given).
    nodes : int
        Chebyshev-Lobatto intervals per period integral, at least 8.
    levels_per_chunk : int
        Levels integrated at once: memory grows with it, the numbers do not change
        (but in the last bit of a few, where vector lengths change).

    Returns
    -------
    Backbone

    Examples
    --------
    >>> b = exact_backbone([1e-12, 1e-7, 1e-6])  # u_max = y_max - y0 [m]
    >>> [f"{f:.2f}" for f in b.frequency_hz]
    ['1485.59', '1447.93', '311.92']
    >>> [f"{a * 1e9:.1f}" for a in b.app_m], b.contact_lost.tolist()
    (['0.0', '217.9', '12089.4'], [False, False, True])
    >>> f"{b.contact_loss_app_m * 1e9:.1f} nm"  # sqrt(3) y0 for m2 = 2
    '390.0 nm'
    >>> wide = exact_backbone(app_range_m=(1e-8, 2.5e-5), points=5)
    >>> [f"{a * 1e6:.4g}" for a in wide.app_m[[0, -1]]], wide.contact_lost[[0, -1]].tolist()
    (['0.01', '25'], [False, True])
    """
    start = time.perf_counter()
    model = ContactModel() if model is None else model
    points = check_int("points", points, 1, MAX_POINTS, why="some 20 s at the default nodes;"
                       " a finer curve is several calls")
    nodes = check_int("nodes", nodes, 8)
    levels_per_chunk = check_int("levels_per_chunk", levels_per_chunk)
    r = restoring_force(model)
    y0 = r.y0_m
    u = _compressions(r, u_max_m, app_range_m, points)
    upper = u / y0
    loss = contact_loss_compression(r)
    flies = upper > loss
    half, a1, lower = (np.empty_like(upper) for _ in range(3))
    for first in range(0, upper.size, levels_per_chunk):
        chunk = np.zeros(upper.size, dtype=bool)
        chunk[first:first + levels_per_chunk] = True
        for mask, regime in ((chunk & ~flies, _in_contact), (chunk & flies, _bouncing)):
            if mask.any():
                half[mask], a1[mask], lower[mask] = regime(r, upper[mask], nodes)
    frequency = 1 / (2 * half * r.time_unit_s)
    (half0,), _, _ = _in_contact(r, np.array([1e-9]), 8)
    app_range = None if app_range_m is None else list(check_pair("app_range_m", app_range_m))
    settings = {"points": int(u.size), "nodes": nodes, "app_range_m": app_range}
    return Backbone(
        u_max_m=u, ymin_m=y0 * (1 + lower), ymax_m=y0 * (1 + upper),
        app_m=y0 * (upper - lower), a1_m=y0 * np.abs(a1), frequency_hz=frequency,
        contact_lost=flies, y0_m=y0, f_n0_hz=1 / (2 * half0 * r.time_unit_s),
        contact_loss_app_m=y0 * (loss + 1), model=model.as_dict(), settings=settings,
        elapsed_s=time.perf_counter() - start,
    )
