"""The order-N series as compiled kernels of the frequency response, cached on disk.

``complex_chain`` gives the series as ordered assignments (b_n, means A_n_0,
harmonics z_n_k; Eq. 2.8-2.10, A.1, A.2). Here the chain is flattened into
straight-line code on real numbers: every complex value is a pair of reals,
identical sub-expressions are computed once across the whole chain (the
transfer of each harmonic k, 1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega), say),
and a value known to be real skips the imaginary arithmetic. The residual's
loop over lanes has no branch and no call, so numba runs several lanes per
SIMD instruction.

For a response of order N, the chain of order N+2 gives the residual of the
frequency equation (Eq. 2.7, 2.8) of order N and of the next orders, and the
harmonics of orders N, N+1, N+2 (``series_source``). They are written, with
the kernels of ``template.py`` (grid, root search, waveforms), into
a module in the cache folder (``cache.py``), under a key made of the order
and the text of the source files that shape the code; numba caches the
machine code beside it. A process that finds the module needs no sympy.

numba compiles straight-line code at a few milliseconds a line (about 1,600
lines at order 6), so the first call of an order in a new cache takes seconds;
``tests/benchmarks/bench_perturb.py`` measures it.

Examples
--------
>>> kernels = series_kernels(2)
>>> kernels.ORDER, kernels.B_ORDERS, kernels.TOP_HARMONIC
(2, ((2,), (2,), (2, 4)), 5)
"""

from __future__ import annotations

import re
import threading
from pathlib import Path
from types import ModuleType

from ..cache import (
    SERIES_SOURCES,
    cache_key,
    intact,
    load_generated,
    machine_code_index,
    usable_cache_dir,
)
from ..series.truncation import PAPER_TRUNCATION, Truncation

__all__ = ["kernel_truncation", "series_kernels", "series_kernels_built", "series_source"]

_HERE = Path(__file__).parent
_TEMPLATE = _HERE / "template.py"
#: The files whose text shapes a generated module (a change to one generates it again).
_SOURCES = (*SERIES_SOURCES, Path(__file__), _TEMPLATE)
_LOADED: dict[int, ModuleType] = {}
#: A name of the generated code or a number: no arithmetic.
_ATOM = re.compile(r"[ri]\d+|-?\d+(\.\d*)?(e[-+]?\d+)?")
_LOCK = threading.Lock()


