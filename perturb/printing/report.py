"""Printing the derived series for people: plain text and LaTeX.

For each order: the equation in the form of the paper (left side, right side
from b_k and products of lower orders), its right side split into harmonics,
b_n, and the solution with the closed form of every amplitude and phase; then
the series of omega^2 (Eq. 2.7).

Examples
--------
>>> from perturb.series.lindstedt import derive
>>> print(text_report(derive(1, "paper")).splitlines()[11])
  u_1'' + 2*c*u_1' + omega**2*u_1 = b_1*u_0 - h*u_0**2
"""

from __future__ import annotations

import re

import sympy as sp

from ..series import series_symbols as sym
from ..series.lindstedt import Series, gain_closed_form, lag_closed_form

__all__ = ["text_report", "latex_report", "series_json", "generic_right_side", "latex_names"]

_INDEXED = re.compile(r"^(A|phi|F|psi|z|zc)_(\d+)_(\d+)$")
_SINGLE = re.compile(r"^(b|H|theta|u)_(\d+)$")
_LATEX_BASE = {"A": "A", "phi": r"\varphi", "F": "F", "psi": r"\psi", "z": "z", "zc": r"\bar{z}"}
_LATEX_SINGLE = {"b": "b", "H": "H", "theta": r"\theta", "u": "u"}
_PAPER_PHASE = re.compile(r"^phi(\d+)$")  # the paper's phases phi0-phi9 (``derivation``)


def check_series(series) -> Series:
    if not isinstance(series, Series):
        raise ValueError(f"`series` must be a Series (from `derive`), got {series!r}.")
    return series


def _u(n: int) -> sp.Symbol:
    return sp.Symbol(f"u_{n}")


def generic_right_side(n: int, series: Series | None = None) -> sp.Expr:
    """sum_{k=1..n} b_k u_{n-k} - h sum_{i+j=n-1} u_i u_j (Eq. 2.9, 2.10, A.1, A.2), and
    the terms of the equation in contact that ``series``' truncation keeps beyond Eq. 2.6:
    - k_j (u^j)_(n-j+1) and - d_j (u^j u')_(n-j), u_i' written du_i.

    Examples
    --------
    >>> generic_right_side(3)
    b_1*u_2 + b_2*u_1 + b_3*u_0 - h*(2*u_0*u_2 + u_1**2)
    >>> from perturb.series.lindstedt import derive
    >>> generic_right_side(2, derive(2))  # the paper's contact: d_1 u u' too
    b_1*u_1 + b_2*u_0 - d_1*(du_0*u_1 + du_1*u_0) - 2*h*u_0*u_1
    """
    if n == 0:
        return sym.G * sp.cos(sym.Omega * sym.t)
    bs = sp.Add(*(sym.b(k) * _u(n - k) for k in range(1, n + 1)))
    products = sp.Add(*(_u(i) * _u(n - 1 - i) for i in range(n)))
    if series is None or series.is_eq26:
        return bs - sym.h * products
    eps = sym.eps
    u = sp.Add(*(eps**i * _u(i) for i in range(n)))
    du = sp.Add(*(eps**i * sp.Symbol(f"du_{i}") for i in range(n)))
    total = bs
    for kind, j in series.coefficients:
        order = n - j + 1 if kind == "k" else n - j
        if order < 0:
            continue
        power = sp.expand(u**j * (du if kind == "d" else 1)).coeff(eps, order)
        total -= sym.coefficient(kind, j) * sp.factor_terms(power)
    return total


def latex_names(expr: sp.Expr) -> dict[sp.Symbol, str]:
    """LaTeX names for the engine's symbols: A_2_1 -> A_{2,1}, phi_0_1 -> varphi_{0,1};
    and for the paper's phases: phi3 -> varphi_{3} (its A3, b2, u1 are sympy's A_{3}, ...)."""
    names: dict[sp.Symbol, str] = {sym.omega0: r"\omega_0", sym.eps: r"\varepsilon"}
    for symbol in expr.free_symbols:
        match = _INDEXED.match(str(symbol))
        if match:
            base, n, k = match.groups()
            names[symbol] = f"{_LATEX_BASE[base]}_{{{n},{k}}}"
        match = _SINGLE.match(str(symbol))
        if match:
            base, n = match.groups()
            names[symbol] = f"{_LATEX_SINGLE[base]}_{{{n}}}"
        match = _PAPER_PHASE.match(str(symbol))
        if match:
            names[symbol] = rf"\varphi_{{{match.group(1)}}}"
    return names


