"""The series of any truncation evaluated by numbers: the Lindstedt scheme on samples.

The closed forms of ``derive`` are exact, but for a contact whose laws are no
polynomials (m2 or l not an integer) the consistent series holds every k_j u^j and
d_j u^j u' the order reaches, and its right sides double in size with each order
(some 16,000 terms at order 10, against 380 for Eq. 2.6): too many to compile as
straight-line code. The same scheme is carried out here on numbers, for a batch of
lanes at once:

- each u_n is held as its complex harmonics z_n_k (k = 0..N+1) in the frame of u0
  (z_0_1 = A0), and sampled at S equally spaced phases of a period, with its
  derivative (i k Omega z_n_k);
- the right side of order n (``lindstedt._right_side``) is built on the samples,
  where a product of solutions is a product of numbers: sum_k b_k u_(n-k),
  - k_j (u^j)_(n-j+1) and - d_j (u^j u')_(n-j), the powers (u^j)_m built once each;
- its harmonics come back by a discrete Fourier sum, exact for a trigonometric
  polynomial of degree below S/2 (the right side of order n has degree n+1);
- b_n cancels the part of harmonic 1 in phase with u0, and each harmonic k goes
  through the transfer 1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega), as in
  ``compiled.complex_chain``.

``NumericSeries`` answers as ``CompiledSeries`` does, so every route that takes one
takes the other; tests/test_truncation.py holds the two together on every truncation
the closed forms can be compiled for.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import numpy.typing as npt

from .formulas import SeriesFormulas
from .truncation import Truncation

__all__ = ["NumericSeries", "numeric_series"]


class NumericSeries(SeriesFormulas):
    """The order-N series of ``truncation`` as numbers; arguments ``(A0, omega, Omega, c,
    *coefficients)``, the coefficients named by ``coefficients`` (h = ("k", 2) first).

    Attributes
    ----------
    order : int
    truncation : Truncation
    coefficients : tuple of (str, int)
        ("k", j) for k_j, j >= 2, then ("d", j) for d_j, j >= 1: the arguments after c.
    b_orders : tuple of int
        The n of the b_n that ``b`` returns (the even n >= 2).
    keys : tuple of (int, int)
        The (n, k) of the harmonics that ``amplitudes`` returns (k = ..., n-1, n+1).
    """

    def __init__(self, order: int, truncation: Truncation) -> None:
        self.order = order
        self.truncation = truncation
        spring, damping = truncation.at_order(order)
        self.spring, self.damping = spring, damping
        self.coefficients = truncation.coefficients(order)
        nonlinear = spring >= 2 or damping >= 1
        self.b_orders = tuple(range(2, order + 1, 2)) if nonlinear else ()
        self.keys = tuple((n, k) for n in range(order + 1) for k in range(n + 2)
                          if (n + 1 - k) % 2 == 0)
        self.arguments = ("A0", "omega", "Omega", "c",
                          *("h" if (kind, j) == ("k", 2) else f"{kind}_{j}"
                            for kind, j in self.coefficients))
        # S samples resolve the right side's top harmonic N+1 (and N+2 for safety).
        samples = 2 * (order + 2) + 2
        phases = 2 * np.pi * np.arange(samples) / samples
        self._basis = np.exp(1j * np.outer(np.arange(order + 2), phases))  # (K+1, S)
        self._analysis = np.conj(self._basis).T * (2.0 / samples)  # (S, K+1)
        self._analysis[:, 0] /= 2

    def evaluate(self, A0: npt.ArrayLike, omega: npt.ArrayLike, Omega: npt.ArrayLike,
                 c: npt.ArrayLike, *coefficients: npt.ArrayLike,
                 until: str | None = None) -> dict[str, np.ndarray]:
        """Run the scheme; every value by the names of ``CompiledSeries.evaluate``."""
        self._check_count(coefficients)
        A0, omega, Omega, c, *coefs = np.broadcast_arrays(
            *(np.asarray(a, dtype=float) for a in (A0, omega, Omega, c, *coefficients)))
        shape = A0.shape
        A0, omega, Omega, c = (a.reshape(-1) for a in (A0, omega, Omega, c))
        k_of = dict(zip(self.coefficients, (x.reshape(-1) for x in coefs)))
        harmonics = np.arange(self._basis.shape[0])
        derivative = 1j * harmonics[None, :] * Omega[:, None]
        env: dict[str, np.ndarray] = {"A0": A0}
        z = np.zeros((A0.size, harmonics.size), dtype=complex)
        z[:, 1] = A0
        u, du = [self._samples(z)], [self._samples(z * derivative)]
        powers: dict[tuple[int, int], np.ndarray] = {}
        b: dict[int, np.ndarray] = {}

        def power(j: int, m: int) -> np.ndarray:
            """(u^j)_m on the samples: the terms of eps^m in u^j."""
            if j == 1:
                return u[m]
            if (j, m) not in powers:
                powers[(j, m)] = sum(power(j - 1, m - i) * u[i] for i in range(m + 1))
            return powers[(j, m)]

        def with_velocity(j: int, m: int) -> np.ndarray:
            return sum(power(j, m - i) * du[i] for i in range(m + 1))

        for n in range(1, self.order + 1):
            rhs = np.zeros_like(u[0])
            for k, b_k in b.items():  # sum_k b_k u_(n-k)
                rhs += b_k[:, None] * u[n - k]
            for j in range(2, min(self.spring, n + 1) + 1):  # - k_j (u^j)_(n-j+1)
                rhs -= k_of[("k", j)][:, None] * power(j, n - j + 1)
            for j in range(1, min(self.damping, n) + 1):  # - d_j (u^j u')_(n-j)
                rhs -= k_of[("d", j)][:, None] * with_velocity(j, n - j)
            forcing = _products(rhs, self._analysis)  # harmonics k = 0..N+1, as z_n_k
            forcing[:, (n + 1 - harmonics) % 2 == 1] = 0  # u_n holds k = n+1, n-1, ...
            if n in self.b_orders:
                # Eq. 2.10, A.2: b_n A0 cancels the fundamental's part in phase with u0.
                b[n] = -forcing[:, 1].real / A0
                forcing[:, 1] = 1j * forcing[:, 1].imag
                env[f"b_{n}"] = b[n].reshape(shape)
            z = np.zeros_like(forcing)
            z[:, 0] = forcing[:, 0].real / omega**2  # the mean: omega^2 A_n_0 = F_n_0
            k = harmonics[1:]
            z[:, 1:] = forcing[:, 1:] / (omega[:, None] ** 2 - (k * Omega[:, None]) ** 2
                                         + 2j * k * c[:, None] * Omega[:, None])
            for kept in range(n + 1, -1, -2):
                name = f"A_{n}_0" if kept == 0 else f"z_{n}_{kept}"
                env[name] = (z[:, 0].real if kept == 0 else z[:, kept]).reshape(shape)
            if until is not None and until in env:
                break
            u.append(self._samples(z))
            du.append(self._samples(z * derivative))
        env["z_0_1"] = env["A_0_1"] = A0.reshape(shape)
        return env

    def _check_count(self, coefficients: tuple) -> None:
        """A ValueError unless there is one value per entry of ``coefficients``."""
        if len(coefficients) != len(self.coefficients):
            raise ValueError(f"expected {len(self.coefficients)} coefficients "
                             f"{self.arguments[4:]}, got {len(coefficients)}.")

    def _samples(self, z: np.ndarray) -> np.ndarray:
        """u = sum_k Re(z_k exp(i k theta)) at the S phases theta (lanes, S)."""
        return _products(z, self._basis).real

    def __repr__(self) -> str:
        return (f"NumericSeries(order={self.order}, truncation={self.truncation.name!r}, "
                f"coefficients={self.arguments[4:]})")


def _products(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a @ b summed term by term in a fixed order: every lane's value is the same
    whatever the lanes beside it (a matrix product's blocking follows the batch's
    size, and a frequency band solved in chunks must equal the band solved at once)."""
    out = a[:, :1] * b[:1]
    for i in range(1, a.shape[1]):
        out = out + a[:, i:i + 1] * b[i:i + 1]
    return out


@lru_cache(maxsize=None)
def numeric_series(order: int, truncation: Truncation) -> NumericSeries:
    """The order-N series of ``truncation`` as numbers (cached per order and truncation)."""
    return NumericSeries(order, truncation)
