"""The derived series as fast numeric formulas (``lambdify`` with ``cse=True``).

Each harmonic is carried as a complex amplitude ``z_n_k = A_n_k exp(i phi_n_k)``
in the frame where u0 has phase 0 (``z_0_1 = A0``): every phi_n_k is k phi0 plus
a part that does not depend on phi0, and b_n does not depend on phi0 at all.
The chain of closed forms (right side, b_n, transfer) is composed without
expanding, and ``lambdify(..., cse=True)`` shares the common parts.

Deriving and lambdifying orders 0 to 10 takes 0.4-0.7 s, every process (measured
2026-11-23; against about 0.03 s to import them from the disk). The
lambdified code is plain arithmetic, so each order's formulas are also written
to the cache on disk (``perturb.cache``) as a Python module, ``formulas_KEY.py``,
under a key made of the order and the code of every file that shapes them
(``SERIES_SOURCES``); a later process imports that instead of deriving.

Examples
--------
>>> import numpy as np
>>> formulas = compile_series(2, "paper")
>>> formulas.arguments
('A0', 'omega', 'Omega', 'c', 'h')
>>> b2 = formulas.b(1e-7, 9000.0, 4000.0, 100.0, 2e14)
>>> float(np.round(b2[0], 3))
-16599679.205
"""

from __future__ import annotations

import inspect
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import ModuleType
from typing import Callable

import numpy as np
import numpy.typing as npt
import sympy as sp

from ..cache import (
    SERIES_SOURCES,
    CacheWarning,
    cache_key,
    import_generated,
    intact,
    remove_generated,
    usable_cache_dir,
    write_generated,
)
from . import series_symbols as sym
from .formulas import SeriesFormulas, compile_series
from .lindstedt import Series, derive, transfer

__all__ = ["compile_series", "formulas_cached", "CompiledSeries", "complex_chain",
           "SeriesFormulas", "lambdified_series", "lambdify_chain", "chain_arguments"]

#: The arguments of every compiled formula of Eq. 2.6, in order; a series that keeps
#: more of the equation in contact takes its other coefficients after h.
A0 = sp.Symbol("A0", positive=True)
ARGUMENTS = (A0, sym.omega, sym.Omega, sym.c, sym.h)


def chain_arguments(coefficients: tuple[tuple[str, int], ...]) -> tuple[sp.Symbol, ...]:
    """A0, omega, Omega, c, then the coefficients (h = k_2 first)."""
    return (*ARGUMENTS[:4], *(sym.coefficient(kind, j) for kind, j in coefficients))


# Eq. 2.8 in the frame of u0: z_0_1 = conj(z_0_1) = A_0_1 = A0.
_FRAME = {
    sym.complex_amplitude(0, 1): A0,
    sym.complex_amplitude(0, 1, True): A0,
    sym.amplitude(0, 1): A0,
}


def complex_chain(series: Series) -> list[tuple[sp.Symbol, sp.Expr]]:
    """The closed forms as ordered assignments ``symbol = expression``.

    Each expression uses the arguments and the symbols assigned before it:
    b_n, A_n_0 (means, real), z_n_k (harmonics) and the conjugates zc_n_k,
    which are not assigned here (the evaluator conjugates z_n_k).
    """
    chain: list[tuple[sp.Symbol, sp.Expr]] = []
    for n in range(1, series.order + 1):
        equation = series.equations[n]
        if equation.has_b:
            # Eq. 2.10 / A.2: b_n A0^2 = -Re(sum of other fundamental terms * conj(z0)).
            total = sp.Add(*(t.value() + t.value(True) for t in equation.b_sources))
            chain.append((sym.b(n), (-total / (2 * A0)).xreplace(_FRAME)))
        for k, terms in equation.rhs.items():
            value = sp.Add(*(t.value() for t in terms)).xreplace(_FRAME)
            if k == 0:
                # The mean: omega^2 A_n_0 = F_n_0 (Eq. 2.9, A.1).
                conjugate = sp.Add(*(t.value(True) for t in terms)).xreplace(_FRAME)
                chain.append((sym.amplitude(n, 0), (value + conjugate) / (2 * sym.omega**2)))
            else:
                chain.append((sym.complex_amplitude(n, k), value * transfer(k)))
    return chain


@dataclass(frozen=True)
class _Step:
    """One lambdified assignment of the chain."""

    name: str
    kind: str  # "b", "mean" or "harmonic"
    inputs: tuple[str, ...]
    function: Callable


@lru_cache(maxsize=None)
def _compile_step(symbol: sp.Symbol, expr: sp.Expr) -> _Step:
    """One formula of the chain lambdified (kept: the chain of order N repeats most of
    those of the orders below it, 160 of the 205 steps of orders 0 to 10)."""
    inputs = tuple(sorted((s for s in expr.free_symbols), key=str))
    name = str(symbol)
    kind = "b" if name.startswith("b_") else ("mean" if name.startswith("A_") else "harmonic")
    function = sp.lambdify(inputs, expr, modules="numpy", cse=True)
    return _Step(name, kind, tuple(str(s) for s in inputs), function)


