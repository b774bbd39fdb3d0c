"""Analytic against numerical: backbones and forced responses, order by order.

``compare`` gathers the two comparisons of ``_compare_backbone`` and
``_compare_response`` into one result, with where the full model parts from
Eq. 2.6 (contact loss, or the damping law while in contact).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perturb import PAPER_BAND_HZ

from ._compare_backbone import BackboneComparison, compare_backbones
from ._compare_response import (
    MODELS,
    ResponseComparison,
    SteadyCurve,
    _relative_difference,
    compare_response,
    steady_curve,
)
from common import progress

__all__ = ["Comparison", "compare", "model_parting"]


@dataclass
class Comparison:
    """Series of several orders against the exact backbone and RK4 steady states.

    Attributes
    ----------
    backbone : BackboneComparison
    curves : list of SteadyCurve
        RK4 steady states per (model, P_a).
    responses : list of ResponseComparison
        Per (model, P_a, order).
    frequency_hz : ndarray
        The frequency grid of the sweeps and of the analytic responses.
    tolerance : float
        The relative difference that counts as parting.
    """

    backbone: BackboneComparison
    curves: list[SteadyCurve]
    responses: list[ResponseComparison]
    frequency_hz: np.ndarray
    tolerance: float

    @property
    def orders(self) -> tuple[int, ...]:
        return self.backbone.orders

    @property
    def pa_fracs(self) -> tuple[float, ...]:
        return tuple(sorted({c.pa_frac for c in self.curves}))

    def curve(self, model: str, pa_frac: float) -> SteadyCurve:
        return next(c for c in self.curves if c.model == model and np.isclose(c.pa_frac, pa_frac))

    def response(self, model: str, pa_frac: float, order: int) -> ResponseComparison:
        return next(r for r in self.responses if r.model == model and r.order == order
                    and np.isclose(r.pa_frac, pa_frac))

    def parting(self, pa_frac: float) -> dict:
        """Where the full model's steady states part from those of Eq. 2.6."""
        return model_parting(self.curve("eq26", pa_frac), self.curve("full", pa_frac),
                             self.tolerance)

    def as_json(self) -> dict:
        return {
            "frequency_hz": [float(self.frequency_hz[0]), float(self.frequency_hz[-1]),
                             int(self.frequency_hz.size)],
            "backbone": self.backbone.as_json(),
            "responses": [r.as_json() for r in self.responses],
            "parting": {f"{p:g}": self.parting(p) for p in self.pa_fracs},
            "notes": [note for c in self.curves for note in c.notes],
        }


def model_parting(eq26: SteadyCurve, full: SteadyCurve, tolerance: float) -> dict:
    """Count the states (same frequency and sweep direction) where App differs > tolerance.

    In contact, the two models differ only by the damping law (and, for m2 != 2,
    by the spring's terms above the quadratic); otherwise by contact loss.
    """
    both = eq26.settled & full.settled & np.isfinite(eq26.app_m) & np.isfinite(full.app_m)
    differ = both & (_relative_difference(full.app_m, eq26.app_m) > tolerance)
    lost = differ & full.contact_lost
    return {
        "states": int(both.sum()),
        "differ": int(differ.sum()),
        "differ_with_contact_loss": int(lost.sum()),
        "differ_in_contact": int((differ & ~lost).sum()),
        "in_contact_hz": np.unique(full.frequency_hz[differ & ~lost]).tolist(),
    }


def _checked(orders, pa_fracs, tolerance) -> tuple[tuple[int, ...], tuple[float, ...], float]:
    """The arguments of ``compare``, or a ValueError naming the one that is wrong."""
    orders, pa_fracs = tuple(np.atleast_1d(orders)), tuple(np.atleast_1d(pa_fracs))
    if not orders or not all(_is_int(n) and n >= 0 for n in orders):
        raise ValueError(f"`orders` must be a non-empty sequence of integers >= 0, got {orders!r}.")
    try:
        fracs = np.asarray(pa_fracs, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"`pa_fracs` must be real numbers, got {pa_fracs!r}.") from None
    if fracs.size == 0 or not np.all(np.isfinite(fracs) & (fracs >= 0)):
        raise ValueError(f"`pa_fracs` must be a non-empty sequence of finite numbers >= 0, "
                         f"got {pa_fracs!r}.")
    tolerance = float(tolerance)
    if not (np.isfinite(tolerance) and tolerance > 0):
        raise ValueError(f"`tolerance` must be finite and > 0, got {tolerance!r}.")
    return tuple(int(n) for n in orders), tuple(float(p) for p in fracs), tolerance


def _is_int(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def compare(
    orders=(2, 4, 6),
    pa_fracs=(0.05, 0.10, 0.15),
    *,
    frequencies_hz=None,
    steps_per_period: int = 128,
    tolerance: float = 0.01,
    quiet: bool = True,
) -> Comparison:
    """Series of each order against the exact backbone and RK4 steady states.

    Parameters
    ----------
    orders : sequence of int
        Orders N of the series.
    pa_fracs : sequence of float
        Force amplitudes P_a as fractions of the weight Q.
    frequencies_hz : array_like, optional
        Increasing frequency grid; by default the paper's band in 5 Hz steps.
    steps_per_period : int
        RK4 steps per period of the steady states.
    tolerance : float
        Relative error bounding the backbone's range, and the difference that
        counts as the two models parting.
    quiet : bool
        No progress on stderr.

    Returns
    -------
    Comparison

    Examples
    --------
    >>> result = compare((4, 6), (0.05,), frequencies_hz=np.arange(700.0, 800.0, 5.0))
    >>> [f"{result.response('eq26', 0.05, n).largest_error:.1e}" for n in (4, 6)]
    ['2.2e-04', '1.5e-05']
    """
    orders, pa_fracs, tolerance = _checked(orders, pa_fracs, tolerance)
    if frequencies_hz is None:
        frequencies_hz = np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + 1.0, 5.0)
    grid = np.asarray(frequencies_hz, dtype=float)
    backbone = compare_backbones(orders, tolerance=tolerance)
    limits = dict(zip(backbone.orders, backbone.limit_app_m))
    bar = progress(len(pa_fracs) * len(MODELS), "compare: RK4 sweeps", quiet=quiet)
    curves = []
    for pa_frac in pa_fracs:
        for model in MODELS:
            curves.append(steady_curve(grid, float(pa_frac), model, steps_per_period))
            bar.update()
    bar.close()
    responses = [compare_response(curve, n, grid, limits[n])
                 for curve in curves for n in backbone.orders]
    return Comparison(backbone=backbone, curves=curves, responses=responses, frequency_hz=grid,
                      tolerance=tolerance)
