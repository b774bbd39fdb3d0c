"""Analytic against numerical: backbones and forced responses, order by order.

``compare`` gathers the two comparisons of ``backbones`` and
``responses`` into one result, with where the full model parts from
Eq. 2.6 (contact loss, or the damping law while in contact).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import asdict

import numpy as np

from perturb import FULL, PAPER_BAND_HZ, ContactModel, ContactParameters, frequency_response
from perturb.common import (
    Result,
    check_int,
    check_positive,
    lane_array,
    lookup,
    progress,
    result,
)
from perturb.series.slow_orders import check_slow_order
from perturb.series.truncation import truncation_for, truncation_settings

from ..simulation.ranges import check_tested
from .backbones import BackboneComparison, compare_backbones
from .responses import (
    MODELS,
    ResponseComparison,
    SteadyCurve,
    compare_response,
    relative_difference,
    steady_curves,
)

__all__ = ["Comparison", "compare", "model_parting"]


@result
class Comparison(Result):
    """Series of several orders against the exact backbone and RK4 steady states.

    Attributes
    ----------
    model : dict
        The full model (``ContactModel.as_dict()``); the curves named "eq26" use
        the same parameters with the effects of Eq. 2.6 (``settings["models"]``).
    settings : dict
        orders, pa_frac, steps_per_period, tolerance, and the effects of each RK4 model.
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

    model: dict
    settings: dict
    backbone: BackboneComparison
    curves: list[SteadyCurve]
    responses: list[ResponseComparison]
    frequency_hz: np.ndarray
    tolerance: float
    elapsed_s: float = 0.0

    @property
    def orders(self) -> tuple[int, ...]:
        return self.backbone.orders

    @property
    def pa_frac(self) -> tuple[float, ...]:
        return tuple(sorted({c.pa_frac for c in self.curves}))

    def curve(self, model_name: str, pa_frac: float) -> SteadyCurve:
        """The RK4 curve of one model and P_a (a KeyError lists the curves there are)."""
        return lookup(f"curve {model_name!r} at pa_frac={pa_frac!r}", self.curves,
                      lambda c: c.model_name == model_name and np.isclose(c.pa_frac, pa_frac),
                      lambda c: (c.model_name, c.pa_frac))

    def response(self, model_name: str, pa_frac: float, order: int) -> ResponseComparison:
        """One order's comparison (a KeyError lists the comparisons there are)."""
        return lookup(f"response {model_name!r} at pa_frac={pa_frac!r}, order {order!r}",
                      self.responses,
                      lambda r: (r.model_name == model_name and r.order == order
                                 and np.isclose(r.pa_frac, pa_frac)),
                      lambda r: (r.model_name, r.pa_frac, r.order))

    def parting(self, pa_frac: float) -> dict:
        """Where the full model's steady states part from those of Eq. 2.6."""
        return model_parting(self.curve("eq26", pa_frac), self.curve("full", pa_frac),
                             self.tolerance)

    def derived(self) -> dict:
        return {"parting": {f"{p:g}": self.parting(p) for p in self.pa_frac},
                "notes": [note for c in self.curves for note in c.notes]}

    def summary(self) -> str:
        return (f"Comparison: orders {list(self.orders)} at P_a = {list(self.pa_frac)} Q, "
                f"{self.frequency_hz.size} frequencies, {self.elapsed_s:.3g} s")

    def table(self) -> str:
        from .table import format_comparison

        return format_comparison(self)


def model_parting(eq26: SteadyCurve, full: SteadyCurve, tolerance: float) -> dict:
    """Count the states (same frequency and sweep direction) where App differs > tolerance.

    In contact, the two models differ only by the damping law (and, for m2 != 2,
    by the spring's terms above the quadratic); otherwise by contact loss.
    """
    both = eq26.settled & full.settled & np.isfinite(eq26.app_m) & np.isfinite(full.app_m)
    differ = both & (relative_difference(full.app_m, eq26.app_m) > tolerance)
    lost = differ & full.contact_lost
    return {
        "states": int(both.sum()),
        "differ": int(differ.sum()),
        "differ_with_contact_loss": int(lost.sum()),
        "differ_in_contact": int((differ & ~lost).sum()),
        "in_contact_hz": np.unique(full.frequency_hz[differ & ~lost]).tolist(),
    }


def _checked(orders, pa_frac, tolerance) -> tuple[tuple[int, ...], tuple[float, ...], float]:
    """The arguments of ``compare``, or a ValueError naming the one that is wrong."""
    orders = tuple(np.atleast_1d(np.asarray(orders, dtype=object)))
    if not orders:
        raise ValueError(f"`orders` must be a non-empty sequence of integers >= 0, got {orders!r}.")
    orders = tuple(check_int("orders", n, minimum=0) for n in orders)
    fracs = tuple(float(p) for p in lane_array("pa_frac", pa_frac))
    return orders, fracs, check_positive("tolerance", tolerance)


