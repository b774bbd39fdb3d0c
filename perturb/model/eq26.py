"""Eq. 2.6 derived from the physical model, not typed by hand.

With u = y - y0, the conservative force F_k = F_s + Q is expanded in a Taylor
series about the static deflection y0, and the damping force F_d is
linearised there (Eq. 2.5). Divided by M, Eq. 2.4 becomes

    u'' + 2c u' + omega0^2 u + eps*h u^2 = G cos(2 pi f_e t)       (Eq. 2.6)

Each coefficient below is a derivative of a force of ``ContactModel``; their
values at a parameter set are one object, ``Eq26Numbers``: ``derive_numbers``
derives it, and ``eq26_numbers`` (``numbers.py``) keeps it on disk.
"""

from __future__ import annotations

import math
from functools import cache, cached_property

import sympy as sp

from .contact_model import ContactModel
from .numbers import Eq26Numbers, eq26_numbers
from .parameters import PAPER, ContactParameters
from .symbols import M, P_a, f_e, g, t, v, y

__all__ = ["Eq26", "Eq26Numbers", "eq26_numbers", "derive_numbers"]


# The symbolic laws do not depend on the parameter values: each derivation below
# is done once per process, whatever the parameters.
@cache
def _force_derivative(order: int) -> sp.Expr:
    """d^k F_k / dy^k at y0, with F_k = F_s + Q in contact (Eq. 2.3)."""
    model = ContactModel()
    force = model.power_spring(y) + M * g
    return sp.simplify(sp.diff(force, y, order).subs(y, model.static_deflection))


@cache
def _stiffness_coefficient(j: int) -> sp.Expr:
    return sp.simplify(-_force_derivative(j) / (sp.factorial(j) * M))


@cache
def _two_c() -> sp.Expr:
    model = ContactModel()
    damping = model.power_damping(y, v)
    return sp.simplify(-sp.diff(damping, v).subs(y, model.static_deflection) / M)


def derive_numbers(parameters: ContactParameters = PAPER) -> Eq26Numbers:
    """The numbers of Eq. 2.6 at ``parameters``, derived by sympy (no cache: this is
    what ``eq26_numbers`` stores on disk the first time it sees ``parameters``)."""
    eq = Eq26(ContactModel(parameters))
    value = eq.model.evaluate
    omega0 = math.sqrt(value(eq.omega0_squared))
    c = value(eq.c)
    return Eq26Numbers(
        y0_m=value(eq.y0),  # the closed form of the static deflection: y0's one route
        f_n0_hz=omega0 / (2 * math.pi),
        omega0_rad_s=omega0,
        Q_n=parameters.Q_n,
        c_per_s=c,
        h_per_m_s2=value(eq.h),
        damping_ratio=c / omega0,
        G_per_P_a=value(eq.G / P_a),
    )


class Eq26:
    """Coefficients of Eq. 2.6, as expressions of the model's symbols.

    Parameters
    ----------
    model : ContactModel
        The physical model; its spring and damping are taken in their full
        (power-law) form, as the paper does, whatever its effects say.

    Examples
    --------
    >>> eq = Eq26()
    >>> eq.omega0_squared
    g*m2*(S*c_n/(M*g))**(1/m2)
    >>> round(eq.numbers().f_n0_hz, 2)
    1485.59
    """

    def __init__(self, model: ContactModel | None = None) -> None:
        if model is not None and not isinstance(model, ContactModel):
            raise ValueError(f"`model` must be a ContactModel, got {model!r}.")
        base = model if model is not None else ContactModel()
        # Eq. 2.5 expands the full laws, so derive from the power-law model.
        self.model = ContactModel(base.parameters)

    @cached_property
    def y0(self) -> sp.Expr:
        return self.model.static_deflection

    def force_derivative(self, order: int) -> sp.Expr:
        """d^k F_k / dy^k at y0."""
        return _force_derivative(order)

    def stiffness_coefficients(self, degree: int) -> list[sp.Expr]:
        """k_j with F_k(y0 + u)/M = -sum_j k_j u^j, for j = 0..degree (Eq. 2.5)."""
        return [_stiffness_coefficient(j) for j in range(degree + 1)]

    @cached_property
    def omega0_squared(self) -> sp.Expr:
        """omega0^2 = M^-1 S c_n m2 y0^(m2-1) (Eq. 2.6)."""
        return self.stiffness_coefficients(1)[1]

    @cached_property
    def h(self) -> sp.Expr:
        """eps*h = (1/2) M^-1 S c_n m2 (m2-1) y0^(m2-2) (Eq. 2.6)."""
        return self.stiffness_coefficients(2)[2]

    @property
    def two_c(self) -> sp.Expr:
        """2c = M^-1 S h_n y0^l: minus d F_d / d ydot at y0, over M (Eq. 2.5, 2.6)."""
        return _two_c()

    @cached_property
    def c(self) -> sp.Expr:
        return self.two_c / 2

    @cached_property
    def G(self) -> sp.Expr:
        """G = P_a / M (Eq. 2.6)."""
        return sp.diff(self.model.drive, P_a).subs(t, 0) * P_a / M

    @cached_property
    def static_residual(self) -> sp.Expr:
        """F_k(y0)/M, which vanishes: y0 is an equilibrium."""
        return sp.simplify(self.stiffness_coefficients(0)[0])

    def equation(self, u_func: sp.Function | None = None) -> sp.Expr:
        """The left side minus the right side of Eq. 2.6, in u(t)."""
        uf = u_func if u_func is not None else sp.Function("u")(t)
        return (
            sp.diff(uf, t, 2)
            + self.two_c * sp.diff(uf, t)
            + self.omega0_squared * uf
            + self.h * uf**2
            - self.G * sp.cos(2 * sp.pi * f_e * t)
        )

    def numbers(self) -> Eq26Numbers:
        """The coefficients' values at the model's parameters (``eq26_numbers``)."""
        return eq26_numbers(self.model.parameters)

    def __repr__(self) -> str:
        return f"Eq26({self.model!r})"

