"""The backbone series of the free, undamped Eq. 2.6 against its numerical period."""

from fractions import Fraction
from functools import partial as _partial

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from perturb import backbone_series

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
backbone_series = _partial(backbone_series, truncation="paper")


def test_classical_coefficient():
    # Nayfeh and Mook: omega = omega0 (1 - 5/12 alpha^2 + ...) for u'' + omega0^2 u + h u^2 = 0.
    series = backbone_series(16)
    assert series.coefficients[2] == Fraction(-5, 12)
    assert all(q == 0 for q in series.coefficients[1::2])
    assert len(series.coefficients) == 17


def sol_free_oscillator(x_max):
    """x'' + x + x^2 = 0 from rest at x_max: (omega/omega0, first-harmonic amplitude)."""

    def turning(t, s):
        return s[1]

    turning.terminal, turning.direction = True, 1
    sol = solve_ivp(
        lambda t, s: [s[1], -s[0] - s[0] ** 2],
        (0.0, 50.0),
        [x_max, 0.0],
        rtol=1e-12,
        atol=1e-14,
        events=turning,
        dense_output=True,
    )
    half = sol.t_events[0][0]  # the minimum: half a period (the orbit is symmetric)
    tau = np.linspace(0.0, half, 4001)
    x = sol.sol(tau)[0]
    period = 2 * half
    # a = (4/T) int_0^{T/2} x cos(2 pi t / T) dt, by Simpson's rule
    weights = np.ones(tau.size)
    weights[1:-1:2], weights[2:-1:2] = 4, 2
    integral = (tau[1] - tau[0]) / 3 * np.sum(weights * x * np.cos(2 * np.pi * tau / period))
    return 2 * np.pi / period, 4 / period * integral


@pytest.mark.parametrize("x_max", [0.1, 0.2, 0.3])
def test_error_falls_with_order(x_max):
    ratio, alpha = sol_free_oscillator(x_max)
    errors = [abs(backbone_series(n).frequency_ratio(alpha) - ratio) for n in (2, 4, 6, 8, 10)]
    assert all(b < a for a, b in zip(errors, errors[1:])), errors
    # the truncation error of order N is about the first dropped term, c_(N+2) alpha^(N+2)
    assert errors[-1] < 5 * abs(float(backbone_series(12).coefficients[12])) * alpha**12 + 1e-11


def test_order_16_matches_to_round_off_at_small_amplitude():
    ratio, alpha = sol_free_oscillator(0.1)
    assert abs(backbone_series(16).frequency_ratio(alpha) - ratio) < 1e-11


@pytest.mark.parametrize("bad", [-1, 1.5, "8"])
def test_rejects_bad_order(bad):
    with pytest.raises(ValueError, match="`order`"):
        backbone_series(bad)
