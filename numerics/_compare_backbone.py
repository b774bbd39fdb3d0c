"""The backbone series of every order against the exact backbone.

``perturb.backbone_series(N)`` gives omega/omega0 of Eq. 2.6's free oscillation
as a power series in alpha = h a1 / omega0^2 (Eq. 2.7), a1 the amplitude of the
fundamental. The exact backbone of the full model (``exact_backbone``) reports
a1 too, so each order is compared at the same a1, up to and past contact loss.

Each order's range is capped at contact loss: past it the slider flies, which
the series of Eq. 2.6 knows nothing of, and orders 4 and 6 come back within
1 % there (at 540 and 498 nm) only because their error changes sign.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perturb import ContactModel, Eq26, backbone_series

from ._backbone import exact_backbone

__all__ = ["BackboneComparison", "compare_backbones", "validity_limit"]


@dataclass
class BackboneComparison:
    """Series backbones of several orders against the exact one.

    Attributes
    ----------
    orders : tuple of int
    a1_m, app_m, exact_hz : ndarray, shape (points,)
        The exact backbone: fundamental amplitude, A_pp and frequency.
    contact_lost : ndarray of bool, shape (points,)
    series_hz, error : ndarray, shape (orders, points)
        The series' frequency at each a1 and |f_series / f_exact - 1|.
    limit_a1_m, limit_app_m : ndarray, shape (orders,)
        The amplitude up to which each order holds: within ``tolerance`` and
        in contact (the smaller of the 1 % crossing and contact loss).
    crossing_a1_m, crossing_app_m : ndarray, shape (orders,)
        Where the error first exceeds ``tolerance``, contact or not (for
        orders 4 and up beyond contact loss, where the error changes sign).
    contact_loss_app_m : float
        A_pp at which contact is first lost.
    tolerance : float
    """

    orders: tuple[int, ...]
    a1_m: np.ndarray
    app_m: np.ndarray
    exact_hz: np.ndarray
    contact_lost: np.ndarray
    series_hz: np.ndarray
    error: np.ndarray
    limit_a1_m: np.ndarray
    limit_app_m: np.ndarray
    crossing_a1_m: np.ndarray
    crossing_app_m: np.ndarray
    contact_loss_app_m: float
    tolerance: float

    @property
    def capped(self) -> np.ndarray:
        """Orders whose limit is contact loss rather than their 1 % crossing."""
        return self.crossing_app_m > self.limit_app_m

    def as_json(self) -> dict:
        return {
            "orders": list(self.orders),
            "a1_m": self.a1_m.tolist(),
            "app_m": self.app_m.tolist(),
            "exact_hz": self.exact_hz.tolist(),
            "series_hz": self.series_hz.tolist(),
            "limit_a1_m": self.limit_a1_m.tolist(),
            "limit_app_m": self.limit_app_m.tolist(),
            "crossing_a1_m": self.crossing_a1_m.tolist(),
            "crossing_app_m": self.crossing_app_m.tolist(),
            "contact_loss_app_m": self.contact_loss_app_m,
            "tolerance": self.tolerance,
        }


def validity_limit(amplitude: np.ndarray, error: np.ndarray, tolerance: float) -> float:
    """The amplitude where ``error`` first exceeds ``tolerance``, interpolated in log-log.

    Examples
    --------
    >>> float(validity_limit(np.array([1.0, 10.0]), np.array([1e-3, 1e-1]), 1e-2))
    3.1622776601683795
    """
    above = np.flatnonzero(error > tolerance)
    if above.size == 0:
        return float(amplitude[-1])
    i = above[0]
    if i == 0:
        return float(amplitude[0])
    x0, x1 = np.log(amplitude[i - 1 : i + 1])
    e0, e1 = np.log(error[i - 1 : i + 1])
    return float(np.exp(x0 + (np.log(tolerance) - e0) * (x1 - x0) / (e1 - e0)))


def compare_backbones(
    orders=(2, 4, 6), *, model: ContactModel | None = None, points: int = 400,
    tolerance: float = 0.01,
) -> BackboneComparison:
    """Backbone series of each order against the exact backbone of ``model``.

    Parameters
    ----------
    orders : sequence of int
        Orders N of the series (>= 0).
    model : ContactModel, optional
        The full model whose exact backbone is the reference (paper's by default).
    points : int
        Levels of the exact backbone, log-spaced from 1e-4 y0 to 3 y0.
    tolerance : float
        Relative frequency error that bounds each order's range.

    Returns
    -------
    BackboneComparison

    Examples
    --------
    >>> result = compare_backbones((2, 4))
    >>> [f"{a * 1e9:.0f} nm" for a in result.limit_app_m]  # within 1 % and in contact, A_pp
    ['365 nm', '390 nm']
    >>> [f"{a * 1e9:.0f} nm" for a in result.crossing_app_m]  # order 4: past contact loss
    ['365 nm', '540 nm']
    """
    model = ContactModel() if model is None else model
    orders = tuple(int(n) for n in orders)
    if not orders or min(orders) < 0:
        raise ValueError(f"`orders` must be a non-empty sequence of integers >= 0, got {orders!r}.")
    y0 = model.numeric(model.static_deflection)
    exact = exact_backbone(y0 * np.geomspace(1e-4, 3.0, points), model=model)
    coefficients = Eq26(model).numeric_coefficients()
    alpha = coefficients["h"] / coefficients["omega0_squared"] * exact.a1_m  # Eq. 2.7's parameter
    series = np.array([exact.f_n0_hz * backbone_series(n).frequency_ratio(alpha) for n in orders])
    error = np.abs(series / exact.frequency_hz - 1)
    crossing_a1 = np.array([validity_limit(exact.a1_m, e, tolerance) for e in error])
    crossing_app = np.interp(crossing_a1, exact.a1_m, exact.app_m)
    loss_app = exact.contact_loss_app_m
    loss_a1 = np.interp(loss_app, exact.app_m, exact.a1_m)
    return BackboneComparison(
        orders=orders, a1_m=exact.a1_m, app_m=exact.app_m, exact_hz=exact.frequency_hz,
        contact_lost=exact.contact_lost, series_hz=series, error=error,
        limit_a1_m=np.minimum(crossing_a1, loss_a1), limit_app_m=np.minimum(crossing_app, loss_app),
        crossing_a1_m=crossing_a1, crossing_app_m=crossing_app,
        contact_loss_app_m=loss_app, tolerance=tolerance,
    )
