"""The symbolic model of Eq. 2.1-2.6 and the checks on its inputs."""

import math

import pytest
import sympy as sp

from perturb import (
    EQ_2_6,
    PAPER,
    PAPER_F_N0_HZ,
    ContactModel,
    ContactParameters,
    Effects,
    Eq26,
    symbols,
)


def test_natural_frequency_is_the_papers(paper_figures):
    assert abs(paper_figures["f_n0_hz"] / PAPER_F_N0_HZ - 1) < 1e-3, paper_figures["f_n0_hz"]


def test_static_deflection_balances_the_weight(paper_figures):
    expected = (PAPER.M * PAPER.g / (PAPER.S * PAPER.c_n)) ** (1 / PAPER.m2)
    assert paper_figures["y0_m"] == pytest.approx(expected, rel=1e-14)


def test_y0_is_an_equilibrium_for_any_exponent():
    assert Eq26().static_residual == 0


def test_eq26_coefficients_match_the_papers_formulas():
    # Eq. 2.6, typed here only to check the derivation.
    S, c_n, m2, h_n, l, M, g = (symbols.PARAMETER_SYMBOLS[k] for k in "S c_n m2 h_n l M g".split())
    eq = Eq26()
    y0 = eq.y0
    assert sp.simplify(eq.two_c - S * h_n * y0**l / M) == 0
    assert sp.simplify(eq.omega0_squared - S * c_n * m2 * y0 ** (m2 - 1) / M) == 0
    assert sp.simplify(eq.h - S * c_n * m2 * (m2 - 1) * y0 ** (m2 - 2) / (2 * M)) == 0
    assert sp.simplify(eq.G - symbols.P_a / M) == 0


def test_quadratic_spring_taylor_series_ends_at_the_quadratic_term():
    # For m2 = 2 the spring law is a parabola: every Taylor term past u^2 vanishes.
    model = ContactModel(effects=Effects(spring="taylor", taylor_degree=6))
    spring = sp.expand(model.spring_law(symbols.y).subs(model.values))
    full = sp.expand(model.power_spring(symbols.y).subs(model.values))
    assert sp.Poly(spring, symbols.y).degree() == 2
    assert all(abs(c) < 1e-3 for c in sp.Poly(spring - full, symbols.y).coeffs())


def test_cubic_taylor_term_exists_for_a_fractional_exponent():
    eq = Eq26(ContactModel(ContactParameters(m2=1.5)))
    assert eq.model.evaluate(eq.stiffness_coefficients(3)[3]) != 0


def test_eq26_model_is_the_taylor_polynomial_without_contact_loss():
    accel = ContactModel(effects=EQ_2_6).acceleration()
    assert not accel.has(sp.Piecewise)
    u = sp.Symbol("u")
    eq = Eq26()
    expected = (
        -eq.omega0_squared * u - eq.h * u**2 - eq.two_c * symbols.v
        + eq.G * sp.cos(2 * sp.pi * symbols.f_e * symbols.t)
    )
    assert sp.simplify(accel.subs(symbols.y, eq.y0 + u) - expected) == 0


@pytest.mark.parametrize("name", ["S", "c_n", "h_n", "M", "g"])
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_bad_physical_parameters_are_named(name, bad):
    with pytest.raises(ValueError, match=f"`{name}`.*{bad}"):
        ContactParameters(**{name: bad})


@pytest.mark.parametrize("bad", [True, "1", None])
def test_parameters_must_be_real_numbers(bad):
    with pytest.raises(ValueError, match=f"`M` must be one real number, got {bad!r}"):
        ContactParameters(M=bad)


@pytest.mark.parametrize("name, bad", [("m2", 0.9), ("l", -0.5), ("m2", math.nan)])
def test_bad_exponents_are_named(name, bad):
    with pytest.raises(ValueError, match=f"`{name}`.*{bad}"):
        ContactParameters(**{name: bad})


def test_continued_law_needs_a_polynomial():
    with pytest.raises(ValueError, match="contact_loss=False"):
        ContactModel(ContactParameters(m2=1.5), Effects(contact_loss=False))
    ContactModel(ContactParameters(m2=1.5), EQ_2_6)  # the Taylor law is a polynomial


@pytest.mark.parametrize(
    "changes, name",
    [({"spring": "cubic"}, "spring"), ({"damping": "x"}, "damping"),
     ({"taylor_degree": 0}, "taylor_degree"), ({"gravity": 1}, "gravity")],
)
def test_bad_effects_are_named(changes, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        Effects(**changes)
