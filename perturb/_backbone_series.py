"""The backbone of Eq. 2.6: the free, undamped frequency as a series in amplitude.

Without damping and forcing, Eq. 2.6 is ``u'' + omega0^2 u + h u^2 = 0``. With
``x = h u / omega0^2``, ``tau = omega t`` and ``W = (omega / omega0)^2`` it reads
``W x'' + x + x^2 = 0``. The Lindstedt-Poincare series

    x = sum_{n>=1} alpha^n x_n(tau),   x_1 = cos(tau),   W = 1 + sum_k w_k alpha^k

with ``alpha = h a / omega0^2`` (``a`` the amplitude of the fundamental, so no
x_n with n >= 2 holds cos(tau)) gives at order alpha^n

    x_n'' + x_n = -sum_{k=1}^{n-1} w_k x_{n-k}'' - sum_{i+j=n} x_i x_j,

and w_{n-1} removes the secular cos(tau) on the right. Each x_n is a cosine
polynomial held as an array of exact ``Fraction`` coefficients, which is much
faster than general symbolic simplification. Finally
``omega / omega0 = sqrt(W) = 1 - (5/12) alpha^2 + ...`` (Nayfeh and Mook).

Examples
--------
>>> series = backbone_series(4)
>>> series.as_strings()
['1', '0', '-5/12', '0', '-485/1728']
>>> round(series.frequency_ratio(0.1), 6)
0.995805
"""

from __future__ import annotations

import time
from fractions import Fraction
from functools import lru_cache

import numpy as np

from common import Result, result

from ._effects import EQ_2_6
from ._model import ContactModel
from ._series_symbols import check_order

__all__ = ["BackboneSeries", "backbone_series"]

Cosines = list[Fraction]  # index j: coefficient of cos(j tau)


def _product(a: Cosines, b: Cosines) -> Cosines:
    """(sum a_p cos p tau)(sum b_q cos q tau), by cos p cos q = (cos(p+q) + cos(p-q)) / 2."""
    out = [Fraction(0)] * (len(a) + len(b) - 1)
    for p, ap in enumerate(a):
        if ap:
            for q, bq in enumerate(b):
                if bq:
                    half = ap * bq / 2
                    out[p + q] += half
                    out[abs(p - q)] += half
    return out


def _add_into(total: Cosines, part: Cosines, scale: Fraction) -> None:
    total.extend([Fraction(0)] * (len(part) - len(total)))
    for j, value in enumerate(part):
        total[j] += scale * value


def _series_sqrt(w: list[Fraction], order: int) -> list[Fraction]:
    """Coefficients of sqrt(1 + sum_k w_k alpha^k) to alpha^order (w[0] unused)."""
    root = [Fraction(1)] + [Fraction(0)] * order
    for n in range(1, order + 1):
        # (root^2)_n = w_n: 2 root_n + sum_{0<i<n} root_i root_{n-i} = w_n.
        cross = sum((root[i] * root[n - i] for i in range(1, n)), Fraction(0))
        root[n] = (w[n] - cross) / 2
    return root


def _lindstedt_poincare(order: int) -> tuple[list[Fraction], list[Cosines]]:
    """w_1..w_order of W, and the cosine arrays of x_1..x_{order+1}."""
    w = [Fraction(0)] * (order + 1)
    x: list[Cosines] = [[], [Fraction(0), Fraction(1)]]  # x_0 unused, x_1 = cos(tau)
    for n in range(2, order + 2):
        rhs: Cosines = []
        for i in range(1, n):
            _add_into(rhs, _product(x[i], x[n - i]), Fraction(-1))
        for k in range(1, n - 1):
            # -w_k x_{n-k}'' = +w_k j^2 a_j cos(j tau)
            _add_into(rhs, [j * j * a for j, a in enumerate(x[n - k])], w[k])
        rhs.extend([Fraction(0)] * (2 - len(rhs)))
        # The secular cos(tau): the term w_{n-1} x_1'' = -w_{n-1} cos(tau) cancels it.
        w[n - 1] = -rhs[1]
        rhs[1] = Fraction(0)
        x.append([value / (1 - j * j) if j != 1 else Fraction(0) for j, value in enumerate(rhs)])
    return w, x[1:]


def _fractions(name: str, value) -> tuple[Fraction, ...]:
    try:
        return tuple(Fraction(q) for q in value)
    except (TypeError, ValueError, ZeroDivisionError):
        raise ValueError(f"`{name}` must be exact rationals such as '-5/12', "
                         f"got {value!r}.") from None