@dataclass(frozen=True)
class CompiledSeries(SeriesFormulas):
    """Lambdified formulas of a series; arguments ``(A0, omega, Omega, c, *coefficients)``.

    Every formula of the chain (b_n, means, complex harmonics) is lambdified on
    its own with ``cse=True`` and evaluated in order, so that nothing is
    expanded or computed twice.

    Attributes
    ----------
    order : int
    b_orders : tuple of int
        The n of the non-zero b_n, in the order ``b`` returns them.
    keys : tuple of (int, int)
        The (n, k) of the harmonics that ``amplitudes`` returns, in order.
    coefficients : tuple of (str, int)
        The equation's coefficients after c: ("k", 2) (h), then any k_j and d_j the
        truncation keeps (``Series.coefficients``).
    """

    order: int
    b_orders: tuple[int, ...]
    keys: tuple[tuple[int, int], ...]
    steps: tuple[_Step, ...]
    coefficients: tuple[tuple[str, int], ...] = (("k", 2),)

    @property
    def arguments(self) -> tuple[str, ...]:
        return tuple(str(a) for a in chain_arguments(self.coefficients))

    def evaluate(
        self,
        A0: npt.ArrayLike,
        omega: npt.ArrayLike,
        Omega: npt.ArrayLike,
        c: npt.ArrayLike,
        *coefficients: npt.ArrayLike,
        until: str | None = None,
    ) -> dict[str, np.ndarray]:
        """Run the chain; return every assigned value by name (z_n_k complex)."""
        values = (A0, omega, Omega, c, *coefficients)
        if len(values) != len(self.arguments):
            raise ValueError(f"expected the arguments {self.arguments}, got {len(values)}.")
        env = dict(zip(self.arguments, np.broadcast_arrays(*map(np.asarray, values))))
        env["z_0_1"] = env["zc_0_1"] = env["A_0_1"] = env["A0"]
        for step in self.steps:
            value = step.function(*(env[name] for name in step.inputs))
            if step.kind == "harmonic":
                env[step.name] = value
                env["zc" + step.name[1:]] = np.conj(value)
            else:
                env[step.name] = np.real(value)
            if step.name == until:
                break
        return env


@lru_cache(maxsize=None)
def lambdified_series(order: int) -> CompiledSeries:
    """The closed forms of Eq. 2.6's order-N series, lambdified (cached, in this process
    and on disk)."""
    path = _formulas_path(order)
    if formulas_cached(order):
        try:
            return _from_module(_import_formulas(path, order))
        except Exception:  # a garbled file: derived again, and written anew
            remove_generated(path)
    compiled = lambdify_chain(derive(order, "paper"))
    source = _formulas_source(compiled)
    if source is not None:
        try:
            write_generated(path, source)
        except OSError as error:  # a full disk: the formulas are derived, only not kept
            warnings.warn(f"the formulas of order {order} are not cached ({error})",
                          CacheWarning, stacklevel=2)
    return compiled


def lambdify_chain(series: Series) -> CompiledSeries:
    """The closed forms of any derived series, lambdified (not cached: a consistent
    series past order 4 or so takes long; ``compile_series`` evaluates those by
    ``NumericSeries``, and the tests hold the two routes together)."""
    steps = tuple(_compile_step(symbol, expr) for symbol, expr in complex_chain(series))
    return CompiledSeries(series.order, series_b_orders(series), series_keys(series), steps,
                          series.coefficients)


def formulas_cached(order: int) -> bool:
    """Whether the formulas of Eq. 2.6's order-N series are on disk, whole
    (``compile_series`` then derives nothing)."""
    return intact(_formulas_path(order))


def _formulas_path(order: int) -> Path:
    return usable_cache_dir() / f"formulas_{cache_key(('formulas', order), SERIES_SOURCES)}.py"


def _formulas_source(compiled: CompiledSeries) -> str | None:
    """The module of ``compiled``'s formulas: each step's lambdified code, renamed; None
    if a step's code needs a name from lambdify's namespace (then it is not cached)."""
    functions = []
    for i, step in enumerate(compiled.steps):
        if step.function.__code__.co_names:
            return None
        try:  # lambdify keeps its code in linecache, which a caller may have cleared
            source = inspect.getsource(step.function)
        except OSError:
            return None
        functions.append(source.replace("def _lambdifygenerated(", f"def step_{i}(", 1))
    steps = tuple((step.name, step.kind, step.inputs) for step in compiled.steps)
    return "\n".join([
        f"# Generated by perturb.series.compiled (order {compiled.order}): do not edit.",
        f"ORDER = {compiled.order!r}", f"B_ORDERS = {compiled.b_orders!r}",
        f"KEYS = {compiled.keys!r}", f"STEPS = {steps!r}", "", *functions,
        f"FUNCTIONS = ({''.join(f'step_{i}, ' for i in range(len(steps)))})", ""])


def _import_formulas(path: Path, order: int) -> ModuleType:
    def check(module: ModuleType) -> None:
        if module.ORDER != order or len(module.FUNCTIONS) != len(module.STEPS):
            raise ValueError(f"{path} does not hold the formulas of order {order}")

    return import_generated(path, f"_series_formulas_{path.stem}", check)


def _from_module(module: ModuleType) -> CompiledSeries:
    steps = tuple(_Step(name, kind, tuple(inputs), function)
                  for (name, kind, inputs), function in zip(module.STEPS, module.FUNCTIONS))
    return CompiledSeries(module.ORDER, tuple(module.B_ORDERS),
                          tuple(tuple(key) for key in module.KEYS), steps)


def series_b_orders(series: Series) -> tuple[int, ...]:
    """The n of the non-zero b_n of ``series``, increasing."""
    return tuple(n for n in range(1, series.order + 1) if series.has_b(n))


def series_keys(series: Series) -> tuple[tuple[int, int], ...]:
    """The (n, k) of every harmonic of ``series``, by order then harmonic."""
    return tuple((n, k) for n in range(series.order + 1) for k in series.harmonics(n))
