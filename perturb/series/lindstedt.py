"""The order-by-order Lindstedt-type derivation of Eq. 2.6 (Eq. 2.7-2.10, A.1, A.2).

With omega^2 = omega0^2 + sum_k eps^k b_k and u = sum_n eps^n u_n (Eq. 2.7),
Eq. 2.6 is written ``u'' + 2c u' + omega^2 u = G cos(Omega t) +
(sum_k eps^k b_k) u - eps h u^2``, and collecting powers of eps gives, at order n,

    u_n'' + 2c u_n' + omega^2 u_n = sum_{k=1..n} b_k u_{n-k} - h sum_{i+j=n-1} u_i u_j

(plus G cos(Omega t) at order 0). Each right side is split into harmonics of
the excitation; b_n removes the part of the fundamental that is in phase with
u0 (which gives b2 = 2 h A2 + h A1 cos(phi1), Eq. 2.10); every harmonic k is
then solved in closed form by the linear transfer
``1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega) = H_k exp(i theta_k)``.

Examples
--------
>>> series = derive(4, "paper")
>>> series
Series(order=4, b=[0, b_2, 0, b_4], harmonics=[(1,), (0, 2), (1, 3), (0, 2, 4), (1, 3, 5)])
>>> series.b_closed_form(2)
2*A_1_0*h + A_1_2*h*cos(2*phi_0_1 - phi_1_2)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import sympy as sp

from perturb.common import check_int

from ..model import symbols as model_symbols
from ..model.eq26 import Eq26
from ..model.parameters import PAPER, ContactParameters
from . import series_symbols as sym
from .harmonics import Term, by_harmonic, merge, multiply, solution_term
from .truncation import PAPER_TRUNCATION, Truncation, truncation_for

__all__ = ["derive", "Series", "OrderEquation", "transfer", "gain_closed_form", "lag_closed_form"]
__all__ += ["equation_2_6", "eq26_substitution"]


def transfer(k: int) -> sp.Expr:
    """1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega): the linear response to harmonic k."""
    return 1 / (sym.omega**2 - k**2 * sym.Omega**2 + 2 * sp.I * k * sym.c * sym.Omega)


def gain_closed_form(k: int) -> sp.Expr:
    """H_k = |transfer(k)|."""
    return 1 / sp.sqrt(
        (sym.omega**2 - k**2 * sym.Omega**2) ** 2 + 4 * k**2 * sym.c**2 * sym.Omega**2
    )


def lag_closed_form(k: int) -> sp.Expr:
    """theta_k = arg transfer(k), in (-pi, 0]."""
    return -sp.atan2(2 * k * sym.c * sym.Omega, sym.omega**2 - k**2 * sym.Omega**2)


@dataclass(frozen=True)
class OrderEquation:
    """The order-n equation: its right side by harmonic, and what fixes b_n.

    Attributes
    ----------
    order : int
    rhs : dict of int to list of Term
        Right side by harmonic (the b_n u0 term included when b_n != 0).
    b_sources : list of Term
        The harmonic-1 terms other than b_n u0; b_n cancels their part in phase
        with u0 and is zero when there are none.
    """

    order: int
    rhs: dict[int, list[Term]]
    b_sources: list[Term]

    @property
    def has_b(self) -> bool:
        return bool(self.b_sources)

    @property
    def harmonics(self) -> tuple[int, ...]:
        return tuple(self.rhs)


def _right_side(order: int, solutions: list[tuple[int, ...]], has_b: list[bool],
                products: _Products) -> list[Term]:
    """sum_{k=1..n-1} b_k u_{n-k} - h sum_{i+j=n-1} u_i u_j (without b_n u0), and the
    terms of the equation in contact that Eq. 2.6 leaves out, where the truncation keeps
    them: - k_j (u^j)_(n-j+1) for j >= 3 and - d_j (u^j u')_(n-j) for j >= 1 (h u^2 is
    k_2's)."""
    terms: list[Term] = []
    for k in range(1, order):
        if has_b[k]:
            terms += [
                solution_term(order - k, m).scaled(Fraction(1), bs=(k,))
                for m in solutions[order - k]
            ]
    spring, damping = products.degrees
    # j = 2: - h sum_{i+j=n-1} u_i u_j, Eq. 2.9, 2.10, A.1, A.2.
    for j in range(2, min(spring, order + 1) + 1):
        terms += [p.scaled(Fraction(-1), coefficients=(("k", j),))
                  for p in products.power(j, order - j + 1)]
    for j in range(1, min(damping, order) + 1):
        terms += [p.scaled(Fraction(-1), coefficients=(("d", j),))
                  for p in products.with_velocity(j, order - j)]
    return merge(terms)


class _Products:
    """(u^j)_m and (u^j u')_m: the terms of eps^m in u^j and u^j u', for the solutions
    known so far, each computed once (every later order reuses them)."""

    def __init__(self, solutions: list[tuple[int, ...]], degrees: tuple[int, int]) -> None:
        self.solutions = solutions
        self.degrees = degrees
        self._powers: dict[tuple[int, int], list[Term]] = {}
        self._velocity: dict[tuple[int, int], list[Term]] = {}

    def _times(self, terms: list[Term], m: int, derivative: bool) -> list[Term]:
        out: list[Term] = []
        for k in self.solutions[m]:
            if derivative and k == 0:
                continue  # a mean has no derivative
            factor = solution_term(m, k, derivative)
            for term in terms:
                out += multiply(term, factor)
        return out

    def power(self, j: int, m: int) -> list[Term]:
        """The terms of eps^m in u^j = (sum_i eps^i u_i)^j."""
        if j == 1:
            return [solution_term(m, k) for k in self.solutions[m]]
        if (j, m) not in self._powers:
            terms: list[Term] = []
            for i in range(m + 1):
                terms += self._times(self.power(j - 1, m - i), i, False)
            self._powers[(j, m)] = merge(terms)
        return self._powers[(j, m)]

    def with_velocity(self, j: int, m: int) -> list[Term]:
        """The terms of eps^m in u^j u'."""
        if (j, m) not in self._velocity:
            terms: list[Term] = []
            for i in range(m + 1):
                terms += self._times(self.power(j, m - i), i, True)
            self._velocity[(j, m)] = merge(terms)
        return self._velocity[(j, m)]


def _derive_orders(order: int, truncation: Truncation) -> list[OrderEquation]:
    # Eq. 2.8: u0 = A0 cos(Omega t + phi0), the linear response to G cos(Omega t).
    equations = [OrderEquation(0, {1: []}, [])]
    solutions: list[tuple[int, ...]] = [(1,)]
    has_b = [False]
    products = _Products(solutions, truncation.at_order(order))
    for n in range(1, order + 1):
        terms = by_harmonic(_right_side(n, solutions, has_b, products))
        sources = list(terms.get(1, []))
        if sources:
            # b_n u0 joins the fundamental; b_n is fixed below (Eq. 2.10, A.2).
            terms[1] = sources + [solution_term(0, 1).scaled(Fraction(1), bs=(n,))]
        equations.append(OrderEquation(n, terms, sources))
        solutions.append(tuple(terms))
        has_b.append(bool(sources))
    return equations


class Series:
    """The perturbation series of the equation in contact to a given order, once derived.

    Use :func:`derive`, which caches the result. Every closed form is written
    with the systematic names of ``perturb.series.series_symbols``: A_n_k, phi_n_k
    (solution), F_n_k, psi_n_k (right side), b_n, H_k and theta_k (transfer),
    and the equation's coefficients h = k_2, k_j and d_j that ``truncation`` keeps.
    """

    def __init__(self, order: int, truncation: Truncation = PAPER_TRUNCATION) -> None:
        self.order = sym.check_order(order)
        self.truncation = truncation
        self.equations = _derive_orders(self.order, truncation)
        #: Whether the series keeps Eq. 2.6's terms only (h and linear damping).
        self.is_eq26 = truncation.keeps_eq26_only(order)

    @property
    def coefficients(self) -> tuple[tuple[str, int], ...]:
        """The equation's coefficients the series holds past c: ("k", j) for k_j, j >= 2,
        then ("d", j) for d_j, j >= 1 (the compiled formulas' arguments after c)."""
        return self.truncation.coefficients(self.order)

    # -- structure -----------------------------------------------------------
    def harmonics(self, n: int) -> tuple[int, ...]:
        """Harmonics of the order-n solution u_n."""
        return self.equations[self._check_n(n)].harmonics

    def has_b(self, n: int) -> bool:
        """Whether b_n is non-zero (b_1 = b_3 = ... = 0: no fundamental at odd orders)."""
        n = self._check_n(n)
        return n >= 1 and self.equations[n].has_b

    def _check_n(self, n: int) -> int:
        return check_int("n", n, minimum=0, maximum=self.order)

    def _rhs(self, n: int, k: int) -> list[Term]:
        """The terms of harmonic k of the order-n right side; a KeyError lists the harmonics."""
        rhs = self.equations[self._check_n(n)].rhs
        if k not in rhs:
            raise KeyError(f"no harmonic k={k!r} at order n={n}; available: {sorted(rhs)}")
        return rhs[k]

    # -- closed forms in the systematic names --------------------------------
    def b_closed_form(self, n: int) -> sp.Expr:
        """b_n = -(1/A0) sum of the fundamental's parts in phase with u0 (Eq. 2.10, A.2)."""
        if not self.has_b(n):
            return sp.Integer(0)
        phi0 = sym.phase(0, 1)
        in_phase = sum(
            t.coefficient() * sp.cos(t.phase() - phi0) for t in self.equations[n].b_sources
        )
        return sp.expand(-in_phase / sym.amplitude(0, 1))

    def rhs_cosines(self, n: int, k: int) -> sp.Expr:
        """Harmonic k of the order-n right side, as a sum of cosines of t."""
        return sp.Add(*(term.printed() for term in self._rhs(n, k)))

    def forcing_closed_form(self, n: int, k: int) -> tuple[sp.Expr, sp.Expr]:
        """(F_n_k, psi_n_k) with F cos(k Omega t + psi) = harmonic k of the right side."""
        terms = self._rhs(n, k)
        if k and len(terms) == 1 and not terms[0].bs:
            # One cosine of known sign: its size, and pi more phase if negative.
            (term,) = terms
            flip = sp.pi if term.number < 0 else 0
            return sp.Abs(term.coefficient()), term.phase() + flip
        cos_part = sp.Add(*(t.coefficient() * sp.cos(t.phase()) for t in terms))
        if k == 0:
            return cos_part, sp.Integer(0)
        sin_part = sp.Add(*(t.coefficient() * sp.sin(t.phase()) for t in terms))
        return sp.sqrt(cos_part**2 + sin_part**2), sp.atan2(sin_part, cos_part)

    def solution_closed_form(self, n: int, k: int) -> tuple[sp.Expr, sp.Expr]:
        """(A_n_k, phi_n_k) of u_n in closed form of F_n_k, psi_n_k, H_k, theta_k."""
        self._rhs(n, k)  # a KeyError for a harmonic u_n does not have
        if n == 0:
            # Eq. 2.8: A0 = G H_1, phi0 = theta_1.
            return sym.G * sym.gain(1), sym.lag(1)
        if k == 0:
            return sym.forcing_amplitude(n, 0) / sym.omega**2, sp.Integer(0)
        return sym.gain(k) * sym.forcing_amplitude(n, k), sym.forcing_phase(n, k) + sym.lag(k)

    def solution(self, n: int) -> sp.Expr:
        """u_n = sum_k A_n_k cos(k Omega t + phi_n_k)."""
        return sp.Add(*(solution_term(n, k).printed() for k in self.harmonics(n)))

    def displacement(self) -> sp.Expr:
        """u = sum_n eps^n u_n, the reconstructed multiharmonic response (Eq. 2.7)."""
        return sp.Add(*(sym.eps**n * self.solution(n) for n in range(self.order + 1)))

    def omega_squared(self) -> sp.Expr:
        """omega^2 = omega0^2 + sum eps^n b_n, the non-zero b only (Eq. 2.7)."""
        return sym.omega0**2 + sp.Add(
            *(sym.eps**n * sym.b(n) for n in range(1, self.order + 1) if self.has_b(n))
        )

    def __repr__(self) -> str:
        bs = [sym.b(n) if self.has_b(n) else 0 for n in range(1, self.order + 1)]
        harmonics = [self.harmonics(n) for n in range(self.order + 1)]
        kept = "" if self.is_eq26 else (
            f", truncation={self.truncation.name!r}, "
            f"terms={[str(sym.coefficient(*c)) for c in self.coefficients]}")
        return f"Series(order={self.order}, b={bs}, harmonics={harmonics}{kept})"


def equation_2_6(u: sp.Expr) -> sp.Expr:
    """Left minus right side of Eq. 2.6 in the series' symbols (eps = 1)."""
    t = sym.t
    return (
        sp.diff(u, t, 2)
        + 2 * sym.c * sp.diff(u, t)
        + sym.omega0**2 * u
        + sym.h * u**2
        - sym.G * sp.cos(sym.Omega * t)
    )


def eq26_substitution(eq: Eq26) -> dict[sp.Symbol, sp.Expr]:
    """The series' symbols c, h, G, omega0, Omega, t as the model's expressions.

    The series is derived for Eq. 2.6 with these coefficients; ``Eq26`` derives
    them from the physical model (Eq. 2.5), so that substituting this map into
    :func:`equation_2_6` gives ``Eq26.equation``.

    Examples
    --------
    >>> subs = eq26_substitution(Eq26())
    >>> subs[sym.Omega]
    2*pi*f_e
    """
    return {
        sym.c: eq.c,
        sym.h: eq.h,
        sym.G: eq.G,
        sym.omega0: sp.sqrt(eq.omega0_squared),
        sym.Omega: 2 * sp.pi * model_symbols.f_e,
        sym.t: model_symbols.t,
    }


def derive(order: int, truncation: str | Truncation = "consistent",
           parameters: ContactParameters = PAPER) -> Series:
    """Derive the series of the equation in contact to ``order`` (cached: a second call
    is free).

    Parameters
    ----------
    order : int
        The highest power N of eps kept, N >= 0.
    truncation : {"consistent", "paper"} or Truncation
        "consistent": every term k_j u^j (at eps^(j-1)) and d_j u^j u' (at eps^j) of the
        equation in contact up to eps^N; "paper": Eq. 2.6 (h = k_2 and linear damping).
    parameters : ContactParameters
        The contact, which tells where its laws' Taylor series end (an integer m2 or l):
        the consistent series of the paper's contact has h and d_1 only.

    Returns
    -------
    Series

    Examples
    --------
    >>> derive(2, "paper").harmonics(2)
    (1, 3)
    >>> derive(2).coefficients  # the paper's contact: h and d_1 (l = 1)
    (('k', 2), ('d', 1))
    >>> derive(-1)
    Traceback (most recent call last):
    ...
    ValueError: `order` must be an integer >= 0, got -1.
    """
    order = sym.check_order(order)
    resolved = truncation_for(truncation, parameters)
    return _derive(order, resolved.name, *resolved.at_order(order))


@lru_cache(maxsize=None)
def _derive(order: int, name: str, spring: int, damping: int) -> Series:
    return Series(order, Truncation(name, spring, damping))
