"""The numba kernel of the numeric series (``perturb.series.kernel``) against the same
scheme in numpy (``NumericSeries``): every b_n and z_n_k, on the truncations of the
paper's contact and of two others, at orders 0 to 10.

The two routes round differently (the kernel samples half a period and takes the damping
as the derivative of the powers of u), so they agree to round-off, measured on the scale
at which each route makes it:

- z_n_k against the largest |z_n_h| of its order n (any h, any lane): every harmonic of
  u_n comes out of one Fourier sum of the samples of the right side of order n, so its
  error is some 1e-16 of the whole of u_n, not of the harmonic itself (which can be
  orders of magnitude smaller: measured on its own scale, the two routes differ by up
  to 5e-8 on 8 lanes at order 10, and against 60-digit arithmetic both err at that
  level, the kernel a few times less);
- b_n against its largest |b_n| over the lanes.

The lanes are physically sized (A0 = 10-60 nm, omega 8-10 krad/s, Omega 3-9 krad/s,
c = 150 /s) and kept off the internal resonances omega = k Omega, k = 2..N+1, where
the transfer omega^2 / (omega^2 - k^2 Omega^2) exceeds 10: there the series itself is
ill-conditioned, and both routes lose digits in step (measured against the scheme in
60-digit arithmetic: at omega / Omega = 2.0003, order 10, z_10_11 of the numpy route is
off by 5e-9 and the kernel's by 1.3e-9). Off them the two agree to some 5e-14 at order 10
(the largest over 1,250 draws of 32 lanes).
"""

import numpy as np
import pytest

from perturb.model.parameters import PAPER, ContactParameters
from perturb.series.kernel import KernelSeries, kernel_series
from perturb.series.numeric import NumericSeries
from perturb.series.truncation import Truncation, series_values, truncation_for

#: (truncation, contact): a generic contact (every k_j, d_j), Eq. 2.6, the paper's
#: contact to consistent order (k_2 and d_1) and a cubic spring with quadratic damping.
CASES = {
    "consistent-m2=1.5-l=0.5": ("consistent", ContactParameters(m2=1.5, l=0.5)),
    "paper": ("paper", PAPER),
    "consistent-paper-contact": ("consistent", PAPER),
    "consistent-m2=3-l=2": ("consistent", ContactParameters(m2=3.0, l=2.0)),
}
ORDERS = [0, 1, 2, 5, 8, 10]
TOLERANCE = 1e-12
LANES = 32
MAX_TRANSFER = 10.0  # the lanes' largest omega^2 / |omega^2 - k^2 Omega^2|, k >= 2


def _both(case: str, order: int):
    """NumericSeries and KernelSeries of ``case`` at ``order``, built as
    ``perturb.series.compiled.compile_series`` builds them, and the contact's coefficients."""
    name, parameters = CASES[case]
    truncation = truncation_for(name, parameters)
    at_order = Truncation(truncation.name, *truncation.at_order(order))
    numeric, kernel = NumericSeries(order, at_order), KernelSeries(order, at_order)
    return numeric, kernel, series_values(parameters).coefficients(numeric.coefficients)


def _lanes(order: int, count: int = LANES, seed: int = 20261124):
    """(A0, omega, Omega, c) of ``count`` physically sized lanes, off the internal
    resonances (module docstring)."""
    rng = np.random.default_rng(seed)
    a0, omega = rng.uniform(1e-8, 6e-8, 20 * count), rng.uniform(8e3, 1e4, 20 * count)
    Omega = rng.uniform(3e3, 9e3, 20 * count)
    k = np.arange(2, order + 2)[:, None]
    transfer = np.max(omega**2 / np.abs(omega**2 - (k * Omega) ** 2), axis=0, initial=0.0)
    kept = np.flatnonzero(transfer <= MAX_TRANSFER)[:count]
    assert kept.size == count
    return a0[kept], omega[kept], Omega[kept], np.full(count, 150.0)


