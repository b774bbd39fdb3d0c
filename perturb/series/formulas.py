"""A series as numeric formulas, whatever its truncation: the one entry point.

``compile_series`` hands Eq. 2.6's series to its lambdified closed forms
(``compiled.py``, sympy or its cache on disk) and any other truncation to the same
scheme carried out on numbers (``numeric.py``), which needs no sympy: a
consistent response in a new process derives and compiles nothing. Both answer as
``SeriesFormulas`` does.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import numpy.typing as npt

from perturb.common import check_int

from ..model.parameters import PAPER, ContactParameters
from .truncation import Truncation, truncation_for

__all__ = ["SeriesFormulas", "compile_series"]


class SeriesFormulas:
    """What every numeric form of a series answers, from its ``evaluate``: the b_n, the
    frequency shift of Eq. 2.7, the harmonics and the waveform. Arguments are
    ``(A0, omega, Omega, c, *coefficients)``, the coefficients those ``coefficients``
    names (h first)."""

    order: int
    b_orders: tuple[int, ...]
    keys: tuple[tuple[int, int], ...]
    coefficients: tuple[tuple[str, int], ...]

    def evaluate(self, *args, until: str | None = None) -> dict[str, np.ndarray]:
        raise NotImplementedError

    def b(self, *args: npt.ArrayLike) -> list[np.ndarray]:
        """The non-zero b_n (real), one per entry of ``b_orders``."""
        if not self.b_orders:
            return []
        env = self.evaluate(*args, until=f"b_{self.b_orders[-1]}")
        return [env[f"b_{n}"] for n in self.b_orders]

    def frequency_shift(self, *args: npt.ArrayLike) -> np.ndarray:
        """sum_n b_n = omega^2 - omega0^2 (Eq. 2.7); arguments as ``evaluate``."""
        values = self.b(*args)
        return sum(values) if values else np.zeros(np.broadcast(*args).shape)

    def amplitudes(self, *args: npt.ArrayLike) -> list[np.ndarray]:
        """Complex z_n_k (real for means), one per entry of ``keys``, with phi0 = 0."""
        env = self.evaluate(*args)
        return [env[f"A_{n}_0"] if k == 0 else env[f"z_{n}_{k}"] for n, k in self.keys]

    def harmonics(self, amplitudes: list[np.ndarray]) -> np.ndarray:
        """sum_n z_n_k for k = 0..K, shape (lanes, K + 1), from ``amplitudes``."""
        lanes = np.broadcast_shapes(*(np.shape(z) for z in amplitudes))  # any count
        top = max(k for _, k in self.keys)
        total = np.zeros((*lanes, top + 1), dtype=complex)
        for (_, k), z in zip(self.keys, amplitudes):
            total[..., k] += z
        return total

    def waveform(self, theta: npt.ArrayLike, *args: npt.ArrayLike) -> np.ndarray:
        """The reconstructed u = sum_n u_n at phases ``theta`` = Omega t (phi0 = 0).

        Returns an array of shape ``broadcast(args).shape + theta.shape``.

        Examples
        --------
        >>> import numpy as np
        >>> u = compile_series(0, "paper").waveform(np.array([0.0, np.pi]), 2.0, 1.0, 0.5, 0.1, 0.3)
        >>> u.tolist()
        [2.0, -2.0]
        """
        theta = np.asarray(theta, dtype=float)
        per_harmonic = self.harmonics(self.amplitudes(*args))
        basis = np.exp(1j * np.multiply.outer(np.arange(per_harmonic.shape[-1]), theta))
        return np.tensordot(per_harmonic, basis, axes=1).real


def compile_series(order: int, truncation: str | Truncation = "consistent",
                   parameters: ContactParameters = PAPER, *,
                   compiled: bool = True) -> SeriesFormulas:
    """The order-N series as fast numeric formulas (cached, in this process and on disk).

    Parameters
    ----------
    order : int
        The order N >= 0 of the series.
    truncation : {"consistent", "paper"} or Truncation
        Which terms of the equation in contact the series keeps (``derive``).
    parameters : ContactParameters
        The contact, which tells where its laws' Taylor series end.
    compiled : bool
        For a series other than Eq. 2.6's: the scheme as one numba kernel
        (``KernelSeries``: compiled once for every order and truncation, then cached on
        disk) or in numpy (``NumericSeries``: no compiling, many times slower; ``make
        bench`` measures both).

    Returns
    -------
    CompiledSeries, KernelSeries or NumericSeries
        Eq. 2.6's series (the paper's truncation, or a consistent one that keeps the
        same terms) as its closed forms lambdified (``CompiledSeries``); any other as
        the same scheme carried out on numbers, whose closed forms grow too fast to
        compile. All take ``(A0, omega, Omega, c, *coefficients)``.
    """
    order = check_int("order", order, minimum=0)
    if not isinstance(compiled, bool):
        raise ValueError(f"`compiled` must be True or False, got {compiled!r}.")
    resolved = truncation_for(truncation, parameters)
    return _formulas(order, Truncation(resolved.name, *resolved.at_order(order)), compiled)


@lru_cache(maxsize=None)
def _formulas(order: int, kept: Truncation, compiled: bool) -> SeriesFormulas:
    if kept.keeps_eq26_only(order):
        from .compiled import lambdified_series

        return lambdified_series(order)
    if compiled:
        from .kernel import kernel_series

        return kernel_series(order, kept)
    from .numeric import numeric_series

    return numeric_series(order, kept)


#: ``compile_series.cache_clear()`` empties what it keeps in this process (a study that
#: times first calls does).
compile_series.cache_clear = _formulas.cache_clear
