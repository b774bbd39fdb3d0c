"""The conservative force of the model in units of the weight, about y0.

With the static deflection y0 as the unit of length, sigma = y / y0 - 1, and
sqrt(y0 / g) as the unit of time, Eq. 2.4 without damping and drive becomes

    sigma'' = -r(sigma),   r(sigma) = -F_k(y0 (1 + sigma)) / (M g)    (Eq. 2.3)

with r = (1 + sigma)^m2 - 1 in contact and r = -1 in free flight (sigma <= -1).
``r`` is derived here from ``perturb.ContactModel`` and rewritten by sympy as
``expm1(m2 * log1p(sigma))``, so that it keeps full relative accuracy at tiny
sigma, where ``(1 + sigma)^m2 - 1`` would cancel catastrophically.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp
from sympy.codegen.rewriting import expm1_opt, log1p_opt, optimize

from perturb import ContactModel, eq26_numbers
from perturb import symbols as sym

__all__ = ["Restoring", "restoring_force"]

_SIGMA = sp.Symbol("sigma", real=True)


@dataclass(frozen=True)
class Restoring:
    """The scaled conservative force of a model, and its scales.

    Attributes
    ----------
    y0_m : float
        Static deflection y0 [m], the unit of length.
    time_unit_s : float
        sqrt(y0 / g) [s], the unit of time.
    contact : callable
        r(sigma) for sigma >= -1 (in contact), vectorised.
    flight : float
        r in free flight (sigma < -1): -1, the weight alone.
    expression : sympy.Expr
        r(sigma) in contact, as evaluated.
    """

    y0_m: float
    time_unit_s: float
    contact: Callable[[np.ndarray], np.ndarray]
    flight: float
    expression: sp.Expr

    def __call__(self, sigma: np.ndarray) -> np.ndarray:
        """r(sigma) on both sides of the contact edge sigma = -1."""
        sigma = np.asarray(sigma, dtype=float)
        inside = sigma > -1.0
        return np.where(inside, self.contact(np.where(inside, sigma, 0.0)), self.flight)


def _check_effects(model: ContactModel) -> None:
    effects = model.effects
    if effects.spring != "power" or not effects.gravity or not effects.contact_loss:
        raise ValueError(
            "the exact backbone needs the power-law spring with gravity and contact "
            f"loss (damping is dropped); got `model` with effects {effects.describe()!r}."
        )


def _scaled_contact_force(model: ContactModel) -> sp.Expr:
    """r(sigma) in contact, symbolic in m2: -F_k(y0 x) / (M g) with x = 1 + sigma."""
    x = sp.Symbol("x", positive=True)
    conservative = model.spring_law(sym.y) + model.gravity_force  # F_k, Eq. 2.3
    scaled = -conservative.subs(sym.y, model.static_deflection * x) / (sym.M * sym.g)
    scaled = sp.powsimp(sp.expand_power_base(sp.expand(scaled), force=True), force=True)
    # x^m2 - 1 = expm1(m2 log1p(sigma)): exact at tiny sigma, for any m2.
    as_exp = scaled.replace(
        lambda e: e.is_Pow and e.base == x, lambda e: sp.exp(e.exp * sp.log(e.base))
    )
    return optimize(as_exp.subs(x, 1 + _SIGMA), [log1p_opt, expm1_opt])


def restoring_force(model: ContactModel | None = None) -> Restoring:
    """The scaled restoring force r(sigma) of a model's conservative part.

    Parameters
    ----------
    model : ContactModel, optional
        Needs the power-law spring, gravity and contact loss; damping is
        ignored. The paper's model by default.

    Returns
    -------
    Restoring

    Examples
    --------
    >>> r = restoring_force()
    >>> r.expression
    expm1(2*log1p(sigma))
    >>> [float(x) for x in r([-2.0, -1.0, 1e-12, 1.0])]
    [-1.0, -1.0, 2.000000000001e-12, 3.0]
    """
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    _check_effects(model)
    contact = _scaled_contact_force(model).subs(model.values)
    flight = -model.gravity_force / (sym.M * sym.g)  # the weight alone, Eq. 2.1 with y <= 0
    y0 = eq26_numbers(model.parameters).y0_m  # y0's one route
    g = model.parameters.g
    return Restoring(
        y0_m=y0,
        time_unit_s=math.sqrt(y0 / g),
        contact=sp.lambdify(_SIGMA, contact, modules="numpy"),
        flight=float(flight),
        expression=contact,
    )
