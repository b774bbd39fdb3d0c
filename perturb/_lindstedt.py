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
>>> series = derive(4)
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

from common import check_int

from . import _series_symbols as sym
from . import _symbols as model_symbols
from ._eq26 import Eq26
from ._harmonics import Term, by_harmonic, merge, multiply, solution_term

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


def _right_side(order: int, solutions: list[tuple[int, ...]], has_b: list[bool]) -> list[Term]:
    """sum_{k=1..n-1} b_k u_{n-k} - h sum_{i+j=n-1} u_i u_j (without b_n u0)."""
    terms: list[Term] = []
    for k in range(1, order):
        if has_b[k]:
            terms += [
                solution_term(order - k, m).scaled(Fraction(1), bs=(k,))
                for m in solutions[order - k]
            ]
    for i in range(order):
        j = order - 1 - i
        for ki in solutions[i]:
            for kj in solutions[j]:
                products = multiply(solution_term(i, ki), solution_term(j, kj))
                terms += [p.scaled(Fraction(-1), h_power=1) for p in products]
    return merge(terms)


def _derive_orders(order: int) -> list[OrderEquation]:
    # Eq. 2.8: u0 = A0 cos(Omega t + phi0), the linear response to G cos(Omega t).
    equations = [OrderEquation(0, {1: []}, [])]
    solutions: list[tuple[int, ...]] = [(1,)]
    has_b = [False]
    for n in range(1, order + 1):
        terms = by_harmonic(_right_side(n, solutions, has_b))
        sources = list(terms.get(1, []))
        if sources:
            # b_n u0 joins the fundamental; b_n is fixed below (Eq. 2.10, A.2).
            terms[1] = sources + [solution_term(0, 1).scaled(Fraction(1), bs=(n,))]
        equations.append(OrderEquation(n, terms, sources))
        solutions.append(tuple(terms))
        has_b.append(bool(sources))
    return equations


class Series:
    """The perturbation series of Eq. 2.6 to a given order, once derived.

    Use :func:`derive`, which caches the result. Every closed form is written
    with the systematic names of ``perturb._series_symbols``: A_n_k, phi_n_k
    (solution), F_n_k, psi_n_k (right side), b_n, H_k and theta_k (transfer).
    """

    def __init__(self, order: int) -> None:
        self.order = sym.check_order(order)
        self.equations = _derive_orders(self.order)

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
        return f"Series(order={self.order}, b={bs}, harmonics={harmonics})"


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


@lru_cache(maxsize=None)
def derive(order: int) -> Series:
    """Derive the series of Eq. 2.6 to ``order`` (cached: a second call is free).

    Parameters
    ----------
    order : int
        The highest power N of eps kept, N >= 0.

    Returns
    -------
    Series

    Examples
    --------
    >>> derive(2).harmonics(2)
    (1, 3)
    >>> derive(-1)
    Traceback (most recent call last):
    ...
    ValueError: `order` must be an integer >= 0, got -1.
    """
    return Series(sym.check_order(order))
