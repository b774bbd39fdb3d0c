"""The derivation study: the series of Eq. 2.6 order by order, step by step, in the paper's names.

For each order n the derivation shows four steps, as Eq. 2.8-2.10, A.1 and A.2 do:

1. the equation of order eps^n, its right side from b_k and products of the lower
   orders (``u2'' + 2*c*u2' + omega**2*u2 = b1*u1 + b2*u0 - 2*h*u0*u1``), then
   with the lower orders put in;
2. that right side split into harmonics of Omega t (cos a cos b = (cos(a + b) +
   cos(a - b))/2), each harmonic as a sum of cosines;
3. the secular condition: the part of harmonic 1 in phase with u0 must vanish,
   which gives b_n (b_n = 0 at odd orders, which hold no other harmonic 1);
4. the solution u_n, each harmonic k through the transfer H_k exp(i theta_k)
   (a mean through 1/omega^2), with the closed form of every amplitude and phase.

Names are the paper's up to order 4 (A0-A19, phi0-phi9, b1-b4, read as
``names`` documents: signed amplitudes, phi0, phi1, phi2, phi5, phi9 the
transfer phases theta_1..theta_5) and the engine's beyond (A_n_k, F_n_k, psi_n_k,
b_n, theta_k). The paper has no name for the gain H_k of the transfer, so H_k it is.
Orders 0-2 are solved term by term as Eq. 2.8-2.10 do (each cosine of the right
side through the transfer of its harmonic: A1, ..., A7); from order 3 on, as A.1 and
A.2 do, each harmonic k of the right side is first gathered into one
F cos(k Omega t + psi) (A8 cos(...), A9 cos(2 Omega t + phi3), ...). A phase of
u_n is then written as the paper writes it, the right side's phase plus the
transfer's: u3 = A11 + A12 cos(2 Omega t + phi3 + phi1) + ..., and so on past the
paper's order (A_5_2 cos(2 Omega t + psi_5_2 + phi1)).

The consistent series of a contact (``derive(order, "consistent", parameters)``) is
studied the same way, in the engine's names: its extra terms (k_j u^j, d_j u^j u', a
derivative written k Omega A cos(k Omega t + phi + pi/2)) do not fit the paper's, so
every order's harmonics are gathered into F_n_k cos(k Omega t + psi_n_k) as A.1 and A.2
do, from order 0 on.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp

from ..series import series_symbols as sym
from ..series.harmonics import Term
from ..series.lindstedt import Series, gain_closed_form, lag_closed_form
from .names import paper_names
from .report import (
    check_series,
    equation_line,
    generic_right_side,
    latex_of,
    left_side_latex,
    left_side_text,
    split_row,
)

__all__ = ["derivation_text", "derivation_latex"]

#: The highest order the paper writes out, and the equation of each of its orders.
PAPER_ORDER = 4
EQUATIONS = ("2.8", "2.9", "2.10", "A.1", "A.2")
#: Orders 0-2 are solved term by term (Eq. 2.8-2.10), later ones harmonic by harmonic.
TERMWISE_ORDERS = 3

#: (amplitude, phase) of ``amplitude * cos(k Omega t + phase)``; a mean has phase 0.
Part = tuple[sp.Expr, sp.Expr]


def _paper(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


def _termwise_parts() -> dict[tuple[int, int], list[Part]]:
    """u0, u1 and u2 as Eq. 2.8-2.10 write them, by (order, harmonic)."""
    A = [_paper(f"A{i}") for i in range(8)]
    phi = [_paper(f"phi{i}") for i in range(3)]
    return {
        (0, 1): [(A[0], phi[0])],
        (1, 0): [(A[2], sp.Integer(0))],
        (1, 2): [(A[1], 2 * phi[0] + phi[1])],
        (2, 1): [(A[7], 2 * phi[0]), (A[5], 2 * phi[0] + phi[1])],
        (2, 3): [(A[6], 3 * phi[0] + phi[1] + phi[2])],
    }


#: Eq. 2.10 first writes A7 cos(...) as A3 cos(...) + A4 cos(...): A3 from b2 u0, A4 the rest.
SPLIT = {"A7": ("A3", "A4")}


def _cosines(k: int, parts: list[Part]) -> sp.Expr:
    return sp.Add(*(a * sp.cos(k * sym.Omega * sym.t + x) for a, x in parts))


@dataclass(frozen=True)
class _Row:
    """``left = right``; without ``left`` the row continues the equation above it
    (``= right``); ``harmonic`` marks one harmonic of the split right side."""

    right: sp.Expr
    left: sp.Expr | tuple[str, str] | None = None  # an expression, or (text, LaTeX)
    harmonic: int | None = None


@dataclass(frozen=True)
class _Step:
    title: tuple[str, str]  # (text, LaTeX)
    rows: tuple[_Row, ...]


TITLES = {
    "equation": ("Equation, its right side from b_k and the lower orders:",
                 r"The equation, its right side from $b_k$ and the lower orders:"),
    "harmonics": ("Right side split into harmonics of Omega*t "
                  "(cos(a)*cos(b) = (cos(a + b) + cos(a - b))/2):",
                  r"The right side split into harmonics of $\Omega t$:"),
    "secular": ("Secular condition: the part of harmonic 1 in phase with u0 vanishes:",
                r"Secular condition: the part of harmonic 1 in phase with $u_0$ vanishes:"),
    "solution": ("Solution, harmonic k through the transfer H_k*exp(I*theta_k), "
                 "a mean through 1/omega**2:",
                 r"Solution, harmonic $k$ through the transfer $H_k e^{i\theta_k}$, "
                 r"a mean through $1/\omega^2$:"),
}


class _Derivation:
    """Builds the steps of each order, the lower orders' solutions in their display names."""

    def __init__(self, series: Series) -> None:
        self.series = series
        if series.is_eq26:
            names = paper_names(min(series.order, PAPER_ORDER))
            # The paper's names that are one engine symbol (A12 = A_3_2, phi3 = psi_3_2, ...).
            self.rename = {engine: _paper(name) for name, engine in names.items()
                           if engine.isidentifier()}
            self.rename["theta_1"] = self.rename["phi_0_1"]  # u0 = G H_1 cos(Omega t + theta_1)
        else:  # the terms the paper does not have: the engine's names throughout
            self.rename = {"theta_1": sym.phase(0, 1)}
        # The paper solves orders 0-2 term by term (Eq. 2.8-2.10); the consistent series'
        # extra terms do not fit those names, so it gathers every order's harmonics.
        self.termwise_orders = TERMWISE_ORDERS if series.is_eq26 else 0
        self.termwise = _termwise_parts()
        self.parts: dict[tuple[int, int], list[Part]] = {}  # u_n by harmonic, solved so far
        self.transfers: set[int] = set()  # harmonics whose transfer is written out

    def name(self, symbol: sp.Symbol) -> sp.Symbol:
        """The paper's name of an engine symbol, where the paper has one."""
        return self.rename.get(str(symbol), symbol)

    def b(self, n: int) -> sp.Symbol:
        return self.name(sym.b(n))

    def lag(self, k: int) -> sp.Expr:
        return self.name(sym.lag(k)) if k else sp.Integer(0)

    # -- the right side ------------------------------------------------------
    def _expand(self, term: Term) -> list[Part]:
        """One engine term with each factor written as the paper writes that harmonic."""
        b_names = {sym.b(j): self.b(j) for j in term.bs}
        parts: list[Part] = [(term._prefactor().xreplace(b_names), sp.Integer(0))]
        for f in term.factors:
            # A derivative factor (d_j u^j u'): k Omega A cos(k Omega t + phi + pi/2).
            scale = f.harmonic * sym.Omega if f.derivative else 1
            shift = sp.pi / 2 if f.derivative else 0
            parts = [(c * a * scale, x + f.sign * (y + shift)) for c, x in parts
                     for a, y in self.parts[(f.order, f.harmonic)]]
        if term.harmonic == 0:  # a constant: cos(phase) is part of its amplitude
            parts = [(c * sp.cos(x), sp.Integer(0)) for c, x in parts]
        return parts

    def right_side(self, n: int) -> dict[int, list[Part]]:
        if n == 0:
            return {1: [(sym.G, sp.Integer(0))]}
        rhs = {k: [p for term in terms for p in self._expand(term)]
               for k, terms in self.series.equations[n].rhs.items()}
        if not self.series.has_b(n):  # the paper writes b_n u0 at odd orders too (Eq. 2.9, A.1)
            rhs[1] = [(self.b(n) * a, x) for a, x in self.parts[(0, 1)]]
        return dict(sorted(rhs.items()))

    def solution(self, n: int) -> sp.Expr:
        return sp.Add(*(_cosines(k, parts) for (m, k), parts in self.parts.items() if m == n))

    # -- the steps -----------------------------------------------------------
    def equation(self, n: int) -> _Step:
        generic = generic_right_side(n, self.series)
        names = {sp.Symbol(f"u_{i}"): sp.Symbol(f"u{i}") for i in range(n)}
        names.update({sp.Symbol(f"du_{i}"): sp.Symbol(f"u{i}'") for i in range(n)})
        names.update({sym.b(k): self.b(k) for k in range(1, n + 1)})
        left = (left_side_text(n, "u"), left_side_latex(n))
        rows = [_Row(generic.xreplace(names), left)]
        if n:
            known = {sym.b(k): 0 for k in range(1, n) if not self.series.has_b(k)}
            known.update({sp.Symbol(f"u_{i}"): self.solution(i) for i in range(n)})
            known.update({sp.Symbol(f"du_{i}"): sp.diff(self.solution(i), sym.t)
                          for i in range(n)})
            rows.append(_Row(generic.xreplace(known).xreplace(names)))
        return _Step(TITLES["equation"], tuple(rows))

    def forcing(self, n: int, rhs: dict[int, list[Part]]) -> tuple[dict, list[_Row]]:
        """Harmonics k of the engine's right side gathered into F cos(k Omega t + psi) (A.1)."""
        gathered, rows = dict(rhs), []
        for k in self.series.harmonics(n):
            amplitude = self.name(sym.forcing_amplitude(n, k))
            if k == 0:
                rows.append(_Row(sp.Add(*(a for a, _ in rhs[0])), amplitude))
                gathered[0] = [(amplitude, sp.Integer(0))]
                continue
            phase = self.name(sym.forcing_phase(n, k))
            cos_part = sp.Add(*(a * sp.cos(x) for a, x in rhs[k]))
            sin_part = sp.Add(*(a * sp.sin(x) for a, x in rhs[k]))
            rows.append(_Row(sp.sqrt(cos_part**2 + sin_part**2), amplitude))
            rows.append(_Row(sp.atan2(sin_part, cos_part), phase))
            gathered[k] = [(amplitude, phase)]
        total = sp.Add(*(_cosines(k, parts) for k, parts in gathered.items()))
        return gathered, [_Row(total), *rows]

    def harmonics(self, n: int, rhs: dict[int, list[Part]]) -> tuple[_Step, dict]:
        rows = [_Row(_cosines(k, parts), harmonic=k) for k, parts in rhs.items()]
        gathered = rhs
        if n >= self.termwise_orders:
            gathered, more = self.forcing(n, rhs)
            rows += more
        return _Step(TITLES["harmonics"], tuple(rows)), gathered

    def secular(self, n: int, rhs: dict[int, list[Part]]) -> tuple[_Step, sp.Expr]:
        (a0, phi0), = self.parts[(0, 1)]
        in_phase = sp.expand(sp.Add(*(a * sp.cos(x - phi0) for a, x in rhs[1])))
        b_n = sp.expand(-in_phase.subs(self.b(n), 0) / a0)
        rows = (_Row(sp.Integer(0), in_phase), _Row(b_n, self.b(n)))
        return _Step(TITLES["secular"], rows), b_n

    def _transfer(self, k: int, amplitude: sp.Expr) -> sp.Expr:
        return amplitude / sym.omega**2 if k == 0 else amplitude * sym.gain(k)

    def _solve_termwise(self, n: int, k: int, parts: list[Part]) -> list[_Row]:
        """Each cosine through the transfer, gathered by phase into the paper's amplitudes."""
        by_phase: dict[sp.Expr, sp.Expr] = {}
        for a, x in parts:
            phase = x + self.lag(k)
            by_phase[phase] = by_phase.get(phase, 0) + self._transfer(k, a)
        rows = []
        for amplitude, phase in self.termwise[(n, k)]:
            value = by_phase.pop(phase)
            if str(amplitude) in SPLIT:
                first, rest = (_paper(name) for name in SPLIT[str(amplitude)])
                rest_value, first_value = sp.expand(value).as_independent(self.b(n))
                rows += [_Row(first_value, first), _Row(rest_value, rest)]
                value = first + rest
            rows.append(_Row(value, amplitude))
        if by_phase:
            raise RuntimeError(f"u{n}, harmonic {k}: terms of phases {list(by_phase)} are not "
                               "in the paper's form of the solution")
        self.parts[(n, k)] = self.termwise[(n, k)]
        return rows

    def _solve_gathered(self, n: int, k: int, parts: list[Part]) -> list[_Row]:
        (forcing, phase), = parts
        amplitude = self.name(sym.amplitude(n, k))
        self.parts[(n, k)] = [(amplitude, phase + self.lag(k))]
        return [_Row(self._transfer(k, forcing), amplitude)]

    def _transfers(self, n: int) -> list[_Row]:
        """H_k and theta_k in closed form, for each harmonic solved first at order n."""
        rows = []
        for k in sorted(k for (m, k) in self.parts if m == n and k not in self.transfers and k):
            self.transfers.add(k)
            rows += [_Row(gain_closed_form(k), sym.gain(k)), _Row(lag_closed_form(k), self.lag(k))]
        return rows

    def solve(self, n: int, rhs: dict[int, list[Part]], b_n: sp.Expr) -> _Step:
        if n and b_n == 0:  # b_n u0 goes
            rhs = {k: [(a.subs(self.b(n), 0), x) for a, x in parts] for k, parts in rhs.items()}
            rhs = {k: [(a, x) for a, x in parts if a != 0] for k, parts in rhs.items()}
        solve = self._solve_termwise if n < self.termwise_orders else self._solve_gathered
        definitions = [row for k, parts in rhs.items() if parts for row in solve(n, k, parts)]
        u_n, u = sp.Symbol(f"u{n}"), self.solution(n)
        split = {_paper(name): _paper(first) + _paper(rest)
                 for name, (first, rest) in SPLIT.items()}
        if n < self.termwise_orders and u.has(*split):  # Eq. 2.10: the four terms, then regrouped
            rows = [_Row(u.xreplace(split).expand(), u_n), _Row(u)]
        else:
            rows = [_Row(u, u_n)]
        return _Step(TITLES["solution"], tuple(rows + definitions + self._transfers(n)))

    def order(self, n: int) -> list[_Step]:
        """The steps of order n; solves it (its u_n becomes known to the next orders)."""
        rhs = self.right_side(n)
        steps = [self.equation(n)]
        if n == 0:
            return [*steps, self.solve(0, rhs, sp.Integer(0))]
        harmonics, gathered = self.harmonics(n, rhs)
        secular, b_n = self.secular(n, rhs)
        return [*steps, harmonics, secular, self.solve(n, gathered, b_n)]