def _assert_same_series(numeric_env: dict, kernel_env: dict, last_order: int) -> None:
    """Every b_n and z_n_k of orders 1..last_order agree (the scales of the docstring)."""
    for n in range(1, last_order + 1):
        names = [name for name in numeric_env
                 if name.startswith((f"z_{n}_", f"A_{n}_"))]
        assert names, f"order {n} has no harmonic"
        scale = max(np.max(np.abs(numeric_env[name])) for name in names)
        for name in names:
            error = np.max(np.abs(kernel_env[name] - numeric_env[name]))
            assert error <= TOLERANCE * scale, f"{name}: {error / scale:.2e} of order {n}"
        if f"b_{n}" in numeric_env:
            b_numeric, b_kernel = numeric_env[f"b_{n}"], kernel_env[f"b_{n}"]
            error = np.max(np.abs(b_kernel - b_numeric))
            assert error <= TOLERANCE * np.max(np.abs(b_numeric)), f"b_{n}"


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("case", list(CASES))
def test_kernel_equals_the_numeric_scheme(case, order):
    numeric, kernel, coefficients = _both(case, order)
    assert (kernel.coefficients, kernel.b_orders, kernel.keys, kernel.arguments) == (
        numeric.coefficients, numeric.b_orders, numeric.keys, numeric.arguments)
    args = (*_lanes(order), *coefficients)
    numeric_env, kernel_env = numeric.evaluate(*args), kernel.evaluate(*args)
    assert list(kernel_env) == list(numeric_env)  # the same names, in the same order
    for name, value in numeric_env.items():
        assert kernel_env[name].shape == value.shape, name
        assert np.iscomplexobj(kernel_env[name]) == np.iscomplexobj(value), name
    np.testing.assert_array_equal(kernel_env["z_0_1"], numeric_env["z_0_1"])
    _assert_same_series(numeric_env, kernel_env, order)
    # b() stops at the last b_n and writes no harmonic: the same b_n.
    b_numeric, b_kernel = numeric.b(*args), kernel.b(*args)
    assert len(b_kernel) == len(b_numeric) == len(numeric.b_orders)
    for n, x, y in zip(numeric.b_orders, b_numeric, b_kernel):
        assert np.max(np.abs(y - x)) <= TOLERANCE * np.max(np.abs(x)), f"b_{n} of b()"
        np.testing.assert_array_equal(y, kernel_env[f"b_{n}"])
    for x, y in zip(numeric.amplitudes(*args), kernel.amplitudes(*args)):
        assert y.dtype == x.dtype


@pytest.mark.parametrize("until", ["b_4", "z_3_2", "A_5_0", "A0"])
def test_until_stops_early_with_the_same_values(until):
    """``until`` stops after the order that assigns it, as NumericSeries does, and every
    value it gives is that of the whole run, to the last bit (the kernel's samples
    follow the series' order, not the order it stops at)."""
    numeric, kernel, coefficients = _both("consistent-m2=1.5-l=0.5", 8)
    args = (*_lanes(8), *coefficients)
    numeric_env = numeric.evaluate(*args, until=until)
    kernel_env = kernel.evaluate(*args, until=until)
    assert list(kernel_env) == list(numeric_env)
    last = {"b_4": 4, "z_3_2": 3, "A_5_0": 5, "A0": 1}[until]
    assert f"z_{last + 1}_{last + 2}" not in kernel_env
    _assert_same_series(numeric_env, kernel_env, last)
    whole = kernel.evaluate(*args)
    for name, value in kernel_env.items():
        np.testing.assert_array_equal(value, whole[name], err_msg=name)
    assert [f"b_{n}" in kernel_env for n in kernel.b_orders] == [
        n <= last for n in kernel.b_orders]