def left_side_text(n: int, u: str = "u_") -> str:
    return f"{u}{n}'' + 2*c*{u}{n}' + omega**2*{u}{n}"


def left_side_latex(n: int) -> str:
    return rf"\ddot u_{{{n}}} + 2c\,\dot u_{{{n}}} + \omega^2 u_{{{n}}}"


def _order_items(series: Series, n: int) -> list[tuple[str, sp.Expr, sp.Expr]]:
    """(label, left, right) pairs that describe order n after its equation."""
    items: list[tuple[str, sp.Expr, sp.Expr]] = []
    if n == 0:
        amplitude, phase = series.solution_closed_form(0, 1)
        items.append(("solution", _u(0), series.solution(0)))
        items.append(("closed form", sym.amplitude(0, 1), amplitude))
        items.append(("closed form", sym.phase(0, 1), phase))
        return items
    for k in series.harmonics(n):
        items.append(("right side", sp.Symbol(f"[harmonic {k}]"), series.rhs_cosines(n, k)))
    items.append(("frequency", sym.b(n), series.b_closed_form(n)))
    items.append(("solution", _u(n), series.solution(n)))
    for k in series.harmonics(n):
        forcing, forcing_phase = series.forcing_closed_form(n, k)
        amplitude, phase = series.solution_closed_form(n, k)
        items.append(("closed form", sym.forcing_amplitude(n, k), forcing))
        if k:
            items.append(("closed form", sym.forcing_phase(n, k), forcing_phase))
        items.append(("closed form", sym.amplitude(n, k), amplitude))
        if k:
            items.append(("closed form", sym.phase(n, k), phase))
    return items


def _transfer_lines(series: Series) -> list[tuple[sp.Expr, sp.Expr]]:
    top = max(max(series.harmonics(n)) for n in range(series.order + 1))
    lines = []
    for k in range(1, top + 1):
        lines.append((sym.gain(k), gain_closed_form(k)))
        lines.append((sym.lag(k), lag_closed_form(k)))
    return lines


def equation_line(left: sp.Expr, right: sp.Expr, pretty: bool) -> str:
    if pretty:
        return sp.pretty(sp.Eq(left, right, evaluate=False), use_unicode=True, wrap_line=False)
    return f"{sp.sstr(left)} = {sp.sstr(right)}"


def text_report(series: Series, *, pretty: bool = False, each_order=None) -> str:
    """The derivation as text, order by order.

    Parameters
    ----------
    series : Series
    pretty : bool
        Two-dimensional unicode formulas (``sympy.pretty``) instead of one-line
        expressions.
    each_order : callable, optional
        Called with no argument after each order is written (for progress: the
        closed forms of high orders take long to simplify and print).
    """
    check_series(series)

    def block(left: sp.Expr, right: sp.Expr, indent: str) -> list[str]:
        return [indent + row for row in equation_line(left, right, pretty).splitlines()]

    lines = [
        *heading_lines(series),
        "Eq. 2.7:",
        *block(sym.omega**2, series.omega_squared(), "  "),
        "Transfer of harmonic k: H_k*exp(I*theta_k) = 1/(omega**2 - k**2*Omega**2 + 2*I*k*c*Omega)",
    ]
    for n in range(series.order + 1):
        lines.append(f"-- eps^{n}")
        lines.append(f"  {left_side_text(n)} = {sp.sstr(generic_right_side(n, series))}")
        for label, left, right in _order_items(series, n):
            lines += block(left, right, "    " if label == "closed form" else "  ")
        if each_order is not None:
            each_order()
    lines.append("-- transfer functions")
    for left, right in _transfer_lines(series):
        lines += block(left, right, "  ")
    return "\n".join(lines) + "\n"