def _orders(series: Series, each_order: Callable[[], object] | None) -> list[list[_Step]]:
    derivation = _Derivation(series)
    orders = []
    for n in range(series.order + 1):
        orders.append(derivation.order(n))
        if each_order is not None:
            each_order()
    return orders


def _heading(n: int, series: Series) -> tuple[str, str]:
    if not series.is_eq26:
        return (f"Order eps^{n}", rf"Order $\varepsilon^{{{n}}}$")
    if n <= PAPER_ORDER:
        return (f"Order eps^{n} (Eq. {EQUATIONS[n]})",
                rf"Order $\varepsilon^{{{n}}}$ (Eq.~{EQUATIONS[n]})")
    return (f"Order eps^{n} (beyond the paper: the engine's names)",
            rf"Order $\varepsilon^{{{n}}}$ (beyond the paper: the engine's names)")


def _preamble(series: Series) -> list[str]:
    if not series.is_eq26:
        return _consistent_preamble(series)
    omega2 = series.omega_squared().xreplace({sym.b(n): _paper(f"b{n}")
                                              for n in range(1, PAPER_ORDER + 1)})
    return [
        f"Derivation of the series of Eq. 2.6 to order {series.order}, step by step, "
        "in the paper's names",
        "Eq. 2.6: u'' + 2*c*u' + omega0**2*u + eps*h*u**2 = G*cos(Omega*t), Omega = 2*pi*f_e",
        # eps in the text, as in the lines above and below (sympy names it epsilon).
        f"Eq. 2.7: u = u0 + eps*u1 + eps**2*u2 + ..., omega**2 = "
        f"{sp.sstr(omega2.xreplace({sym.eps: sp.Symbol('eps', positive=True)}))}",
        "Names: the paper's A0-A19, phi0-phi9, b1-b4 (Eq. 2.8-2.10, A.1, A.2), the engine's "
        "beyond order 4 (A_n_k, F_n_k, psi_n_k, b_n, theta_k); amplitudes are signed, as the "
        "paper's.",
        "Transfer of harmonic k: H_k*exp(I*theta_k) = 1/(omega**2 - k**2*Omega**2 + "
        "2*I*k*c*Omega); the paper writes theta_k for k = 1..5 as phi0, phi1, phi2, phi5, phi9.",
    ]


