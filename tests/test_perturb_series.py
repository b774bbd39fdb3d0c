"""The derived series of Eq. 2.6: structure, the b_n rule, and the residual.

The residual checks substitute the truncated series back into Eq. 2.6 itself
(differentiated in t by sympy or evaluated on a time grid), not into the
harmonic algebra that produced it.
"""

from functools import partial as _partial

import numpy as np
import pytest
import sympy as sp

from perturb import compile_series, derive
from perturb import series_symbols as sym
from perturb.series.compiled import A0, complex_chain
from perturb.series.lindstedt import gain_closed_form, lag_closed_form

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
derive = _partial(derive, truncation="paper")
compile_series = _partial(compile_series, truncation="paper")


def test_paper_structure_of_order_4():
    # Eq. 2.9-A.2: u1 mean + 2nd, u2 1st + 3rd, u3 mean, 2nd, 4th, u4 1st, 3rd, 5th.
    series = derive(4)
    assert [series.harmonics(n) for n in range(5)] == [(1,), (0, 2), (1, 3), (0, 2, 4), (1, 3, 5)]
    assert [series.has_b(n) for n in range(1, 5)] == [False, True, False, True]


@pytest.mark.parametrize("order", [5, 9])
def test_odd_b_vanish_identically(order):
    series = derive(order)
    for n in range(1, order + 1, 2):
        assert series.b_closed_form(n) == 0
        assert 1 not in series.harmonics(n)


def test_b2_is_the_papers_formula():
    # Eq. 2.10: b2 = 2 h A2 + h A1 cos(phi1), with A2 = A_1_0, A1 = -A_1_2 and
    # phi1 = phi_1_2 - 2 phi_0_1 - pi (perturb.printing.names).
    b2 = derive(2).b_closed_form(2)
    A1, A2 = -sym.amplitude(1, 2), sym.amplitude(1, 0)
    phi1 = sym.phase(1, 2) - 2 * sym.phase(0, 1) - sp.pi
    assert sp.simplify(b2 - (2 * sym.h * A2 + sym.h * A1 * sp.cos(phi1))) == 0


def test_b2_closed_form_by_hand():
    # By hand: b2 = -h^2 A0^2 / omega^2 - (h^2 A0^2 / 2) Re(1/(omega^2 - 4 Omega^2 + 4 i c Omega)).
    series = derive(2)
    a0, phi0 = sym.amplitude(0, 1), sym.phase(0, 1)
    closed = {
        sym.amplitude(1, 0): -sym.h * a0**2 / (2 * sym.omega**2),
        sym.amplitude(1, 2): sym.h * a0**2 * gain_closed_form(2) / 2,
        sym.phase(1, 2): 2 * phi0 + sp.pi + lag_closed_form(2),
    }
    b2 = series.b_closed_form(2).xreplace(closed)
    detuning = sym.omega**2 - 4 * sym.Omega**2
    by_hand = -(sym.h**2) * a0**2 / sym.omega**2 - sym.h**2 * a0**2 / 2 * detuning / (
        detuning**2 + 16 * sym.c**2 * sym.Omega**2
    )
    difference = sp.simplify(sp.expand_trig(b2 - by_hand))
    assert difference == 0


def _exact_chain(order, values):
    """The compiled chain evaluated in exact (Gaussian rational) arithmetic."""
    env = {A0: values["A0"], sym.omega: values["omega"], sym.Omega: values["Omega"]}
    env.update({sym.c: values["c"], sym.h: values["h"]})
    env[sym.complex_amplitude(0, 1, True)] = values["A0"]
    env[sym.complex_amplitude(0, 1)] = values["A0"]
    for symbol, expr in complex_chain(derive(order)):
        value = sp.expand_complex(expr.xreplace(env))
        env[symbol] = value
        name = str(symbol)
        if name.startswith("z_"):
            env[sp.Symbol("zc" + name[1:])] = sp.conjugate(value)
    return env


@pytest.mark.parametrize("order", [2, 4])
def test_residual_vanishes_to_order_exactly(order):
    """Substituted into Eq. 2.6, the series leaves exactly O(eps^(N+1)).

    With rational parameters every amplitude and b_n is a Gaussian rational, so
    the residual's coefficients of eps^0..eps^N are trigonometric polynomials
    in t with exact coefficients, which must be identically zero.
    """
    R = sp.Rational
    values = {"A0": R(1), "omega": R(1), "Omega": R(9, 20), "c": R(1, 25), "h": R(3, 10)}
    env = _exact_chain(order, values)
    t, eps = sym.t, sym.eps
    Omega, c, omega = values["Omega"], values["c"], values["omega"]
    u = sp.Integer(0)
    for n in range(order + 1):
        for k in derive(order).harmonics(n):
            if k == 0:
                u += eps**n * env[sym.amplitude(n, 0)]
            else:
                z = env[sym.complex_amplitude(n, k)] if n else values["A0"]
                re, im = sp.re(z), sp.im(z)
                u += eps**n * (re * sp.cos(k * Omega * t) - im * sp.sin(k * Omega * t))
    shift = sum(eps**n * env[sym.b(n)] for n in range(1, order + 1) if derive(order).has_b(n))
    # The drive: u0 = A0 cos(Omega t) answers G cos(Omega t + arg) = Re(A0 D_1 e^{i Omega t}).
    d1 = values["A0"] * (omega**2 - Omega**2 + 2 * sp.I * c * Omega)
    drive = sp.re(d1) * sp.cos(Omega * t) - sp.im(d1) * sp.sin(Omega * t)
    omega0_sq = omega**2 - shift
    residual = (
        sp.diff(u, t, 2) + 2 * c * sp.diff(u, t) + omega0_sq * u + eps * values["h"] * u**2 - drive
    )
    polynomial = sp.Poly(sp.expand(residual), eps)
    for power in range(order + 1):
        coefficient = polynomial.coeff_monomial(eps**power)
        assert sp.expand(sp.sympify(coefficient).rewrite(sp.exp)) == 0, power
    top = polynomial.coeff_monomial(eps ** (order + 1))
    assert sp.expand(sp.sympify(top).rewrite(sp.exp)) != 0