class _Program:
    """Straight-line code of the chain, on real numbers.

    Each value is a pair (real part, imaginary part) of atoms: a variable
    ``r{v}`` or ``i{v}``, a number, or None for a part that is zero (a real
    value has no imaginary part). Only arithmetic that is not known to be
    trivial is written: a real part is taken by dropping the imaginary one,
    numbers go into the expressions, and a product's numbers are multiplied
    first (4 i for ``4*I*Omega*c``).
    """

    def __init__(self, arguments) -> None:
        self.parts: list[tuple[str | None, str | None]] = []
        self.operands: list[tuple[int, ...]] = []
        self.code: list[str] = []
        self.memo: dict = {}
        for argument in arguments:
            self.memo[argument] = self._value((f"r{len(self.parts)}", None))

    def _value(self, parts, operands: tuple[int, ...] = (), code: str = "") -> int:
        self.parts.append(parts)
        self.operands.append(operands)
        self.code.append(code)
        return len(self.parts) - 1

    def _computed(self, key, operands, real: str | None, imag: str | None) -> int:
        """The value with parts computed by the expressions ``real``, ``imag`` (None: zero)."""
        if key not in self.memo:
            v = len(self.parts)
            # A part that is a name or a number is used as it is, not copied.
            names = tuple(e if e is None or _ATOM.fullmatch(e) else f"{p}{v}"
                          for p, e in zip("ri", (real, imag)))
            code = "; ".join(f"{n} = {e}" for n, e in zip(names, (real, imag)) if n != e)
            self.memo[key] = self._value(names, operands, code)
        return self.memo[key]

    def is_complex(self, v: int) -> bool:
        return self.parts[v][1] is not None

    def constant(self, number: complex) -> int:
        number = complex(number)
        if ("constant", number) not in self.memo:
            self.memo[("constant", number)] = self._value(
                (repr(number.real) if number.real else None,
                 repr(number.imag) if number.imag else None))
        return self.memo[("constant", number)]

    def add(self, a: int, b: int) -> int:
        (ra, ia), (rb, ib) = self.parts[a], self.parts[b]
        return self._computed(("+", a, b), (a, b), _sum(ra, rb), _sum(ia, ib))

    def multiply(self, a: int, b: int) -> int:
        (ra, ia), (rb, ib) = self.parts[a], self.parts[b]
        real = _sum(_product(ra, rb), _negative(_product(ia, ib)))
        imag = _sum(_product(ra, ib), _product(ia, rb))
        return self._computed(("*", a, b), (a, b), real, imag)

    def divide(self, a: int, b: int) -> int:
        (ra, ia), (rb, ib) = self.parts[a], self.parts[b]
        if ib is None:
            return self._computed(("/", a, b), (a, b), ra and f"{ra} / {rb}",
                                  ia and f"{ia} / {rb}")
        # a / b = a conj(b) / |b|^2; here |b|^2 is of the order omega^4, far from overflow.
        norm = self._computed(("|.|^2", b), (b,), f"{rb} * {rb} + {ib} * {ib}", None)
        rn = self.parts[norm][0]
        real = _sum(_product(ra, rb), _product(ia, ib))
        imag = _sum(_product(ia, rb), _negative(_product(ra, ib)))
        return self._computed(("/", a, b), (a, b, norm), real and f"({real}) / {rn}",
                              imag and f"({imag}) / {rn}")

    def conjugate(self, a: int) -> int:
        ra, ia = self.parts[a]
        if ia is None:
            return a
        if ("conj", a) not in self.memo:
            v = len(self.parts)
            self.memo[("conj", a)] = self._value((ra, f"i{v}"), (a,), f"i{v} = {_negative(ia)}")
        return self.memo[("conj", a)]

    def real(self, a: int) -> int:
        ra, ia = self.parts[a]
        return a if ia is None else self._value((ra, None), (a,))

    def total(self, values: list[int], combine) -> int:
        """values[0] combined with the others, left to right."""
        result = values[0]
        for value in values[1:]:
            result = combine(result, value)
        return result

    def expression(self, expr) -> int:
        """The value of a sympy expression (sums, products, integer powers, numbers)."""
        if expr in self.memo:
            return self.memo[expr]
        if expr.is_number:
            value = self.constant(complex(expr))
        elif expr.is_Add:
            value = self.total(self._real_first(expr.args), self.add)
        elif expr.is_Mul:
            value = self._product(expr)
        elif expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
            value = self.total([self.expression(expr.base)] * int(expr.exp), self.multiply)
        elif expr.is_Pow and expr.exp.is_Integer:
            value = self.divide(self.constant(1.0), self.expression(1 / expr))
        else:
            raise TypeError(f"no straight-line code for {expr!r} ({type(expr).__name__})")
        self.memo[expr] = value
        return value

    def _real_first(self, terms) -> list[int]:
        values = [self.expression(term) for term in terms]
        return sorted(values, key=self.is_complex)

    def _product(self, expr) -> int:
        """number * numerator / denominator: one division per product."""
        import sympy as sp

        number = sp.Mul(*(f for f in expr.args if f.is_number))
        over = [f for f in expr.args if f.is_Pow and f.exp.is_Integer and f.exp < 0]
        factors = [f for f in expr.args if not f.is_number and f not in over]
        value = self.total(self._real_first(factors), self.multiply) if factors else None
        if number != 1 or value is None:
            coefficient = self.constant(complex(number))
            value = coefficient if value is None else self.multiply(coefficient, value)
        if over:
            value = self.divide(value, self.total(self._real_first([1 / f for f in over]),
                                                  self.multiply))
        return value

    def function(self, header: str, outputs: list[int], body_end: list[str],
                 indent: str = "    ") -> str:
        """Source of a function computing only what ``outputs`` need."""
        needed, stack = set(outputs), list(outputs)
        while stack:
            for used in self.operands[stack.pop()]:
                if used not in needed:
                    needed.add(used)
                    stack.append(used)
        body = [self.code[v] for v in sorted(needed) if self.code[v]]
        return "\n".join([header, *(f"{indent}{line}" for line in body + body_end)]) + "\n"


def _sum(a: str | None, b: str | None) -> str | None:
    """a + b as code, None for zero."""
    if a is None or b is None:
        return a if b is None else b
    return f"{a} - {b[1:]}" if b.startswith("-") else f"{a} + {b}"


def _product(a: str | None, b: str | None) -> str | None:
    """a * b as code (a and b are names or numbers), None for zero."""
    if a is None or b is None:
        return None
    for one, other in ((a, b), (b, a)):
        if one == "1.0":
            return other
        if one == "-1.0":
            return _negative(other)
    return f"{a} * {b}"


def _negative(a: str | None) -> str | None:
    if a is None:
        return None
    return a[1:] if a.startswith("-") else f"-{a}"


