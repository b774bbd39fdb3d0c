"""The numeric series of any truncation as one numba kernel, compiled once for every order.

``NumericSeries`` carries out the Lindstedt scheme on samples in numpy, every step on
arrays of shape (lanes, samples): correct, but its temporaries make it slow
(``tests/benchmarks/bench_truncation.py`` times the two). ``scheme_lanes`` carries
out the same scheme lane by lane on small work arrays that stay in the cache. The order,
the degrees of the truncation and the coefficients are arguments at run time, so the
kernel is compiled once (and cached on disk by numba) for every order and truncation.

Per lane, the right side of order n of the equation in contact (Eq. 2.5 carried on to
every power, ``truncation``) is built as ``NumericSeries`` builds it, with three
shortcuts that change nothing but the rounding:

- u_n is sampled at the phases theta_s = pi s / H, s = 0..H-1, of half a period only:
  u_n holds the harmonics k = n+1, n-1, ... (Eq. 2.9, A.1), all of one parity, so
  u_n(theta + pi) = (-1)^(n+1) u_n(theta), and so is every product of the right side of
  order n. The sum over the S = 2H phases of a period is twice that over the first H,
  and S = 2N + 4 > 2 (N + 1) resolves the right side's top harmonic N + 1 without
  aliasing. S follows the order N only, not the order a call stops at, so that ``b``,
  ``evaluate(until=...)`` and the whole run give the very same b_n, and each lane's
  numbers do not depend on the lanes beside it (a band solved in chunks equals the band
  solved at once, as for ``NumericSeries``).
- d_j (u^j u')_(n-j) = d_j / (j+1) d/dt (u^(j+1))_(n-j): the damping terms are the
  derivative of the same powers (u^j)_m (j + m = n + 1) that the spring terms
  - k_j (u^j)_(n-j+1) take, so no velocity is sampled and no product (u^j u')_m is
  formed; the derivative is i k Omega on harmonic k, after the Fourier sum.
- sum_k b_k u_(n-k) is added on the harmonics (b_k z_(n-k)_h), not on the samples.

The rest is as in ``NumericSeries``: (u^j)_m = sum_i (u^(j-1))_(m-i) u_i on the samples,
each built once; the harmonics of the right side F_n_k by a discrete Fourier sum;
b_n = -Re(F_n_1) / A0 cancels the part of the fundamental in phase with u0 (Eq. 2.10,
A.2), then z_n_k = F_n_k / (omega^2 - k^2 Omega^2 + 2 i k c Omega) and the mean
A_n_0 = Re(F_n_0) / omega^2 (Eq. 2.9, A.1), as ``compiled.complex_chain``.

``KernelSeries`` answers as ``NumericSeries`` does (its subclass, same arguments);
tests/test_series_kernel.py holds the two together.
"""

from __future__ import annotations

from functools import lru_cache

import numba
import numpy as np
import numpy.typing as npt

from .numeric import NumericSeries
from .truncation import Truncation

__all__ = ["KernelSeries", "kernel_series", "scheme_lanes"]

_JIT = {"cache": True, "error_model": "numpy"}  # numpy's rules: x / 0 is inf, no exception


