"""The backbone: the free, undamped frequency as a series in amplitude.

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

The contact's own spring (the consistent truncation) is the same recursion with every
Taylor term: in ``x = u / y0`` the power law with its weight reads
``W x'' + sum_j kappa_j x^j = 0``, ``kappa_j = binom(m2, j) / m2`` (``kappa_1 = 1``),
and ``-sum_{j>=2} kappa_j (x^j)_n`` replaces ``-sum x_i x_j``: coefficients that are
polynomials in m2 (exact rationals at a rational m2), with alpha = a / y0. At m2 = 2,
kappa_2 = 1/2 and no more: Eq. 2.6's coefficients over 2^k.

Examples
--------
>>> series = backbone_series(4, "paper")
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

from perturb.common import Result, result

from ..model.contact_model import ContactModel
from ..model.effects import EQ_2_6
from ..model.parameters import PAPER, ContactParameters
from .series_symbols import check_order
from .slow_orders import check_slow_order
from .truncation import truncation_for

__all__ = ["BackboneSeries", "backbone_series", "power_law_backbone_coefficients"]

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


def _lindstedt_poincare(order: int, kappa=None, normal=lambda q: q):
    """w_1..w_order of W, and the cosine arrays of x_1..x_{order+1}, for
    ``W x'' + x + sum_{j>=2} kappa[j] x^j = 0`` (``kappa`` None: kappa_2 = 1, no more).

    ``kappa`` and the results are exact numbers (Fraction) or sympy expressions, which
    ``normal`` (sympy.expand) keeps in normal form.
    """
    kappa = kappa if kappa is not None else [Fraction(0), Fraction(0), Fraction(1)]
    zero = Fraction(0)
    w = [zero] * (order + 1)
    x: list[Cosines] = [[], [Fraction(0), Fraction(1)]]  # x_0 unused, x_1 = cos(tau)
    powers: dict[tuple[int, int], Cosines] = {}

    def power(j: int, n: int) -> Cosines:
        """The coefficient of alpha^n in x^j, each x_i (i >= 1) known for i <= n - j + 1."""
        if j == 1:
            return x[n]
        if (j, n) not in powers:
            total: Cosines = []
            for i in range(1, n - j + 2):
                _add_into(total, _product(power(j - 1, n - i), x[i]), Fraction(1))
            powers[(j, n)] = [normal(q) for q in total]
        return powers[(j, n)]

    for n in range(2, order + 2):
        rhs: Cosines = []
        for j in range(2, min(n, len(kappa) - 1) + 1):
            if kappa[j] != 0:
                _add_into(rhs, power(j, n), -kappa[j])
        for k in range(1, n - 1):
            # -w_k x_{n-k}'' = +w_k j^2 a_j cos(j tau)
            _add_into(rhs, [j * j * a for j, a in enumerate(x[n - k])], w[k])
        rhs = [normal(q) for q in rhs]
        rhs.extend([Fraction(0)] * (2 - len(rhs)))
        # The secular cos(tau): the term w_{n-1} x_1'' = -w_{n-1} cos(tau) cancels it.
        w[n - 1] = -rhs[1]
        rhs[1] = Fraction(0)
        x.append([value / (1 - j * j) if j != 1 else Fraction(0) for j, value in enumerate(rhs)])
    return w, x[1:]


def power_law_kappa(m2, order: int) -> list:
    """kappa_j = binom(m2, j) / m2, j = 0..order+1: the power-law spring with its weight,
    ``(F_s + Q) / (M omega0^2 y0) = -((1 + x)^m2 - 1) / m2`` in x = u / y0 (Eq. 2.1-2.3).
    ``m2`` a Fraction (exact numbers) or a sympy expression."""
    kappa = [Fraction(0), Fraction(1)]
    term = Fraction(1)
    for j in range(2, order + 2):
        term = term * (m2 - (j - 1)) / j  # binom(m2, j) / m2 from binom(m2, j - 1) / m2
        kappa.append(term)
    return kappa


def _fractions(name: str, value) -> tuple[Fraction, ...]:
    try:
        return tuple(Fraction(q) for q in value)
    except (TypeError, ValueError, ZeroDivisionError):
        raise ValueError(f"`{name}` must be exact rationals such as '-5/12', "
                         f"got {value!r}.") from None


@result
class BackboneSeries(Result):
    """omega / omega0 = sum_k coefficients[k] alpha^k.

    Eq. 2.6's series (``truncation="paper"``) has alpha = h a / omega0^2 and is the
    same for every parameter set, through omega0 and h; the consistent series of a
    power-law contact has alpha = a / y0 (``settings["alpha"]``) and coefficients
    that are exact rationals of m2. ``model`` records the model whose omega0, y0 and
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
        Cosine coefficients of x_1 .. x_(order+1), ``x = alpha u / a``
        (JSON: strings).
    model : dict
        ``ContactModel(parameters, EQ_2_6).as_dict()`` (Eq. 2.6's series) or
        ``ContactModel(parameters).as_dict()``.
    settings : dict
        Empty for Eq. 2.6's series; ``{"truncation": "consistent", "alpha": "a / y0"}``
        for the power law's.
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

    def alpha_per_m(self) -> float:
        """alpha per metre of amplitude: h / omega0^2 (Eq. 2.6's series) or 1 / y0."""
        if self.settings.get("alpha") == "a / y0":
            return 1.0 / self.model["y0_m"]
        return self.model["h_per_m_s2"] / self.model["omega0_rad_s"] ** 2

    def extremes_m(self, alpha: float) -> tuple[float, float]:
        """(max u, min u) of the series orbit x = sum_n alpha^n x_n at ``alpha`` [m]."""
        tau = np.linspace(0.0, np.pi, 2049)  # x is even in tau: half a period holds both
        top = max(len(x) for x in self.waveform)
        table = np.cos(np.outer(np.arange(top), tau))
        x = sum(alpha ** (n + 1) * (np.array([float(q) for q in xn]) @ table[:len(xn)])
                for n, xn in enumerate(self.waveform) if xn)
        return float(x.max()) / self.alpha_per_m(), float(x.min()) / self.alpha_per_m()

    def peak_to_peak_m(self, alpha: float) -> float:
        """App = max u - min u of the series orbit at ``alpha`` [m]."""
        top, bottom = self.extremes_m(alpha)
        return top - bottom

    def frequency_at_app_hz(self, app_m) -> np.ndarray:
        """The series backbone's frequency [Hz] at peak-to-peak amplitudes ``app_m`` [m]
        (App of the series orbit). NaN where the series orbit loses contact
        (y0 + min u <= 0, Eq. 2.1: the free oscillation there is not the law's) or past
        the amplitude where its App stops growing.

        Examples
        --------
        >>> series = backbone_series(8)
        >>> [round(float(f), 2) for f in series.frequency_at_app_hz([1e-7, 1e-6])]
        [1477.9, nan]
        """
        from scipy.optimize import brentq

        app_m = np.atleast_1d(np.asarray(app_m, dtype=float))
        alphas = np.linspace(0.0, 2.0, 401)[1:]
        extremes = np.array([self.extremes_m(a) for a in alphas])
        apps = extremes[:, 0] - extremes[:, 1]
        # The last alpha before App stops growing or the orbit leaves the contact.
        stop = (np.diff(apps) <= 0) | (self.model["y0_m"] + extremes[1:, 1] <= 0)
        top = int(np.argmax(stop)) + 1 if stop.any() else alphas.size
        out = np.full(app_m.shape, np.nan)
        for i, target in enumerate(app_m):
            if 0 < target <= apps[top - 1]:
                alpha = brentq(lambda a, app=target: self.peak_to_peak_m(a) - app, 0.0,
                               alphas[top - 1], xtol=1e-15, rtol=1e-13)
                if self.model["y0_m"] + self.extremes_m(alpha)[1] > 0:
                    out[i] = self.model["f_n0_hz"] * self.frequency_ratio(alpha)
            elif target == 0:
                out[i] = self.model["f_n0_hz"]
        return out

    def as_strings(self) -> list[str]:
        """The coefficients as strings, ``["1", "0", "-5/12", ...]``."""
        return [str(q) for q in self.coefficients]

    def summary(self) -> str:
        shown = ", ".join(self.as_strings()[:5])
        more = ", ..." if len(self.coefficients) > 5 else ""
        return (f"BackboneSeries: omega/omega0 = sum_k c_k alpha^k to order {self.order}, "
                f"alpha = {self.settings.get('alpha', 'h a / omega0^2')} "
                f"(a: {self.amplitude} amplitude): {shown}{more}; "
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
def _exact_series(order: int, m2: Fraction | None = None
                  ) -> tuple[tuple[Fraction, ...], tuple[tuple[Fraction, ...], ...]]:
    """(coefficients, waveform) of the backbone to alpha^order, computed once per order:
    Eq. 2.6's (``m2`` None) or the power law's of exponent ``m2``."""
    kappa = None if m2 is None else power_law_kappa(m2, order)
    w, x = _lindstedt_poincare(order, kappa)
    return tuple(_series_sqrt(w, order)), tuple(tuple(xi) for xi in x)


def power_law_backbone_coefficients(order: int):
    """omega / omega0 of the power-law contact as a series in alpha = a / y0, with
    coefficients that are polynomials in the symbol m2 (sympy).

    Examples
    --------
    >>> power_law_backbone_coefficients(2)[2].factor()
    -(m2 - 1)*(2*m2 + 1)/48
    """
    import sympy as sp

    from ..model.symbols import m2

    order = check_order(order)
    w, _ = _lindstedt_poincare(order, power_law_kappa(m2, order), sp.expand)
    return [sp.expand(q) for q in _series_sqrt(w, order)]


def _exact_m2(m2: float) -> Fraction:
    """m2 as an exact rational: 1.5 -> 3/2, and 4/3 as a float -> 4/3 (the nearest
    fraction with a denominator up to 1000, where it is within 1e-12); a float's
    shortest decimal otherwise."""
    near = Fraction(m2).limit_denominator(1000)
    return near if abs(near - Fraction(m2)) <= 1e-12 * abs(m2) else Fraction(repr(float(m2)))


def backbone_series(order: int, truncation: str = "consistent",
                    parameters: ContactParameters = PAPER, *,
                    allow_slow: bool = False) -> BackboneSeries:
    """The free undamped backbone of the contact to alpha^order, exactly.

    Parameters
    ----------
    order : int
        Highest power of alpha kept, >= 0.
    truncation : {"consistent", "paper"}
        "consistent": the power-law spring of ``parameters`` with every term of its
        Taylor series, in alpha = a / y0, the coefficients exact rationals of m2
        (at m2 = 2 those of "paper" over 2^k); "paper": Eq. 2.6's spring (h u^2), in
        alpha = h a / omega0^2, the same for every contact.
    parameters : ContactParameters
        The contact (its m2 shapes the consistent series; y0, omega0 and h turn alpha
        into an amplitude).
    allow_slow : bool
        Take an order above the one measured to take about a minute
        (``perturb.series.slow_orders``: 100, or 50 for a non-integer m2); refused otherwise.

    Returns
    -------
    BackboneSeries
        A new object per call; the exact series of an order is computed once.

    Examples
    --------
    >>> backbone_series(2, "paper").coefficients[2]
    Fraction(-5, 12)
    >>> backbone_series(2).coefficients[2]  # the paper's contact: alpha = a / y0
    Fraction(-5, 48)
    >>> backbone_series(-2)
    Traceback (most recent call last):
    ...
    ValueError: `order` must be an integer >= 0, got -2.
    """
    start = time.perf_counter()
    resolved = truncation_for(truncation, parameters)
    order = check_slow_order(order, "backbone", resolved, parameters, allow_slow=allow_slow)
    if resolved.name == "paper":
        coefficients, waveform = _exact_series(order)
        model, settings = ContactModel(parameters, EQ_2_6).as_dict(), {}
    else:
        coefficients, waveform = _exact_series(order, _exact_m2(parameters.m2))
        model = ContactModel(parameters).as_dict()
        settings = {"truncation": "consistent", "alpha": "a / y0"}
    return BackboneSeries(
        order=order,
        amplitude="first-harmonic",
        coefficients=coefficients,
        waveform=waveform,
        model=model,
        settings=settings,
        elapsed_s=time.perf_counter() - start,
    )