def heading_lines(series: Series) -> list[str]:
    """The report's first lines: Eq. 2.6, or the equation in contact with the closed form
    of each coefficient the truncation keeps beyond it."""
    if series.is_eq26:
        return [f"Perturbation series of Eq. 2.6 to order {series.order}",
                "Eq. 2.6: u'' + 2*c*u' + omega0**2*u + eps*h*u**2 = G*cos(Omega*t)"]
    lines = [f"Perturbation series of the equation in contact to order {series.order} "
             f"({series.truncation.name} truncation: k_j u^j at eps^(j-1), d_j u^j u' at eps^j)",
             f"Equation: {sp.sstr(_equation_text(series))} = G*cos(Omega*t)",
             "Coefficients (Taylor's of the contact laws at y0; u = y - y0, h = k_2, 2*c = d_0):"]
    from ..series.truncation import coefficient_closed_form

    for kind, j in (("k", 1), ("d", 0), *series.coefficients):
        names = {("k", 1): "omega0**2", ("d", 0): "2*c"}
        name = names.get((kind, j), str(sym.coefficient(kind, j)))
        lines.append(f"  {name} = {sp.sstr(coefficient_closed_form(kind, j))}")
    return lines


def _kept_terms(series: Series, u: sp.Symbol, du: sp.Symbol) -> list[sp.Expr]:
    """k_j u^j and d_j u^j u' for each coefficient the series keeps (h u^2 first)."""
    return [sym.coefficient(kind, j) * u**j * (du if kind == "d" else 1)
            for kind, j in series.coefficients]


def _equation_text(series: Series) -> sp.Expr:
    u, du, ddu = sp.symbols("u u' u''")
    terms = [ddu, 2 * sym.c * du, sym.omega0**2 * u, *_kept_terms(series, u, du)]
    return sp.Add(*terms, evaluate=False)


def _consistent_latex_heading(series: Series) -> list[str]:
    """The equation in contact that the series solves, and its coefficients in closed form."""
    from ..series.truncation import coefficient_closed_form

    u, du = sp.Symbol("u"), sp.Symbol("udot")  # sorts after u: d_1 u \dot u
    extra = sp.Add(*_kept_terms(series, u, du))
    extra_latex = sp.latex(extra, symbol_names={**latex_names(extra), du: r"\dot u"})
    rows = [rf"{latex_of(sym.coefficient(kind, j))} &= {latex_of(coefficient_closed_form(kind, j))}"
            for kind, j in series.coefficients]
    return [
        rf"% Perturbation series of the equation in contact to order {series.order}, "
        rf"{series.truncation.name} truncation (perturb derive)",
        r"\begin{align*}",
        rf"\ddot u + 2c\,\dot u + \omega_0^2 u + {extra_latex} &= G\cos(\Omega t)\\",
        *(row + r"\\" for row in rows),
        rf"\omega^2 &= {latex_of(series.omega_squared())}",
        r"\end{align*}",
    ]


def latex_of(expr: sp.Expr) -> str:
    return sp.latex(expr, symbol_names=latex_names(expr))


def split_row(term: str, *, first: bool) -> str:
    """One harmonic of the split right side: the split opens with ``=`` (as Eq. 2.9
    and 2.10 write it), each further harmonic continues the sum with its sign."""
    if first:
        return rf"&= {term}"
    sign = "" if term.startswith("-") else "+ "
    return rf"&\phantom{{=}}\quad {sign}{term}"