@result
class BackboneSeries(Result):
    """omega / omega0 = sum_k coefficients[k] alpha^k, alpha = h a / omega0^2.

    The series is dimensionless: it holds for every parameter set, through
    omega0 and h. ``model`` records the paper's Eq. 2.6 model, whose omega0 and
    h turn alpha into an amplitude and omega / omega0 into a frequency.

    Attributes
    ----------
    order : int
        Highest power of alpha kept.
    amplitude : str
        What ``a`` is: ``"first-harmonic"``, the amplitude of the fundamental.
    coefficients : tuple of Fraction
        Exact coefficients of alpha^0 .. alpha^order (JSON: strings, ``"-5/12"``).
    waveform : tuple of tuple of Fraction
        Cosine coefficients of x_1 .. x_(order+1), ``x = h u / omega0^2``
        (JSON: strings).
    model : dict
        ``ContactModel(PAPER, EQ_2_6).as_dict()``.
    settings : dict
        Empty: the order is the one setting.
    elapsed_s : float
        Wall time of this call [s] (a repeated order is served from a cache).
    """

    order: int
    amplitude: str
    coefficients: tuple[Fraction, ...]
    waveform: tuple[tuple[Fraction, ...], ...]
    model: dict
    settings: dict
    elapsed_s: float

    def frequency_ratio(self, alpha: float | np.ndarray) -> float | np.ndarray:
        """omega / omega0 at ``alpha`` (Horner's rule on the truncated series)."""
        alpha = np.asarray(alpha, dtype=float)
        total = np.zeros_like(alpha)
        for q in reversed(self.coefficients):
            total = total * alpha + float(q)
        return float(total) if total.ndim == 0 else total

    def as_strings(self) -> list[str]:
        """The coefficients as strings, ``["1", "0", "-5/12", ...]``."""
        return [str(q) for q in self.coefficients]

    def summary(self) -> str:
        shown = ", ".join(self.as_strings()[:5])
        more = ", ..." if len(self.coefficients) > 5 else ""
        return (f"BackboneSeries: omega/omega0 = sum_k c_k alpha^k to order {self.order}, "
                f"alpha = h a / omega0^2 (a: {self.amplitude} amplitude): {shown}{more}; "
                f"{self.elapsed_s:.3f} s")

    def table(self) -> str:
        return "\n".join(f"  c_{k} = {q}" for k, q in enumerate(self.coefficients))

    def as_dict(self) -> dict:
        data = super().as_dict()
        data["coefficients"] = self.as_strings()
        data["waveform"] = [[str(q) for q in x] for x in self.waveform]
        return data

    @classmethod
    def from_dict(cls, data: dict) -> BackboneSeries:
        series = super().from_dict(data)
        series.coefficients = _fractions("coefficients", series.coefficients)
        try:
            series.waveform = tuple(_fractions("waveform", x) for x in series.waveform)
        except TypeError:
            raise ValueError(f"`waveform` must be lists of rationals, got "
                             f"{series.waveform!r}.") from None
        return series


@lru_cache(maxsize=None)
def _exact_series(order: int) -> tuple[tuple[Fraction, ...], tuple[tuple[Fraction, ...], ...]]:
    """(coefficients, waveform) of the backbone to alpha^order, computed once per order."""
    w, x = _lindstedt_poincare(order)
    return tuple(_series_sqrt(w, order)), tuple(tuple(xi) for xi in x)


def backbone_series(order: int) -> BackboneSeries:
    """The free undamped backbone of Eq. 2.6 to alpha^order, exactly.

    Parameters
    ----------
    order : int
        Highest power of alpha = h a / omega0^2 kept, >= 0.

    Returns
    -------
    BackboneSeries
        A new object per call; the exact series of an order is computed once.

    Examples
    --------
    >>> backbone_series(2).coefficients[2]
    Fraction(-5, 12)
    >>> backbone_series(-2)
    Traceback (most recent call last):
    ...
    ValueError: `order` must be an integer >= 0, got -2.
    """
    start = time.perf_counter()
    order = check_order(order)
    coefficients, waveform = _exact_series(order)
    return BackboneSeries(
        order=order,
        amplitude="first-harmonic",
        coefficients=coefficients,
        waveform=waveform,
        model=ContactModel(effects=EQ_2_6).as_dict(),
        settings={},
        elapsed_s=time.perf_counter() - start,
    )