@numba.njit(**_JIT)
def scheme_lanes(a0, omega, Omega, c, k_coef, d_coef, order, spring, damping, stop_order,
                 b_out, z_re_out, z_im_out):
    """The Lindstedt scheme of orders 1..``stop_order`` for every lane.

    Every size (order, degrees) is an argument, so one compilation serves every order
    and truncation; the work arrays are allocated once per call and each lane runs in
    them (lanes in the outer loop: a lane's samples and harmonics stay in the cache).

    Parameters
    ----------
    a0, omega, Omega, c : ndarray of float64, shape (L,)
        A0 (the amplitude of u0), omega, the drive's Omega and c (d_0 = 2c) per lane.
    k_coef : ndarray of float64, shape (spring + 1,) or longer
        k_coef[j] = k_j, j = 2..spring (k_2 = h; entries 0 and 1 unused).
    d_coef : ndarray of float64, shape (damping + 1,)
        d_coef[j] = d_j, j = 1..damping (entry 0 unused: d_0 = 2c is in the transfer).
    order : int
        The order N of the series: harmonics k = 0..N+1.
    spring, damping : int
        The highest j of k_j u^j and of d_j u^j u' kept (``Truncation.at_order(N)``).
    stop_order : int
        The last order computed (clipped to 0..N). Without harmonics asked for, only
        b of that order is (the frequency equation needs b_n up to N only). The values
        do not depend on it: the phases follow N.
    b_out : ndarray of float64, shape (N + 1, L)
        Out: b_n in row n for n = 0..stop_order (0 where the series has no b_n).
    z_re_out, z_im_out : ndarray of float64, shape (N + 1, N + 2, L) or (N + 1, N + 2, 0)
        Out: z_n_k (real part: A_n_0 at k = 0), rows n = 0..stop_order, z_0_1 = A0 and 0
        at the harmonics an order does not hold; with no lanes, no harmonic is written
        and the last order only gives its b.
    """
    lanes = a0.size
    top = order + 1  # the highest harmonic of the series
    stop = min(max(stop_order, 0), order)
    half = order + 2  # H phases on half a period: S = 2H = 2N + 4 (module docstring)
    with_z = z_re_out.shape[2] == lanes and z_im_out.shape[2] == lanes
    nonlinear = spring >= 2 or damping >= 1  # else u_n = 0 and no b_n (n >= 1)
    # The powers (u^j)_m that a right side takes: j <= spring (- k_j (u^j)_m) and
    # j <= damping + 1 (the derivative of (u^(j+1))_m / (j+1) for d_j); j + m = n + 1.
    jtop = max(1, min(max(spring, damping + 1), stop + 1))

    # Tables, once per call: cos(k theta_s), sin(k theta_s) on half a period.
    cos_t = np.empty((top + 1, half))
    sin_t = np.empty((top + 1, half))
    for k in range(top + 1):
        for s in range(half):
            phase = k * np.pi * s / half
            cos_t[k, s] = np.cos(phase)
            sin_t[k, s] = np.sin(phase)

    # Work arrays, once per call; each lane overwrites what it reads.
    powers = np.empty((jtop + 1, stop + 1, half))  # (u^j)_m at the phases; j = 1: u_m
    rhs = np.empty(half)  # - sum_j k_j (u^j)_(n+1-j)
    vel = np.empty(half)  # - sum_j d_(j-1) / j (u^j)_(n+1-j): its derivative is the damping
    z_re = np.zeros((order + 1, top + 1))
    z_im = np.zeros((order + 1, top + 1))
    f_re = np.zeros(top + 1)
    f_im = np.zeros(top + 1)
    inv_re = np.zeros(top + 1)  # 1 / (omega^2 - k^2 Omega^2 + 2 i k c Omega)
    inv_im = np.zeros(top + 1)
    b = np.zeros(order + 1)
    damping_weight = np.zeros(jtop + 1)  # d_(j-1) / j, for the derivative of (u^j)_m
    for j in range(2, min(damping + 1, jtop) + 1):
        damping_weight[j] = d_coef[j - 1] / j

    for lane in range(lanes):
        amplitude = a0[lane]
        w2 = omega[lane] * omega[lane]
        drive = Omega[lane]
        for k in range(1, top + 1):
            den_re = w2 - (k * drive) ** 2
            den_im = 2.0 * k * c[lane] * drive
            size = den_re * den_re + den_im * den_im
            inv_re[k] = den_re / size
            inv_im[k] = -den_im / size
        # Order 0 (Eq. 2.8 in the frame of u0): u0 = A0 cos(theta).
        z_re[0, 1] = amplitude
        z_im[0, 1] = 0.0
        for s in range(half):
            powers[1, 0, s] = amplitude * cos_t[1, s]
        b_out[0, lane] = 0.0
        if with_z:
            for k in range(top + 1):
                z_re_out[0, k, lane] = amplitude if k == 1 else 0.0
                z_im_out[0, k, lane] = 0.0

        for n in range(1, stop + 1):
            last = n == stop
            only_b = last and not with_z
            # (u^j)_(n+1-j) = sum_i (u^(j-1))_(n+1-j-i) u_i, each power built once; the
            # ones of lower j + m were built at the orders below.
            for j in range(2, min(jtop, n + 1) + 1):
                m = n + 1 - j
                for s in range(half):
                    powers[j, m, s] = powers[j - 1, m, s] * powers[1, 0, s]
                for i in range(1, m + 1):
                    for s in range(half):
                        powers[j, m, s] += powers[j - 1, m - i, s] * powers[1, i, s]
            for s in range(half):
                rhs[s] = 0.0
                vel[s] = 0.0
            for j in range(2, min(spring, n + 1) + 1):  # - k_j (u^j)_(n-j+1)
                coefficient = k_coef[j]
                for s in range(half):
                    rhs[s] -= coefficient * powers[j, n + 1 - j, s]
            for j in range(2, min(damping + 1, n + 1) + 1):  # - d_(j-1) (u^(j-1) u')_(n-j+1)
                coefficient = damping_weight[j]
                for s in range(half):
                    vel[s] -= coefficient * powers[j, n + 1 - j, s]

            # The harmonics F_n_k of the right side, k = n+1, n-1, ... (the others vanish).
            for k in range(n + 1, -1, -2):
                if only_b and k != 1:
                    continue
                r_re = r_im = v_re = v_im = 0.0
                # The sums run over the phases inside: measured faster than over the
                # harmonics inside (the harmonics are few, and every other one is 0).
                if damping >= 1:
                    for s in range(half):
                        r_re += rhs[s] * cos_t[k, s]
                        r_im -= rhs[s] * sin_t[k, s]
                        v_re += vel[s] * cos_t[k, s]
                        v_im -= vel[s] * sin_t[k, s]
                elif spring >= 2:
                    for s in range(half):
                        r_re += rhs[s] * cos_t[k, s]
                        r_im -= rhs[s] * sin_t[k, s]
                weight = (2.0 if k > 0 else 1.0) / half
                speed = k * drive  # d/dt is i k Omega on harmonic k
                value_re = weight * (r_re - speed * v_im)
                value_im = weight * (r_im + speed * v_re)
                if nonlinear:
                    for p in range(2, n, 2):  # sum_p b_p u_(n-p)
                        value_re += b[p] * z_re[n - p, k]
                        value_im += b[p] * z_im[n - p, k]
                f_re[k] = value_re
                f_im[k] = value_im
            if nonlinear and n % 2 == 0:
                # Eq. 2.10, A.2: b_n A0 cancels the fundamental's part in phase with u0.
                b[n] = -f_re[1] / amplitude
                f_re[1] = 0.0
                b_out[n, lane] = b[n]
            else:
                b_out[n, lane] = 0.0
            if only_b:
                break

            # Eq. 2.9, A.1: each harmonic through its transfer (``compiled.complex_chain``),
            # and the mean: omega^2 A_n_0 = F_n_0.
            for k in range(n + 1, -1, -2):
                if k == 0:
                    z_re[n, 0] = f_re[0] / w2
                    z_im[n, 0] = 0.0
                else:
                    z_re[n, k] = f_re[k] * inv_re[k] - f_im[k] * inv_im[k]
                    z_im[n, k] = f_re[k] * inv_im[k] + f_im[k] * inv_re[k]
            if with_z:
                for k in range(top + 1):
                    held = k <= n + 1 and (n + 1 - k) % 2 == 0
                    z_re_out[n, k, lane] = z_re[n, k] if held else 0.0
                    z_im_out[n, k, lane] = z_im[n, k] if held else 0.0
            if not last:  # u_n at the phases, for the orders above
                for s in range(half):
                    powers[1, n, s] = 0.0
                for k in range(n + 1, -1, -2):
                    for s in range(half):
                        powers[1, n, s] += z_re[n, k] * cos_t[k, s] - z_im[n, k] * sin_t[k, s]