def derivation_text(series: Series, *, each_order: Callable[[], object] | None = None) -> str:
    r"""The derivation, order by order and step by step, as text: Eq. 2.6's series in the
    paper's names; a series that keeps more of the equation in contact (the consistent
    truncation) in the engine's, every order's harmonics gathered (A.1, A.2's way).

    Parameters
    ----------
    series : Series
        From ``derive``.
    each_order : callable, optional
        Called with no argument after each order is derived (for progress).

    Examples
    --------
    >>> from perturb import derive
    >>> text = derivation_text(derive(2, "paper"))
    >>> print("\n".join(line for line in text.splitlines() if line.startswith(("Order", "    b"))))
    Order eps^0 (Eq. 2.8)
    Order eps^1 (Eq. 2.9)
        b1 = 0
    Order eps^2 (Eq. 2.10)
        b2 = A1*h*cos(phi1) + 2*A2*h
    """
    lines = _preamble(check_series(series))
    for n, steps in enumerate(_orders(series, each_order)):
        lines.append(_heading(n, series)[0])
        for step in steps:
            lines.append("  " + step.title[0])
            lines += ["    " + _text_row(row) for row in step.rows]
    return "\n".join(lines) + "\n"


def _consistent_preamble(series: Series) -> list[str]:
    """The first lines of the study of a series that keeps more than Eq. 2.6."""
    from .report import heading_lines as report_heading

    equation, *coefficients = report_heading(series)[1:]
    return [
        f"Derivation of the {series.truncation.name} series of the equation in contact to "
        f"order {series.order}, step by step, in the engine's names",
        equation,
        *coefficients,
        "u = u0 + eps*u1 + eps**2*u2 + ..., omega**2 = omega0**2 + eps**2*b2 + ...; "
        "ui' = du_i/dt",
        "Names: A_n_k, phi_n_k of u_n's harmonic k, F_n_k, psi_n_k of the right side's, b_n, "
        "and the transfer of harmonic k: H_k*exp(I*theta_k) = 1/(omega**2 - k**2*Omega**2 + "
        "2*I*k*c*Omega).",
    ]


