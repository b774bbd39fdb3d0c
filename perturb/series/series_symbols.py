"""Symbols of the perturbation series of Eq. 2.6-2.10, with systematic names.

Eq. 2.6 is written with the symbols of its own coefficients (``c``, ``h``,
``G``, ``omega0``); the series adds the non-linear natural frequency ``omega``
(Eq. 2.7), the excitation ``Omega = 2 pi f_e``, the book-keeping ``eps`` and,
per order ``n`` and harmonic ``k`` of the excitation:

- ``A_n_k``, ``phi_n_k``: amplitude and phase of the solution,
  ``u_n = sum_k A_n_k cos(k Omega t + phi_n_k)``; the mean (``k = 0``) has a
  signed amplitude and no phase;
- ``F_n_k``, ``psi_n_k``: amplitude and phase of harmonic ``k`` of the right
  side of the order-``n`` equation;
- ``b_n``: the frequency corrections, ``omega^2 = omega0^2 + sum_n eps^n b_n``;
- ``k_j``, ``d_j``: the coefficients of u^j and u^j u' of the equation in contact
  (``truncation.py``); k_2 is Eq. 2.6's ``h``, d_0 is ``2c``;
- ``H_k``, ``theta_k``: gain and phase of the linear transfer of harmonic ``k``,
  ``1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega) = H_k exp(i theta_k)``.

Examples
--------
>>> amplitude(2, 1), phase(2, 1), forcing_amplitude(3, 2), b(4)
(A_2_1, phi_2_1, F_3_2, b_4)
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from perturb.common import check_int

__all__ = ["c", "h", "G", "omega", "omega0", "Omega", "eps", "t"]
__all__ += ["amplitude", "phase", "forcing_amplitude", "forcing_phase", "b", "gain", "lag"]
__all__ += ["complex_amplitude", "check_order", "stiffness", "damping", "coefficient"]

# Coefficients of Eq. 2.6 (c, h, G, omega0) and of the series (Eq. 2.7).
c, h, omega, omega0, Omega = sp.symbols("c h omega omega0 Omega", positive=True)
G = sp.Symbol("G", nonnegative=True)
eps = sp.Symbol("epsilon", positive=True)
t = sp.Symbol("t", real=True)


@lru_cache(maxsize=None)
def amplitude(n: int, k: int) -> sp.Symbol:
    """A_n_k; a mean (k = 0) is signed, other amplitudes are >= 0."""
    return (
        sp.Symbol(f"A_{n}_{k}", real=True) if k == 0 else sp.Symbol(f"A_{n}_{k}", nonnegative=True)
    )


@lru_cache(maxsize=None)
def phase(n: int, k: int) -> sp.Symbol:
    return sp.Symbol(f"phi_{n}_{k}", real=True)


@lru_cache(maxsize=None)
def forcing_amplitude(n: int, k: int) -> sp.Symbol:
    return sp.Symbol(f"F_{n}_{k}", real=True)


@lru_cache(maxsize=None)
def forcing_phase(n: int, k: int) -> sp.Symbol:
    return sp.Symbol(f"psi_{n}_{k}", real=True)


@lru_cache(maxsize=None)
def b(n: int) -> sp.Symbol:
    return sp.Symbol(f"b_{n}", real=True)


@lru_cache(maxsize=None)
def gain(k: int) -> sp.Symbol:
    return sp.Symbol(f"H_{k}", positive=True)


@lru_cache(maxsize=None)
def lag(k: int) -> sp.Symbol:
    return sp.Symbol(f"theta_{k}", real=True)


@lru_cache(maxsize=None)
def stiffness(j: int) -> sp.Symbol:
    """k_j, the coefficient of u^j in the restoring force over M; k_2 is Eq. 2.6's h."""
    return h if j == 2 else sp.Symbol(f"k_{j}", real=True)


@lru_cache(maxsize=None)
def damping(j: int) -> sp.Symbol:
    """d_j, the coefficient of u^j u' in the damping force over M (d_0 = 2c)."""
    return 2 * c if j == 0 else sp.Symbol(f"d_{j}", real=True)


def coefficient(kind: str, j: int) -> sp.Expr:
    """k_j (``kind`` "k") or d_j (``kind`` "d"): a coefficient of the equation in contact."""
    return stiffness(j) if kind == "k" else damping(j)


@lru_cache(maxsize=None)
def complex_amplitude(n: int, k: int, conjugate: bool = False) -> sp.Symbol:
    """z_n_k = A_n_k exp(i phi_n_k) (or its conjugate ``zc_n_k``), for compiling."""
    return sp.Symbol(f"{'zc' if conjugate else 'z'}_{n}_{k}")


def check_order(order: object, name: str = "order", minimum: int = 0) -> int:
    """Return ``order`` as an int, or raise a ValueError naming the argument (``check_int``).

    Examples
    --------
    >>> check_order(3)
    3
    >>> check_order(2.5)
    Traceback (most recent call last):
    ...
    ValueError: `order` must be an integer >= 0, got 2.5.
    """
    return check_int(name, order, minimum)