def _numeric_residual(order, scale):
    """max |Eq. 2.6 residual| over a period, with h -> scale * h (eps = scale)."""
    A0_, omega, Omega, c, h = 1.0, 1.0, 0.45, 0.04, 0.3 * scale
    formulas = compile_series(order)
    amplitudes = formulas.amplitudes(A0_, omega, Omega, c, h)
    shift = float(formulas.frequency_shift(A0_, omega, Omega, c, h))
    theta = np.linspace(0, 2 * np.pi, 512, endpoint=False)
    u = np.zeros_like(theta)
    du = np.zeros_like(theta)
    ddu = np.zeros_like(theta)
    for (_, k), z in zip(formulas.keys, amplitudes):
        wave = complex(z) * np.exp(1j * k * theta)
        u += wave.real
        du += (1j * k * Omega * wave).real
        ddu += (-((k * Omega) ** 2) * wave).real
    drive = (A0_ * (omega**2 - Omega**2 + 2j * c * Omega) * np.exp(1j * theta)).real
    residual = ddu + 2 * c * du + (omega**2 - shift) * u + h * u**2 - drive
    return np.max(np.abs(residual))


@pytest.mark.parametrize("order", [1, 2, 3, 4, 6])
def test_residual_slope_in_eps(order):
    scales = np.array([0.08, 0.04, 0.02, 0.01])
    residuals = np.array([_numeric_residual(order, s) for s in scales])
    slope = np.polyfit(np.log(scales), np.log(residuals), 1)[0]
    assert abs(slope - (order + 1)) < 0.1, f"measured slope {slope:.3f}, expected {order + 1}"


def test_derive_is_cached():
    assert derive(4) is derive(4)


@pytest.mark.parametrize("bad", [-1, 2.5, "3", None, True])
def test_derive_rejects_bad_order(bad):
    with pytest.raises(ValueError, match="`order`"):
        derive(bad)


def test_series_summary_and_missing_harmonic():
    series = derive(2)
    assert "Series(order=2" in repr(series)
    with pytest.raises(ValueError, match="`n` must be an integer <= 2, got 3"):
        series.harmonics(3)
    with pytest.raises(ValueError, match="`n`"):
        series.has_b("1")
    with pytest.raises(KeyError, match=r"no harmonic k=1 at order n=1; available: \[0, 2\]"):
        series.forcing_closed_form(1, 1)
    with pytest.raises(KeyError, match=r"available: \[1\]"):
        series.solution_closed_form(0, 3)


def test_series_is_derived_for_the_models_eq26():
    # The engine's Eq. 2.6, with c, h, G, omega0 of Eq26 (derived from Eq. 2.1-2.5).
    from perturb import Eq26
    from perturb import symbols as model
    from perturb.series.lindstedt import eq26_substitution, equation_2_6

    eq = Eq26()
    u = sp.Function("u")
    ours = equation_2_6(u(sym.t)).xreplace(eq26_substitution(eq))
    assert sp.simplify(ours - eq.equation(u(model.t))) == 0


def test_residual_vanishes_symbolically_at_order_1():
    """All parameters symbolic: the eps^0 and eps^1 parts of the residual vanish."""
    series = derive(1)
    env = {sym.complex_amplitude(0, 1): A0, sym.complex_amplitude(0, 1, True): A0}
    for symbol, expr in complex_chain(series):
        env[symbol] = expr.xreplace(env)
    t, eps, Omega, c, omega = sym.t, sym.eps, sym.Omega, sym.c, sym.omega
    z12 = env[sym.complex_amplitude(1, 2)]
    u = A0 * sp.cos(Omega * t) + eps * (
        env[sym.amplitude(1, 0)]
        + sp.re(z12) * sp.cos(2 * Omega * t)
        - sp.im(z12) * sp.sin(2 * Omega * t)
    )
    d1 = A0 * (omega**2 - Omega**2 + 2 * sp.I * c * Omega)
    drive = sp.re(d1) * sp.cos(Omega * t) - sp.im(d1) * sp.sin(Omega * t)
    residual = sp.diff(u, t, 2) + 2 * c * sp.diff(u, t) + omega**2 * u + eps * sym.h * u**2 - drive
    residual = sp.expand(residual)
    for power in (0, 1):
        assert sp.simplify(residual.coeff(eps, power)) == 0, power
    assert sp.simplify(residual.coeff(eps, 2)) != 0
