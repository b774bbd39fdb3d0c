"""Which terms of the equation in contact a series keeps: the truncation.

In contact (y > 0) the model of Eq. 2.4, divided by M and written in u = y - y0,
is Eq. 2.5 carried on to every power:

    u'' + sum_{j>=1} k_j u^j + sum_{j>=0} d_j u^j u' = G cos(Omega t)

with k_j = -(1/M) (1/j!) d^j(F_s + Q)/dy^j and d_j = -(1/M) (1/j!) d^j(dF_d/dydot)/dy^j
at y0. For the power laws of Eq. 2.1,

    k_j = (S c_n / M) binom(m2, j) y0^(m2 - j),    d_j = (S h_n / M) binom(l, j) y0^(l - j),

so k_1 = omega0^2, k_2 = eps h, d_0 = 2c (Eq. 2.6). The sums end where a law is a
polynomial: k_j = 0 for j > m2 when m2 is an integer, d_j = 0 for j > l when l is one.

A series of order N counts k_j u^j at eps^(j-1) and d_j u^j u' at eps^j, so it carries
every term of the equation up to eps^N: the **consistent** truncation. The **paper**
truncation is Eq. 2.6: k_2 only and linear damping, which is the consistent one only
for m2 = 2 and l = 0. A ``Truncation`` records the highest j of each sum, which is all
that the derivation (``lindstedt.py``) needs to know.

Examples
--------
>>> truncation_for("paper")
Truncation(name='paper', spring_degree=2, damping_degree=0)
>>> from perturb.model.parameters import ContactParameters
>>> truncation_for("consistent", ContactParameters(m2=1.5, l=0.5))
Truncation(name='consistent', spring_degree=None, damping_degree=None)
>>> series_values(ContactParameters(m2=3.0)).coefficients((("k", 4), ("d", 2)))
(0.0, 0.0)
"""

from __future__ import annotations

from dataclasses import dataclass

from ..model.numbers import Eq26Numbers, eq26_numbers
from ..model.parameters import PAPER, ContactParameters

__all__ = ["Truncation", "TRUNCATIONS", "truncation_for", "binomial", "coefficient_closed_form",
           "SeriesValues", "series_values", "measures_model_distance", "truncation_settings"]

#: The truncations by name: "consistent" (every term up to the order) and "paper" (Eq. 2.6).
TRUNCATIONS = ("consistent", "paper")


@dataclass(frozen=True)
class Truncation:
    """The terms of the equation in contact that a series keeps.

    Attributes
    ----------
    name : str
        "consistent" or "paper".
    spring_degree : int or None
        The highest j of k_j u^j kept (None: every j that the order reaches).
    damping_degree : int or None
        The highest j of d_j u^j u' kept (0: linear damping; None: every j).
    """

    name: str
    spring_degree: int | None
    damping_degree: int | None

    def at_order(self, order: int) -> tuple[int, int]:
        """(highest j of k_j, highest j of d_j) that a series of ``order`` carries:
        k_j enters at eps^(j-1), d_j at eps^j."""
        spring = order + 1 if self.spring_degree is None else min(self.spring_degree, order + 1)
        damping = order if self.damping_degree is None else min(self.damping_degree, order)
        return max(spring, 1), max(damping, 0)

    def keeps_eq26_only(self, order: int) -> bool:
        """Whether a series of ``order`` keeps Eq. 2.6's terms and no more (h and linear
        damping): then it is Eq. 2.6's series, whatever the truncation's name."""
        return self.at_order(order) == PAPER_TRUNCATION.at_order(order)

    def coefficients(self, order: int) -> tuple[tuple[str, int], ...]:
        """The coefficients a series of ``order`` holds past c: ("k", 2) (h), the other
        k_j, then d_j, j >= 1 (the arguments of its numeric formulas after c)."""
        spring, damping = self.at_order(order)
        return (("k", 2), *(("k", j) for j in range(3, spring + 1)),
                *(("d", j) for j in range(1, damping + 1)))


#: Eq. 2.6: h u^2 and linear damping.
PAPER_TRUNCATION = Truncation("paper", 2, 0)


def _polynomial_degree(exponent: float) -> int | None:
    """The degree of y^exponent as a polynomial in u = y - y0, or None if it is none."""
    return int(exponent) if float(exponent).is_integer() else None


