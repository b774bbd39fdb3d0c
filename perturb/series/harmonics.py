"""Harmonic book-keeping: products of cosines as the paper writes them.

A ``Term`` is one summand of a right side of the order-by-order equations
(Eq. 2.9, 2.10, A.1, A.2)::

    number * prod(k_j, d_j) * prod(b_j) * prod(A_f) * cos(k Omega t + sum(sign_f phi_f))

where each factor ``f`` is one harmonic ``A_f cos(k_f Omega t + phi_f)`` of a
lower-order solution (a mean factor has no phase), or of its derivative, which
carries k_f Omega and pi/2 more phase (the damping terms d_j u^j u'). A product of two cosines is
split by ``cos a cos b = (cos(a + b) + cos(a - b)) / 2``, exactly as in the
paper's second lines of Eq. 2.9 and 2.10.

The same term has a complex value, with ``z_f = A_f exp(i phi_f)``:
``number * prod(k_j, d_j) * prod(b_j) * prod(z_f or conj(z_f))`` (times i k_f Omega
for a derivative), whose real part
times ``exp(i k Omega t)`` is the term; that form is the one that is compiled.

Examples
--------
>>> u0 = solution_term(0, 1)
>>> [str(term) for term in multiply(u0, u0)]
['A_0_1**2*cos(2*Omega*t + 2*phi_0_1)/2', 'A_0_1**2/2']
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, replace
from fractions import Fraction

import sympy as sp

from . import series_symbols as sym

__all__ = ["Factor", "Term", "solution_term", "multiply", "merge", "by_harmonic"]


@dataclass(frozen=True, order=True)
class Factor:
    """Harmonic ``harmonic`` of the order-``order`` solution, with phase sign ``sign``.

    A ``derivative`` factor is that harmonic of u_n', k Omega A cos(k Omega t + phi + pi/2)
    (the damping terms d_j u^j u' of the equation in contact); a mean has none.
    """

    order: int
    harmonic: int
    sign: int = 1
    derivative: bool = False

    @property
    def is_mean(self) -> bool:
        return self.harmonic == 0

    def angle(self) -> sp.Expr:
        """The phase this factor puts in the cosine: sign (phi_n_k + pi/2 if a derivative)."""
        phase = sym.phase(self.order, self.harmonic) + (sp.pi / 2 if self.derivative else 0)
        return self.sign * phase

    def scale(self) -> sp.Expr:
        """The factor's amplitude: A_n_k, times k Omega for a derivative."""
        amplitude = sym.amplitude(self.order, self.harmonic)
        return amplitude * self.harmonic * sym.Omega if self.derivative else amplitude

    def flipped(self) -> "Factor":
        return self if self.is_mean else replace(self, sign=-self.sign)


@dataclass(frozen=True)
class Term:
    """``number prod(k_j, d_j) prod(b) prod(A) cos(harmonic Omega t + phase)``.

    ``coefficients`` names the equation's coefficients in the product, ("k", j) for
    k_j (("k", 2) is Eq. 2.6's h) and ("d", j) for d_j, sorted.
    """

    number: Fraction
    harmonic: int
    factors: tuple[Factor, ...] = ()
    bs: tuple[int, ...] = ()
    coefficients: tuple[tuple[str, int], ...] = ()

    @property
    def key(self) -> tuple:
        return (self.harmonic, self.factors, self.bs, self.coefficients)

    @property
    def has_phase(self) -> bool:
        return any(not f.is_mean for f in self.factors)

    def scaled(self, number: Fraction, *, coefficients: tuple[tuple[str, int], ...] = (),
               bs: tuple[int, ...] = ()) -> "Term":
        return replace(
            self,
            number=self.number * number,
            coefficients=tuple(sorted(self.coefficients + coefficients)),
            bs=tuple(sorted(self.bs + bs)),
        )

    def _prefactor(self) -> sp.Expr:
        """number * prod(k_j, d_j) * prod(b_j): the part without amplitudes."""
        value = sp.Rational(self.number.numerator, self.number.denominator)
        value *= sp.Mul(*(sym.coefficient(kind, j) for kind, j in self.coefficients))
        return value * sp.Mul(*(sym.b(j) for j in self.bs))

    # -- the printed form (cosine with amplitude and phase) -------------
    def coefficient(self) -> sp.Expr:
        """The real coefficient in front of the cosine."""
        value = self._prefactor()
        for f in self.factors:
            value *= f.scale()
        return value

    def phase(self) -> sp.Expr:
        """The phase inside the cosine (a sum of +-phi_n_k, and +-pi/2 per derivative)."""
        return sp.Add(*(f.angle() for f in self.factors if not f.is_mean))

    # -- the complex form ----------------------------------------------
    def value(self, conjugate: bool = False) -> sp.Expr:
        """``coefficient * exp(i phase)`` written with z_n_k (or its conjugate)."""
        value = self._prefactor()
        for f in self.factors:
            if f.is_mean:
                value *= sym.amplitude(f.order, 0)
            else:
                conjugated = (f.sign < 0) != conjugate
                value *= sym.complex_amplitude(f.order, f.harmonic, conjugated)
                if f.derivative:  # d/dt of z exp(i k Omega t): i k Omega z (conjugated: -i)
                    value *= (-1 if conjugated else 1) * sp.I * f.harmonic * sym.Omega
        return value

    def printed(self) -> sp.Expr:
        """``coefficient * cos(k Omega t + phase)`` as a sympy expression of t."""
        angle = self.harmonic * sym.Omega * sym.t + self.phase()
        return self.coefficient() * sp.cos(angle)

    def __str__(self) -> str:
        return str(self.printed())


def solution_term(order: int, harmonic: int, derivative: bool = False) -> Term:
    """``A_n_k cos(k Omega t + phi_n_k)``, one harmonic of the order-n solution (or of
    its derivative, ``k Omega A_n_k cos(k Omega t + phi_n_k + pi/2)``)."""
    return Term(Fraction(1), harmonic, (Factor(order, harmonic, 1, derivative),))


def _canonical(number: Fraction, harmonic: int, factors: list[Factor], a: Term, b: Term) -> Term:
    if harmonic < 0:
        harmonic, factors = -harmonic, [f.flipped() for f in factors]
    factors = sorted(factors)
    if harmonic == 0:
        # cos(x) = cos(-x): the first factor with a phase carries a + sign.
        first = next((f for f in factors if not f.is_mean), None)
        if first is not None and first.sign < 0:
            factors = sorted(f.flipped() for f in factors)
    return Term(
        number,
        harmonic,
        tuple(factors),
        tuple(sorted(a.bs + b.bs)),
        tuple(sorted(a.coefficients + b.coefficients)),
    )


def multiply(a: Term, b: Term) -> list[Term]:
    """The product of two terms, split into harmonics (Eq. 2.9, 2.10)."""
    number = a.number * b.number
    if not a.has_phase or not b.has_phase:
        # A mean (or a bare coefficient) only scales the other cosine.
        harmonic = a.harmonic + b.harmonic
        return [_canonical(number, harmonic, [*a.factors, *b.factors], a, b)]
    half = number / 2
    total = _canonical(half, a.harmonic + b.harmonic, [*a.factors, *b.factors], a, b)
    differ = _canonical(
        half, a.harmonic - b.harmonic, [*a.factors, *(f.flipped() for f in b.factors)], a, b
    )
    return [total, differ]


def merge(terms: list[Term]) -> list[Term]:
    """Add the numbers of terms that differ only in their number; drop zeros."""
    sums: dict[tuple, Fraction] = defaultdict(Fraction)
    first: dict[tuple, Term] = {}
    for term in terms:
        sums[term.key] += term.number
        first.setdefault(term.key, term)
    return [replace(first[key], number=n) for key, n in sums.items() if n != 0]


def by_harmonic(terms: list[Term]) -> dict[int, list[Term]]:
    """Group terms by harmonic, in increasing harmonic order."""
    groups: dict[int, list[Term]] = defaultdict(list)
    for term in terms:
        groups[term.harmonic].append(term)
    return dict(sorted(groups.items()))