def _chain_program(order: int, truncation: Truncation):
    """The program of the whole chain of the order-N series, and the series."""
    from ..series import series_symbols as sym
    from ..series.compiled import chain_arguments, complex_chain

    series = _series(order, truncation)
    program = _Program(chain_arguments(series.coefficients))
    for symbol, expr in complex_chain(series):
        value = program.expression(expr)
        name = str(symbol)
        if name.startswith("z_"):
            # Harmonic z_n_k; the chain reads its conjugate as zc_n_k.
            _, n, k = name.split("_")
            program.memo[symbol] = value
            program.memo[sym.complex_amplitude(int(n), int(k), True)] = program.conjugate(value)
        else:  # b_n and the means A_n_0 are real
            program.memo[symbol] = program.real(value)
    return program, series


def _series(order: int, truncation: Truncation):
    from ..series.lindstedt import derive

    return derive(order, truncation)


def kernel_truncation(order: int, truncation: Truncation) -> Truncation:
    """The truncation whose kernels serve a response of ``order``: Eq. 2.6's where the
    series of orders N..N+2 keep its terms only, else ``truncation``'s terms at order
    N+2 (the kernels of two contacts with the same terms are the same: the values of
    k_j, d_j are arguments)."""
    if truncation.keeps_eq26_only(order + NEXT_ORDERS[-1]):
        return PAPER_TRUNCATION
    return Truncation("consistent", *truncation.at_order(order + NEXT_ORDERS[-1]))


#: Orders past N whose waveforms estimate the error of order N (``truncation_error``).
NEXT_ORDERS = (1, 2)


def series_source(order: int, truncation: Truncation = PAPER_TRUNCATION) -> str:
    """Python source of the generated kernels of the order-N response of ``truncation``
    (``kernel_truncation``: the terms it keeps at order N+2).

    One chain, that of order N+2, serves the orders N, N+1, N+2 (the first
    terms of a series do not depend on where it stops):

    - ``residual_lanes(G, omega, Omega, c, k_d, omega0, out)``: the residual of
      order N's frequency equation at every lane (omega[i], Omega[i]); ``k_d`` holds
      the equation's coefficients that the series keeps, h first (``COEFFICIENTS``);
    - ``residual_lanes_next(...)``: the same with every b_n up to N+2, the
      frequency equation of the later of orders N+1, N+2 that has its own
      (b_n = 0 for odd n, so one of the two shares order N's);
    - ``harmonics_lanes(a0, omega, Omega, c, k_d, out_re, out_im)``: the real
      and imaginary parts of sum_(n <= N+m) z_n_k at lane i in out[m, k, i],
      m = 0, 1, 2;

    and the constants ``ORDER``, ``B_ORDERS`` (the n of the non-zero b_n of
    orders N, N+1, N+2), ``TOP_HARMONIC`` and ``COEFFICIENTS`` (the (kind, j) of the
    entries of ``k_d``). Each function has the chain
    written out (numba takes about as long to inline a function as to compile
    it); the residuals' loops run in SIMD.
    """
    from ..series import series_symbols as sym
    from ..series.compiled import series_b_orders, series_keys

    kept = kernel_truncation(order, truncation)
    orders = (order, *(order + m for m in NEXT_ORDERS))
    program, series = _chain_program(orders[-1], kept)
    b_orders = tuple(series_b_orders(_series(n, kept)) for n in orders)
    if b_orders[1] not in (b_orders[0], b_orders[2]):  # b_n = 0 at odd n: cannot happen
        raise RuntimeError(f"orders {orders} have three frequency equations: {b_orders}")
    keys = series_keys(series)
    jit = '@numba.njit(cache=True, error_model="numpy")'
    # The coefficients past c are r4, r5, ... (``chain_arguments``), read from k_d.
    unpack = "".join(f"    r{4 + i} = k_d[{i}]\n" for i in range(len(series.coefficients)))

    def residual_source(name: str, b_up_to: tuple[int, ...]) -> str:
        # Eq. 2.7: omega^2 - omega0^2 = sum_n b_n, by increasing n; A0 = G H_1 (Eq. 2.8).
        b_values = [program.memo[sym.b(n)] for n in b_up_to]
        shift = program.total(b_values, program.add) if b_values else program.constant(0.0)
        return program.function(
            f"{jit}\ndef {name}(G, omega, Omega, r3, k_d, omega0, out):  # r3: c\n"
            f"{unpack}"
            "    for lane in range(omega.size):\n"
            "        r1, r2 = omega[lane], Omega[lane]\n"
            "        x, y = r1 * r1 - r2 * r2, 2.0 * r3 * r2\n"
            "        r0 = G / math.sqrt(x * x + y * y)",
            [shift], [f"out[lane] = r1 * r1 - omega0 * omega0 - {program.parts[shift][0] or 0.0}"],
            indent=" " * 8)

    # sum_(n <= N+m) z_n_k by harmonic k, in the frame where z_0_1 = A0 (value 0).
    top = max(k for _, k in keys)
    stores, totals = [], []
    for m, last in enumerate(orders):
        for k in range(top + 1):
            terms = [0 if (n, k) == (0, 1) else program.memo[
                sym.amplitude(n, 0) if k == 0 else sym.complex_amplitude(n, k)]
                for n, j in keys if j == k and n <= last]
            total = program.total(terms, program.add) if terms else program.constant(0.0)
            real, imag = program.parts[total]
            stores.append(f"out_re[{m}, {k}, lane] = {real or 0.0}")
            stores.append(f"out_im[{m}, {k}, lane] = {imag or 0.0}")
            totals.append(total)
    harmonics = program.function(
        f"{jit}\ndef harmonics_lanes(a0, omega, Omega, r3, k_d, out_re, out_im):  # r3: c\n"
        f"{unpack}"
        "    for lane in range(a0.size):\n"
        "        r0, r1, r2 = a0[lane], omega[lane], Omega[lane]",
        totals, stores, indent=" " * 8)
    return (f"ORDER = {order}\nB_ORDERS = {b_orders!r}\nTOP_HARMONIC = {top}\n"
            f"COEFFICIENTS = {series.coefficients!r}\n\n\n"
            f"{residual_source('residual_lanes', b_orders[0])}\n\n"
            f"{residual_source('residual_lanes_next', b_orders[-1])}\n\n{harmonics}")


