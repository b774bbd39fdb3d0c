"""The backbone series of every order against the exact backbone.

``perturb.backbone_series(N, truncation)`` gives omega/omega0 of the free oscillation
as a power series in alpha (a1 / y0 for the contact's own spring, h a1 / omega0^2 for
Eq. 2.6's, Eq. 2.7), a1 the amplitude of the fundamental. The exact backbone of the
full model (``exact_backbone``) reports a1 too, so each order is compared at the same
a1, up to and past contact loss.

Each order's range is capped at contact loss: past it the slider flies, which
the series knows nothing of, and orders 4 and 6 come back within
1 % there (at 540 and 498 nm) only because their error changes sign.
"""

from __future__ import annotations

import time

import numpy as np

from perturb import ContactModel, backbone_series, eq26_numbers
from perturb.common import Result, check_int, check_positive, result
from perturb.series.truncation import truncation_settings

from ..backbone.exact import exact_backbone

__all__ = ["BackboneComparison", "compare_backbones", "validity_limit"]


@result
class BackboneComparison(Result):
    """Series backbones of several orders against the exact one.

    Attributes
    ----------
    orders : tuple of int
    a1_m, app_m, exact_hz : ndarray, shape (points,)
        The exact backbone: fundamental amplitude, A_pp and frequency.
    contact_lost : ndarray of bool, shape (points,)
    series_hz, relative_error : ndarray, shape (orders, points)
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
    model : dict
        The full model whose exact backbone is the reference (``ContactModel.as_dict()``).
    settings : dict
        ``points``: levels of the exact backbone.
    elapsed_s : float
        Wall time [s].
    """

    orders: tuple[int, ...]
    a1_m: np.ndarray
    app_m: np.ndarray
    exact_hz: np.ndarray
    contact_lost: np.ndarray
    series_hz: np.ndarray
    relative_error: np.ndarray
    limit_a1_m: np.ndarray
    limit_app_m: np.ndarray
    crossing_a1_m: np.ndarray
    crossing_app_m: np.ndarray
    contact_loss_app_m: float
    tolerance: float
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    @property
    def capped(self) -> np.ndarray:
        """Orders whose limit is contact loss rather than their 1 % crossing."""
        return self.crossing_app_m > self.limit_app_m

    def csv_rows(self) -> list[dict]:
        """A row per amplitude: the exact backbone, and each order's frequency and
        relative error (``series_hz_order_N``, ``relative_error_order_N``)."""
        rows = []
        for i in range(self.a1_m.size):
            row = {"a1_m": self.a1_m[i], "app_m": self.app_m[i], "exact_hz": self.exact_hz[i],
                   "contact_lost": self.contact_lost[i]}
            for k, order in enumerate(self.orders):
                row[f"series_hz_order_{order}"] = self.series_hz[k, i]
                row[f"relative_error_order_{order}"] = self.relative_error[k, i]
            rows.append(row)
        return rows

    def summary(self) -> str:
        limits = ", ".join(f"{a * 1e9:.0f}" for a in self.limit_app_m)
        return (
            f"BackboneComparison: orders {list(self.orders)} hold within {self.tolerance:g} up "
            f"to A_pp = {limits} nm (contact lost at {self.contact_loss_app_m * 1e9:.1f} nm), "
            f"{self.elapsed_s:.3g} s"
        )

    def table(self) -> str:
        """Per order: the limits in a1 and A_pp (* where contact loss caps it), the crossing.

        Examples
        --------
        >>> print(compare_backbones((2, 4)).table())
         order  a1 limit [nm]  A_pp limit [nm]  A_pp crossing [nm]
             2          181.9           365.5                365.5
             4          193.9           390.0*               540.1
        """
        lines = [f"{'order':>6}{'a1 limit [nm]':>15}{'A_pp limit [nm]':>17}"
                 f"{'A_pp crossing [nm]':>20}"]
        for n, a1, app, cross, capped in zip(self.orders, self.limit_a1_m, self.limit_app_m,
                                              self.crossing_app_m, self.capped):
            mark = "*" if capped else " "
            lines.append(f"{n:>6}{a1 * 1e9:>15.1f}{app * 1e9:>16.1f}{mark}{cross * 1e9:>20.1f}")
        return "\n".join(lines)


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
    tolerance: float = 0.01, truncation: str = "consistent", allow_slow: bool = False,
) -> BackboneComparison:
    """Backbone series of each order against the exact backbone of ``model``.

    Parameters
    ----------
    orders : sequence of int
        Orders N of the series (>= 0), at least one.
    model : ContactModel, optional
        The full model whose exact backbone is the reference (paper's by default).
    points : int
        Levels of the exact backbone, log-spaced in u_max from 1e-4 y0 to 3 y0 (>= 2).
    tolerance : float
        Relative frequency error that bounds each order's range (> 0).
    truncation : {"consistent", "paper"}
        The series of the model's own spring (every Taylor term, alpha = a / y0) or
        Eq. 2.6's (h u^2 only, alpha = h a / omega0^2): ``perturb.backbone_series``.
    allow_slow : bool
        Take orders above the one measured to take about a minute
        (``perturb.backbone_series``'); refused otherwise.

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
    start = time.perf_counter()
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    try:
        orders = tuple(check_int("orders", n, 0) for n in orders)
    except TypeError:
        raise ValueError(f"`orders` must be a sequence of integers >= 0, got {orders!r}.") from None
    if not orders:
        raise ValueError(f"`orders` must be a non-empty sequence of integers >= 0, got {orders!r}.")
    points = check_int("points", points, 2, 1_000_000, why="a curve of a million amplitudes "
                       "is finer than any figure")
    tolerance = check_positive("tolerance", tolerance)
    numbers = eq26_numbers(model.parameters)
    exact = exact_backbone(numbers.y0_m * np.geomspace(1e-4, 3.0, points), model=model)
    backbones = [backbone_series(n, truncation, model.parameters, allow_slow=allow_slow)
                 for n in orders]
    series = np.array([exact.f_n0_hz * b.frequency_ratio(b.alpha_per_m() * exact.a1_m)
                       for b in backbones])
    error = np.abs(series / exact.frequency_hz - 1)
    crossing_a1 = np.array([validity_limit(exact.a1_m, e, tolerance) for e in error])
    crossing_app = np.interp(crossing_a1, exact.a1_m, exact.app_m)
    loss_app = exact.contact_loss_app_m
    loss_a1 = np.interp(loss_app, exact.app_m, exact.a1_m)
    return BackboneComparison(
        orders=orders, a1_m=exact.a1_m, app_m=exact.app_m, exact_hz=exact.frequency_hz,
        contact_lost=exact.contact_lost, series_hz=series, relative_error=error,
        limit_a1_m=np.minimum(crossing_a1, loss_a1), limit_app_m=np.minimum(crossing_app, loss_app),
        crossing_a1_m=crossing_a1, crossing_app_m=crossing_app,
        contact_loss_app_m=loss_app, tolerance=tolerance, model=model.as_dict(),
        settings={"points": points, **truncation_settings(truncation)},
        elapsed_s=time.perf_counter() - start,
    )