def _text_row(row: _Row) -> str:
    if row.harmonic is not None:
        return f"harmonic {row.harmonic}: {sp.sstr(row.right)}"
    if row.left is None:
        return f"  = {sp.sstr(row.right)}"
    if isinstance(row.left, tuple):
        return f"{row.left[0]} = {sp.sstr(row.right)}"
    return equation_line(row.left, row.right, pretty=False)


def derivation_latex(series: Series, *, each_order: Callable[[], object] | None = None) -> str:
    r"""The derivation as a LaTeX fragment: per order a ``\paragraph`` and one ``align*``
    (amsmath), the steps introduced by ``\intertext``, the paper's orders tagged with
    the paper's equation numbers.

    Examples
    --------
    >>> from perturb import derive
    >>> tex = derivation_latex(derive(1, "paper"))
    >>> print(tex[tex.index(r"\ddot u_{1}"):].splitlines()[0])
    \ddot u_{1} + 2c\,\dot u_{1} + \omega^2 u_{1} &= b_{1} u_{0} - h u_{0}^{2} \tag{2.9}\\
    """
    out = [rf"% {line}" for line in _preamble(check_series(series))]
    for n, steps in enumerate(_orders(series, each_order)):
        out.append(rf"\paragraph{{{_heading(n, series)[1]}}}")
        out.append(steps[0].title[1])
        out.append(r"\begin{align*}")
        rows = []
        for i, step in enumerate(steps):
            if i:
                rows.append(rf"\intertext{{{step.title[1]}}}")
            rows += _latex_rows(step.rows)
        if n <= PAPER_ORDER and series.is_eq26:
            rows[0] += rf" \tag{{{EQUATIONS[n]}}}"
        out += [row if row.startswith(r"\intertext") or i == len(rows) - 1 else row + r"\\"
                for i, row in enumerate(rows)]
        out.append(r"\end{align*}")
    return "\n".join(out) + "\n"


def _latex_rows(rows: tuple[_Row, ...]) -> list[str]:
    out = []
    first = True
    for row in rows:
        if row.harmonic is not None:
            out.append(split_row(latex_of(row.right), first=first))
            first = False
        elif row.left is None:
            out.append(rf"&= {latex_of(row.right)}")
        elif isinstance(row.left, tuple):
            out.append(rf"{row.left[1]} &= {latex_of(row.right)}")
        else:
            out.append(rf"{latex_of(row.left)} &= {latex_of(row.right)}")
    return out