def test_b_of_an_odd_order_stops_below_it():
    """Order 7 has b_2..b_6: ``b`` stops the kernel at order 6 and writes no harmonic,
    and gives the b_n of the whole run, to the last bit."""
    numeric, kernel, coefficients = _both("consistent-m2=1.5-l=0.5", 7)
    args = (*_lanes(7), *coefficients)
    assert kernel.b_orders == (2, 4, 6)
    whole = kernel.evaluate(*args)
    for n, x, y in zip(kernel.b_orders, numeric.b(*args), kernel.b(*args)):
        assert np.max(np.abs(y - x)) <= TOLERANCE * np.max(np.abs(x))
        np.testing.assert_array_equal(y, whole[f"b_{n}"])
    np.testing.assert_allclose(kernel.frequency_shift(*args), numeric.frequency_shift(*args),
                               rtol=TOLERANCE)


def test_broadcast_shapes_and_scalars():
    """Arguments broadcast as in NumericSeries: a grid of (A0, omega), scalar Omega, c."""
    numeric, kernel, coefficients = _both("consistent-paper-contact", 4)
    args = (np.linspace(1e-8, 6e-8, 3)[:, None], np.linspace(8e3, 1e4, 5)[None, :],
            5000.0, 150.0, *coefficients)
    numeric_env, kernel_env = numeric.evaluate(*args), kernel.evaluate(*args)
    assert kernel_env["b_4"].shape == kernel_env["z_4_5"].shape == (3, 5)
    assert kernel_env["A0"].shape == numeric_env["A0"].shape == (15,)  # flat, as numpy's
    _assert_same_series(numeric_env, kernel_env, 4)
    empty = kernel.b(np.empty(0), np.empty(0), 5000.0, 150.0, *coefficients)
    assert [x.shape for x in empty] == [(0,), (0,)]


def test_chunks_of_lanes_change_nothing():
    """``evaluate`` runs the kernel a chunk of lanes at a time: 32 lanes in chunks of 5
    (the last one short) give the very numbers of one chunk."""
    kernel, coefficients = _both("consistent-m2=1.5-l=0.5", 6)[1:]
    args = (*_lanes(6), *coefficients)
    whole = kernel.evaluate(*args)
    kernel.lanes_per_call = 5
    chunked = kernel.evaluate(*args)
    assert list(chunked) == list(whole)
    for name, value in whole.items():
        np.testing.assert_array_equal(chunked[name], value, err_msg=name)


def test_coefficients_that_vary_over_the_lanes_take_the_numpy_route():
    numeric, kernel, coefficients = _both("consistent-m2=1.5-l=0.5", 4)
    a0, omega, Omega, c = _lanes(4, count=4)
    varied = (coefficients[0] * np.array([1.0, 1.1, 0.9, 1.0]), *coefficients[1:])
    expected = numeric.evaluate(a0, omega, Omega, c, *varied)
    got = kernel.evaluate(a0, omega, Omega, c, *varied)
    assert list(got) == list(expected)
    for name in expected:
        np.testing.assert_array_equal(got[name], expected[name])
    for x, y in zip(numeric.b(a0, omega, Omega, c, *varied), kernel.b(a0, omega, Omega, c,
                                                                       *varied)):
        np.testing.assert_array_equal(y, x)


def test_bad_arguments_and_the_cached_factory():
    numeric, kernel, coefficients = _both("paper", 2)
    with pytest.raises(ValueError, match="expected 1 coefficients"):
        kernel.evaluate(1e-8, 9e3, 5e3, 150.0)
    with pytest.raises(ValueError, match="expected 1 coefficients"):
        kernel.b(1e-8, 9e3, 5e3, 150.0, 1.0, 2.0)
    truncation = Truncation("paper", *truncation_for("paper").at_order(2))
    assert kernel_series(2, truncation) is kernel_series(2, truncation)
    assert isinstance(kernel_series(2, truncation), NumericSeries)
    assert repr(kernel_series(2, truncation)).startswith("KernelSeries(order=2")