def truncation_for(name: str | Truncation, parameters: ContactParameters = PAPER) -> Truncation:
    """The truncation ``name`` ("consistent" or "paper") for the contact ``parameters``.

    The consistent truncation's sums end where the law is a polynomial (an integer m2
    or l); a ``Truncation`` is returned as it is.
    """
    if isinstance(name, Truncation):
        return name
    if name not in TRUNCATIONS:
        raise ValueError(f"`truncation` must be one of {list(TRUNCATIONS)}, got {name!r}.")
    if not isinstance(parameters, ContactParameters):
        raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
    if name == "paper":
        return PAPER_TRUNCATION
    return Truncation("consistent", _polynomial_degree(parameters.m2),
                      _polynomial_degree(parameters.l))


def truncation_settings(name: str) -> dict[str, str]:
    """The ``settings`` entry a result records for the truncation ``name``: none for the
    paper's, so that Eq. 2.6's results read as they always did (their model's effects,
    ``EQ_2_6``, say it), ``{"truncation": name}`` otherwise."""
    return {} if name == "paper" else {"truncation": name}


def measures_model_distance(order: int, parameters: ContactParameters) -> bool:
    """Whether the error of Eq. 2.6's order-N series at ``parameters`` includes
    ``model_distance``: not on the paper's own contact (m2 = 2, l = 1), whose flags are
    the paper's, nor where the consistent series is Eq. 2.6's (m2 = 2, l = 0)."""
    if (parameters.m2, parameters.l) == (2.0, 1.0):
        return False
    return not truncation_for("consistent", parameters).keeps_eq26_only(order + 2)


def binomial(exponent: float, j: int) -> float:
    """binom(exponent, j) = exponent (exponent - 1) ... (exponent - j + 1) / j!."""
    value = 1.0
    for i in range(j):
        value *= (exponent - i) / (i + 1)
    return value


def coefficient_closed_form(kind: str, j: int):
    """k_j or d_j as an expression of S, c_n, m2, h_n, l, M and y0 (sympy), Taylor's
    coefficient of the model's own force law (``ContactModel``) at y0."""
    import sympy as sp

    from ..model.contact_model import ContactModel
    from ..model.symbols import M, g, v, y

    y0 = sp.Symbol("y0", positive=True)
    model = ContactModel()
    if kind == "k":
        law = model.power_spring(y) + M * g
    else:
        law = sp.diff(model.power_damping(y, v), v)
    value = -sp.diff(law, y, j).subs(y, y0) / (sp.factorial(j) * M)
    return sp.simplify(value)


@dataclass(frozen=True)
class SeriesValues(Eq26Numbers):
    """The numbers of Eq. 2.6 at one contact, and the other k_j, d_j of its equation in
    contact, which a series' formulas take after c (``coefficients``)."""

    parameters: ContactParameters = PAPER

    def coefficients(self, names: tuple[tuple[str, int], ...]) -> tuple[float, ...]:
        """The values of ``names`` (("k", j) or ("d", j)), in order, in closed form (the
        module's docstring), without sympy; h is Eq. 2.6's own number.
        tests/test_truncation.py holds them against the Taylor coefficients that sympy
        derives from ``ContactModel``."""
        return tuple(self.h_per_m_s2 if name == ("k", 2) else self._value(*name)
                     for name in names)

    def _value(self, kind: str, j: int) -> float:
        p, y0 = self.parameters, self.y0_m
        try:
            if kind == "k":
                value = p.S * p.c_n / p.M * binomial(p.m2, j) * y0 ** (p.m2 - j)
            else:
                value = p.S * p.h_n / p.M * binomial(p.l, j) * y0 ** (p.l - j)
        except OverflowError:  # y0^(m2 - j): a series of this order needs it
            raise ValueError(f"`order` is too high for numbers at this contact: {kind}_{j} "
                             f"(y0 = {y0:.3g} m) leaves the floating-point range") from None
        return 0.0 if value == 0 else float(value)


def series_values(parameters: ContactParameters = PAPER) -> SeriesValues:
    """``SeriesValues`` at ``parameters`` (Eq. 2.6's numbers from ``eq26_numbers``)."""
    return SeriesValues(**eq26_numbers(parameters).as_dict(), parameters=parameters)