def _compared_parameters(model, parameters) -> ContactParameters:
    """The parameters of the full model that ``compare`` is given (``parameters=``, the
    deprecated spelling, with a DeprecationWarning)."""
    if parameters is not None:
        warnings.warn("`compare(parameters=...)` is deprecated: pass "
                      "`model=ContactModel(parameters)`", DeprecationWarning, stacklevel=3)
        if model is not None:
            raise ValueError("give `model` or `parameters` (deprecated), not both.")
        if not isinstance(parameters, ContactParameters):
            raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
        return parameters
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel) or model.effects != FULL:
        raise ValueError("`model` must be a ContactModel with the full model's effects (the "
                         f"comparison runs Eq. 2.6's beside it), got {model!r}.")
    return model.parameters


def compare(
    orders=(2, 4, 6),
    pa_frac=(0.05, 0.10, 0.15),
    *,
    frequency_hz=None,
    steps_per_period: int = 128,
    tolerance: float = 0.01,
    model: ContactModel | None = None,
    quiet: bool = True,
    truncation: str = "consistent",
    allow_slow: bool = False,
    unchecked: bool = False,
    parameters: ContactParameters | None = None,
) -> Comparison:
    """Series of each order against the exact backbone and RK4 steady states.

    Parameters
    ----------
    orders : sequence of int
        Orders N of the series.
    pa_frac : float or sequence of float
        Force amplitudes P_a as fractions of the weight Q.
    frequency_hz : array_like, optional
        Increasing frequency grid; by default the paper's band in 5 Hz steps.
    steps_per_period : int
        RK4 steps per period of the steady states.
    tolerance : float
        Relative error bounding the backbone's range, and the difference that
        counts as the two models parting.
    model : ContactModel, optional
        The full model whose contact is compared (the paper's by default): the series
        and RK4 of Eq. 2.6 and of the full model at its parameters. The grid's default
        stays the paper's band.
    quiet : bool
        No progress on stderr.
    truncation : {"consistent", "paper"}
        The series compared: every term of the contact's equation up to the order, or
        Eq. 2.6's (``perturb.frequency_response``, ``perturb.backbone_series``).
    allow_slow : bool
        Take orders above the one measured to take about a minute
        (``perturb.frequency_response``'s); refused otherwise.
    unchecked : bool
        Go past the ranges of f_e, P_a and the contact where the answers are measured
        to hold (``numerics.simulation.ranges.TESTED``); refused otherwise.
    parameters : ContactParameters, optional
        Deprecated: ``model=ContactModel(parameters)`` says the same.

    Returns
    -------
    Comparison

    Examples
    --------
    >>> result = compare((4, 6), 0.05, frequency_hz=np.arange(700.0, 800.0, 5.0),
    ...                  truncation="paper")
    >>> [f"{result.response('eq26', 0.05, n).largest_error:.1e}" for n in (4, 6)]
    ['2.2e-04', '1.5e-05']
    """
    orders, pa_frac, tolerance = _checked(orders, pa_frac, tolerance)
    if frequency_hz is None:
        frequency_hz = np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + 1.0, 5.0)
    grid = lane_array("frequency_hz", frequency_hz, positive=True)
    if np.any(np.diff(grid) <= 0):
        raise ValueError("`frequency_hz` must be strictly increasing.")
    start = time.perf_counter()
    parameters = _compared_parameters(model, parameters)
    truncation = truncation_for(truncation, parameters).name  # a bad name: a ValueError
    for n in orders:  # before any work
        check_slow_order(n, "response", truncation, parameters, allow_slow=allow_slow)
    check_tested(grid, pa_frac, ContactModel(parameters), unchecked=unchecked)
    backbone = compare_backbones(orders, model=ContactModel(parameters), tolerance=tolerance,
                                 truncation=truncation, allow_slow=allow_slow)
    limits = dict(zip(backbone.orders, backbone.limit_app_m))
    bar = progress(len(MODELS), "compare: RK4 sweeps", quiet=quiet)
    by_model = {}
    for model in MODELS:  # all amplitudes and both directions of a model in one batch
        by_model[model] = steady_curves(grid, pa_frac, model, steps_per_period, parameters)
        bar.update()
    bar.close()
    curves = [by_model[model][i] for i in range(len(pa_frac)) for model in MODELS]
    # One series whatever the model it is compared with: solved once per amplitude and
    # order, for the curves of both models.
    series = {(frac, n): frequency_response(grid, frac, n, parameters=parameters,
                                            truncation=truncation, allow_slow=allow_slow)
              for frac in pa_frac for n in backbone.orders}
    responses = [compare_response(curve, n, grid, limits[n], parameters,
                                  response=series[curve.pa_frac, n])
                 for curve in curves for n in backbone.orders]
    settings = {"orders": list(orders), "pa_frac": list(pa_frac),
                "steps_per_period": steps_per_period, "tolerance": tolerance,
                "models": {name: asdict(effects) for name, effects in MODELS.items()},
                **truncation_settings(truncation)}
    return Comparison(model=ContactModel(parameters).as_dict(), settings=settings,
                      backbone=backbone, curves=curves, responses=responses, frequency_hz=grid,
                      tolerance=tolerance, elapsed_s=time.perf_counter() - start)