def latex_report(series: Series) -> str:
    r"""The derivation as a LaTeX fragment (``align*`` blocks, one per order).

    The right side of order n is written twice: as products of lower orders,
    then ``=`` its split into harmonics, one harmonic per line::

        \ddot u_1 + ... &= b_1 u_0 - h u_0^2 \\
        &= -\frac{A_{0,1}^2 h}{2} \\
        &\phantom{=}\quad - \frac{A_{0,1}^2 h \cos(2\Omega t + 2\varphi_{0,1})}{2}
    """
    check_series(series)
    out = [
        rf"% Perturbation series of Eq. 2.6 to order {series.order} (perturb derive)",
        r"\begin{align*}",
        r"\ddot u + 2c\,\dot u + \omega_0^2 u + \varepsilon h u^2 &= G\cos(\Omega t)\\",
        rf"\omega^2 &= {latex_of(series.omega_squared())}",
        r"\end{align*}",
    ] if series.is_eq26 else _consistent_latex_heading(series)
    for n in range(series.order + 1):
        out.append(rf"\paragraph{{$\varepsilon^{{{n}}}$}}")
        out.append(r"\begin{align*}")
        rows = [rf"{left_side_latex(n)} &= {latex_of(generic_right_side(n, series))}"]
        split = 0
        for label, left, right in _order_items(series, n):
            if label == "right side":
                rows.append(split_row(latex_of(right), first=split == 0))
                split += 1
            else:
                rows.append(rf"{latex_of(left)} &= {latex_of(right)}")
        out.append("\\\\\n".join(rows))
        out.append(r"\end{align*}")
    out.append(r"\begin{align*}")
    out.append(
        "\\\\\n".join(
            rf"{latex_of(left)} &= {latex_of(right)}" for left, right in _transfer_lines(series)
        )
    )
    out.append(r"\end{align*}")
    return "\n".join(out) + "\n"


def series_json(series: Series) -> dict:
    """The derivation as JSON-ready data; every expression is a sympy-readable string.

    Keys: ``order``; ``b`` (n -> b_n); ``terms``, one per harmonic of each u_n
    with ``name``, ``order``, ``harmonic``, ``amplitude`` and ``phase`` in closed
    form of lower-order names and of c, h, G, omega, Omega (and the k_j, d_j the
    series keeps); for Eq. 2.6's series ``paper_names``, for any other ``truncation``
    and ``coefficients`` (each k_j, d_j in closed form of S, c_n, m2, h_n, l, M, y0).

    Examples
    --------
    >>> from perturb.series.lindstedt import derive
    >>> data = series_json(derive(1, "paper"))
    >>> data["b"], data["terms"][2]["amplitude"]
    ({'1': '0'}, 'A_0_1**2*h/(2*sqrt(16*Omega**2*c**2 + (-4*Omega**2 + omega**2)**2))')
    """
    check_series(series)
    from .names import paper_names

    terms = []
    for n in range(series.order + 1):
        for k in series.harmonics(n):
            amplitude, phase = _explicit(series, n, k)
            terms.append(
                {
                    "name": f"u_{n}_{k}",
                    "order": n,
                    "harmonic": k,
                    "amplitude": sp.sstr(amplitude),
                    "phase": sp.sstr(phase),
                }
            )
    data = {
        "order": series.order,
        "b": {str(n): sp.sstr(series.b_closed_form(n)) for n in range(1, series.order + 1)},
        "terms": terms,
    }
    if series.is_eq26:
        return {**data, "paper_names": paper_names(min(series.order, 4))}
    from ..series.truncation import coefficient_closed_form

    return {**data, "truncation": series.truncation.name,
            "coefficients": {str(sym.coefficient(kind, j)): sp.sstr(coefficient_closed_form(
                kind, j)) for kind, j in series.coefficients}}


def _explicit(series: Series, n: int, k: int) -> tuple[sp.Expr, sp.Expr]:
    """A_n_k and phi_n_k with F, psi, H and theta replaced by their closed forms."""
    amplitude, phase = series.solution_closed_form(n, k)
    replace = {sym.gain(j): gain_closed_form(j) for j in range(k, k + 1) if j}
    replace.update({sym.lag(j): lag_closed_form(j) for j in range(k, k + 1) if j})
    if n:
        forcing, forcing_phase = series.forcing_closed_form(n, k)
        replace[sym.forcing_amplitude(n, k)] = forcing
        replace[sym.forcing_phase(n, k)] = forcing_phase
    return amplitude.xreplace(replace), sp.sympify(phase).xreplace(replace)