def _module_source(order: int, kept: Truncation) -> str:
    template = _TEMPLATE.read_text()
    imports_end = template.index("# fmt: off")
    return (f"# Generated by perturb.response.codegen (order {order}, {_label(kept)}): "
            "do not edit.\n"
            + template[:imports_end] + series_source(order, kept) + "\n\n"
            + template[imports_end:])


def _label(kept: Truncation) -> str:
    if kept == PAPER_TRUNCATION:
        return "Eq. 2.6"
    return f"k_j to j = {kept.spring_degree}, d_j to j = {kept.damping_degree}"


def series_kernels(order: int, truncation: Truncation = PAPER_TRUNCATION) -> ModuleType:
    """The compiled kernels of the order-N series of ``truncation`` (generated once, then
    cached; one module serves every contact whose series keeps the same terms)."""
    kept = kernel_truncation(order, truncation)
    with _LOCK:
        if (order, kept) not in _LOADED:
            _LOADED[order, kept] = _load(order, kept)
        return _LOADED[order, kept]


def series_kernels_built(order: int, truncation: Truncation = PAPER_TRUNCATION) -> bool:
    """Whether the kernels of the order and truncation are loaded, or generated, intact
    and compiled in the cache (numba's index files beside the module: its machine code
    is there)."""
    kept = kernel_truncation(order, truncation)
    if (order, kept) in _LOADED:
        return True
    path = _path(order, kept)
    return intact(path) and machine_code_index(path) is not None


def _path(order: int, kept: Truncation) -> Path:
    key = ("series", order) if kept == PAPER_TRUNCATION else (
        "series", order, kept.spring_degree, kept.damping_degree)
    return usable_cache_dir() / f"series_{cache_key(key, _SOURCES)}.py"


def _smoke(module: ModuleType) -> None:
    """Call every kernel that ``frequency`` calls once, with the argument types of the
    real calls.

    numba loads a kernel's machine code from its cache at the first call, not at
    import: a truncated or garbled cache file shows only here (and is then rebuilt
    by ``_load``).
    """
    import numpy as np

    one = np.ones(1)
    k_d = np.ones(len(module.COEFFICIENTS))
    shape = (1 + len(NEXT_ORDERS), module.TOP_HARMONIC + 1, 1)
    real, imag = np.zeros(shape), np.zeros(shape)
    tables = (np.ones((shape[1], 4)), np.zeros((shape[1], 4)))
    module.find_roots(1.0, 1e3 * one, np.linspace(5e2, 2e3, 3), np.zeros(2), module.ORDER + 1,
                      5e2, 2e3, 1.0, k_d, 1e3)
    module.nearby_roots(1.0, one, one, one, 1.0, k_d, 1.0)
    module.harmonics_lanes(one, one, one, 1.0, k_d, real, imag)
    module.waveform_extrema(real[0], imag[0], one, *tables, one.copy(), one.copy())
    module.change_peak_to_peak(real[1], imag[1], one, real[0], imag[0], one, *tables, one.copy())


def _load(order: int, kept: Truncation) -> ModuleType:
    """The module of order N and truncation ``kept``, written, compiled and loaded by
    ``cache.load_generated`` (a damaged file or numba cache: rebuilt once)."""
    path = _path(order, kept)
    return load_generated(path, f"_contact_{path.stem}", lambda: _module_source(order, kept),
                          _smoke)