class KernelSeries(NumericSeries):
    """``NumericSeries`` computed by the numba kernel ``scheme_lanes``: the same arguments
    ``(A0, omega, Omega, c, *coefficients)``, attributes and values (to round-off).

    The kernel takes one value of each coefficient for all lanes (as every caller passes:
    the contact's k_j, d_j); coefficients that vary over the lanes are evaluated by
    ``NumericSeries``. Its attributes are ``NumericSeries``', and ``lanes_per_call``.
    """

    #: Lanes per kernel call, in buffers that are reused (6 MB of them at N = 8): memory
    #: stays bounded, the values do not change.
    lanes_per_call: int = 4096

    def evaluate(self, A0: npt.ArrayLike, omega: npt.ArrayLike, Omega: npt.ArrayLike,
                 c: npt.ArrayLike, *coefficients: npt.ArrayLike,
                 until: str | None = None) -> dict[str, np.ndarray]:
        """Run the scheme; every value by the names of ``CompiledSeries.evaluate``.

        Returns
        -------
        dict of str to ndarray
            "A0" (flat), "b_n", "A_n_0" (real), "z_n_k" (complex) of the orders up to
            the one that assigns ``until`` (all, when None), "z_0_1" and "A_0_1".
        """
        lanes = self._lanes(A0, omega, Omega, c, *coefficients)
        if lanes is None:
            return super().evaluate(A0, omega, Omega, c, *coefficients, until=until)
        shape, a0, w, W, damping_c, k_coef, d_coef = lanes
        stop = self._stop_order(until)
        size, rows, columns = a0.size, self.order + 1, self.order + 2
        b_out = np.empty((rows, size))
        held = [(n, k) for n in range(1, stop + 1) for k in range(n + 1, -1, -2)]
        values = {(n, k): np.empty(size, dtype=complex if k else float) for n, k in held}
        # A chunk of lanes at a time, in buffers that are reused: (N+1, N+2, L) buffers for
        # all lanes at once would hold 0.7 GB at 500,000 lanes and order 8, most of it 0.
        chunk = max(1, min(size, self.lanes_per_call))
        b_part, z_re, z_im = np.empty((rows, chunk)), *np.empty((2, rows, columns, chunk))
        for start in range(0, size, chunk):
            part = slice(start, min(start + chunk, size))
            if part.stop - part.start < chunk:  # the kernel writes as many lanes as it gets
                chunk = part.stop - part.start
                b_part, z_re, z_im = np.empty((rows, chunk)), *np.empty((2, rows, columns,
                                                                          chunk))
            scheme_lanes(a0[part], w[part], W[part], damping_c[part], k_coef, d_coef,
                         self.order, self.spring, self.damping, stop, b_part, z_re, z_im)
            b_out[:, part] = b_part
            for (n, k), value in values.items():
                if k == 0:
                    value[part] = z_re[n, 0]
                else:
                    value.real[part] = z_re[n, k]
                    value.imag[part] = z_im[n, k]
        env: dict[str, np.ndarray] = {"A0": a0}  # flat, as NumericSeries leaves it
        for n in range(1, stop + 1):
            if n in self.b_orders:
                env[f"b_{n}"] = b_out[n].reshape(shape)
            for k in range(n + 1, -1, -2):
                name = f"A_{n}_0" if k == 0 else f"z_{n}_{k}"
                env[name] = values[(n, k)].reshape(shape)
        env["z_0_1"] = env["A_0_1"] = a0.reshape(shape)
        return env

    def b(self, *args: npt.ArrayLike) -> list[np.ndarray]:
        """The non-zero b_n (real), one per entry of ``b_orders``: the kernel stops at the
        last b and writes no harmonic (the frequency equation needs nothing else)."""
        if not self.b_orders:
            return []
        lanes = self._lanes(*args)
        if lanes is None:
            return super().b(*args)
        shape, a0, w, W, damping_c, k_coef, d_coef = lanes
        b_out = np.empty((self.order + 1, a0.size))
        no_lanes = np.empty((self.order + 1, self.order + 2, 0))
        scheme_lanes(a0, w, W, damping_c, k_coef, d_coef, self.order, self.spring,
                     self.damping, self.b_orders[-1], b_out, no_lanes, no_lanes)
        return [b_out[n].reshape(shape) for n in self.b_orders]

    def _lanes(self, A0, omega, Omega, c, *coefficients):
        """(shape, A0, omega, Omega, c flat and contiguous, k_coef, d_coef) as the kernel
        takes them; None if a coefficient varies over the lanes."""
        self._check_count(coefficients)
        values = [np.asarray(x, dtype=float) for x in coefficients]
        constants = [_constant(x) for x in values]
        if any(x is None for x in constants):
            return None
        arrays = [np.asarray(a, dtype=float) for a in (A0, omega, Omega, c)]
        shape = np.broadcast_shapes(*(a.shape for a in arrays), *(x.shape for x in values))
        # C-contiguous and writeable, always: numba compiles again for a read-only array.
        flat = [np.require((a if a.shape == shape else np.broadcast_to(a, shape)).reshape(-1),
                           np.float64, ("C", "W")) for a in arrays]
        k_coef = np.zeros(max(self.spring, 2) + 1)  # h is an argument even at order 0
        d_coef = np.zeros(self.damping + 1)
        for (kind, j), value in zip(self.coefficients, constants):
            (k_coef if kind == "k" else d_coef)[j] = value
        return (shape, *flat, k_coef, d_coef)

    def _stop_order(self, until: str | None) -> int:
        """The order after which ``NumericSeries.evaluate`` stops for ``until``: the first
        that assigns it (order 1 for "A0", which is assigned before any); else the last."""
        if until is None:
            return self.order
        for n in range(1, self.order + 1):
            names = {f"b_{n}"} if n in self.b_orders else set()
            names |= {f"A_{n}_0" if k == 0 else f"z_{n}_{k}" for k in range(n + 1, -1, -2)}
            if until in names or until == "A0":
                return n
        return self.order

    def __repr__(self) -> str:
        return (f"KernelSeries(order={self.order}, truncation={self.truncation.name!r}, "
                f"coefficients={self.arguments[4:]})")


def _constant(value: np.ndarray) -> float | None:
    """The one value of ``value`` (0 if it is empty), or None if its entries differ."""
    if value.size == 0:
        return 0.0
    first = value.flat[0]
    if value.size == 1 or np.all(value == first):
        return float(first)
    return None


@lru_cache(maxsize=None)
def kernel_series(order: int, truncation: Truncation) -> KernelSeries:
    """The order-N series of ``truncation`` computed by the numba kernel (cached per order
    and truncation; the kernel itself is compiled once for all).

    Examples
    --------
    >>> from perturb.series.truncation import truncation_for
    >>> series = kernel_series(2, truncation_for("paper"))
    >>> series.b_orders, series.arguments
    ((2,), ('A0', 'omega', 'Omega', 'c', 'h'))
    """
    return KernelSeries(order, truncation)
