"""The series of any contact: the equation in contact to consistent order.

Three routes to each number: the closed forms (``derive``, lambdified), the same scheme
carried out on samples (``NumericSeries``), and the full model (the quadrature backbone,
RK4 steady states of ``numerics``). Contacts off the paper's keep y0 (c_n rescaled) and
c (h_n rescaled), so that only the shape of the laws changes.
"""

import numpy as np
import pytest
import sympy as sp

from numerics import exact_backbone, steady_states
from perturb import (
    PAPER,
    ContactModel,
    ContactParameters,
    backbone_series,
    derive,
    eq26_numbers,
    frequency_response,
    series_orbits,
)
from perturb.model.symbols import m2 as m2_symbol
from perturb.response import frequency as frequency_module
from perturb.response.codegen import series_kernels
from perturb.series.compiled import compile_series, lambdify_chain
from perturb.series.free_backbone import power_law_backbone_coefficients
from perturb.series.numeric import NumericSeries
from perturb.series.truncation import coefficient_closed_form, series_values, truncation_for

Y0 = eq26_numbers(PAPER).y0_m


def contact(m2: float, l: float = 1.0) -> ContactParameters:
    """A power-law contact with the paper's y0 (c_n rescaled) and c (h_n rescaled)."""
    return ContactParameters(m2=m2, l=l, c_n=PAPER.M * PAPER.g / (PAPER.S * Y0**m2),
                             h_n=PAPER.h_n * Y0 ** (1 - l))


# -- the equation and its coefficients ------------------------------------------------

@pytest.mark.parametrize("kind, j", [("k", 2), ("k", 3), ("k", 4), ("d", 1), ("d", 2)])
@pytest.mark.parametrize("parameters", [PAPER, contact(1.5, 0.5), contact(2.5, 1.5)])
def test_coefficient_values_are_the_models_taylor_coefficients(kind, j, parameters):
    """The closed form without sympy against sympy's derivative of the model's own law."""
    model = ContactModel(parameters)
    exact = coefficient_closed_form(kind, j).subs(sp.Symbol("y0", positive=True),
                                                 model.static_deflection)
    value = series_values(parameters).coefficients(((kind, j),))[0]
    expected = model.evaluate(exact)
    assert value == pytest.approx(expected, rel=1e-12, abs=1e-300)


def test_polynomial_laws_end_their_sums():
    assert derive(4).coefficients == (("k", 2), ("d", 1))  # the paper's contact
    assert derive(4, "paper").coefficients == (("k", 2),)
    assert derive(4, parameters=contact(3.0, 0.0)).coefficients == (("k", 2), ("k", 3))
    generic = derive(3, parameters=contact(1.5, 0.5)).coefficients
    assert generic == (("k", 2), ("k", 3), ("k", 4), ("d", 1), ("d", 2), ("d", 3))


def _residual_in_contact(order: int, scale: float) -> float:
    """max |residual| over a period of the consistent order-N series of contact(1.5, 0.5)
    in its own equation, every k_j scaled by scale^(j-1) and d_j by scale^j (eps = scale)."""
    parameters = contact(1.5, 0.5)
    formulas = compile_series(order, "consistent", parameters)
    values = series_values(parameters)
    names = formulas.coefficients
    coefficients = [x * scale ** (j - 1 if kind == "k" else j)
                    for (kind, j), x in zip(names, values.coefficients(names))]
    a0, omega, Omega, c = 2e-7, 9000.0, 8000.0, values.c_per_s
    amplitudes = formulas.amplitudes(a0, omega, Omega, c, *coefficients)
    shift = float(formulas.frequency_shift(a0, omega, Omega, c, *coefficients))
    theta = np.linspace(0, 2 * np.pi, 512, endpoint=False)
    u, du, ddu = (np.zeros_like(theta) for _ in range(3))
    for (_, k), z in zip(formulas.keys, amplitudes):
        wave = complex(z) * np.exp(1j * k * theta)
        u, du, ddu = u + wave.real, du + (1j * k * Omega * wave).real, \
            ddu - ((k * Omega) ** 2 * wave).real
    drive = (a0 * (omega**2 - Omega**2 + 2j * c * Omega) * np.exp(1j * theta)).real
    residual = ddu + 2 * c * du + (omega**2 - shift) * u - drive
    for (kind, j), x in zip(names, coefficients):
        residual += x * u**j * (du if kind == "d" else 1.0)
    return float(np.max(np.abs(residual)))


@pytest.mark.parametrize("order", [1, 2, 3, 4, 6])
def test_consistent_residual_slope_in_eps(order):
    """Substituted into the equation in contact, the consistent series leaves O(eps^(N+1)):
    the slope of the residual against the bookkeeping's eps is N + 1 (the scales stay
    above the round-off floor of some 1e-14, which order 6 meets at eps = 0.02)."""
    scales = np.array([0.32, 0.16, 0.08, 0.04])
    residuals = np.array([_residual_in_contact(order, s) for s in scales])
    slope = np.polyfit(np.log(scales), np.log(residuals), 1)[0]
    assert abs(slope - (order + 1)) < 0.15, f"measured slope {slope:.3f}, expected {order + 1}"


# -- two routes to the numbers --------------------------------------------------------

@pytest.mark.parametrize("parameters", [PAPER, contact(1.5, 0.5), contact(3.0, 2.0)])
@pytest.mark.parametrize("name", ["paper", "consistent"])
def test_numeric_scheme_equals_the_closed_forms(parameters, name):
    """NumericSeries (the scheme on samples) against the lambdified closed forms."""
    rng = np.random.default_rng(7)
    a0, omega = rng.uniform(1e-8, 6e-8, 6), rng.uniform(8e3, 1e4, 6)
    Omega, c = rng.uniform(3e3, 9e3, 6), np.full(6, 150.0)
    truncation = truncation_for(name, parameters)
    series = derive(5, truncation)
    closed = lambdify_chain(series)
    numeric = NumericSeries(5, type(truncation)(truncation.name, *truncation.at_order(5)))
    assert numeric.coefficients == closed.coefficients
    coefficients = series_values(parameters).coefficients(closed.coefficients)
    for z_closed, z_numeric in zip(closed.amplitudes(a0, omega, Omega, c, *coefficients),
                                   numeric.amplitudes(a0, omega, Omega, c, *coefficients)):
        scale = np.max(np.abs(z_closed))
        assert np.max(np.abs(z_numeric - z_closed)) <= 1e-12 * scale + 1e-300
    for b_closed, b_numeric in zip(closed.b(a0, omega, Omega, c, *coefficients),
                                   numeric.b(a0, omega, Omega, c, *coefficients)):
        np.testing.assert_allclose(b_numeric, b_closed, rtol=1e-12)


def test_compile_series_routes():
    assert type(compile_series(4, "paper")).__name__ == "CompiledSeries"
    assert type(compile_series(4)).__name__ == "KernelSeries"  # the paper's contact: d_1
    assert type(compile_series(4, compiled=False)).__name__ == "NumericSeries"
    assert compile_series(4, "consistent", contact(2.0, 0.0)) is compile_series(4, "paper")


# -- the backbone ----------------------------------------------------------------------

def test_textbook_coefficient():
    """(9 k3 omega0^2 - 10 k2^2) a^2 / (24 omega0^4), with k_j = omega0^2 kappa_j / y0^(j-1)."""
    kappa2 = (m2_symbol - 1) / 2
    kappa3 = (m2_symbol - 1) * (m2_symbol - 2) / 6
    textbook = (9 * kappa3 - 10 * kappa2**2) / 24
    assert sp.simplify(power_law_backbone_coefficients(2)[2] - textbook) == 0


def test_paper_contact_backbone_is_eq26s_in_its_alpha():
    """m2 = 2: the consistent coefficients in a / y0 are Eq. 2.6's in a / (2 y0), exactly."""
    consistent, paper = backbone_series(8), backbone_series(8, "paper")
    assert all(c == p / 2**k for k, (c, p) in enumerate(zip(consistent.coefficients,
                                                             paper.coefficients)))


@pytest.mark.parametrize("m2", [1.5, 2.5, 3.0])
def test_backbone_against_the_exact_backbone(m2):
    """The error of the frequency drop at u_max = 0.3 y0 falls by 4x an order pair (measured:
    m2 = 1.5: 2.2e-2, 8.2e-4, 4.0e-5, 2.3e-6 at orders 2, 4, 6, 8), and the paper's
    truncation stays 24-56 % off."""
    parameters = contact(m2)
    exact = exact_backbone(np.array([0.3]) * Y0, model=ContactModel(parameters))
    drop = exact.f_n0_hz - exact.frequency_hz[0]
    errors = []
    for order in (2, 4, 6, 8):
        series = backbone_series(order, parameters=parameters)
        ratio = series.frequency_ratio(series.alpha_per_m() * exact.a1_m[0])
        errors.append(abs((exact.f_n0_hz * (1 - ratio)) / drop - 1))
    assert all(later < earlier / 4 for earlier, later in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-5
    paper = backbone_series(8, "paper", parameters)
    paper_drop = exact.f_n0_hz * (1 - paper.frequency_ratio(paper.alpha_per_m()
                                                             * exact.a1_m[0]))
    assert abs(paper_drop / drop - 1) > 0.2


def test_backbone_frequency_at_app():
    parameters = contact(1.5)
    exact = exact_backbone(np.array([0.1, 0.3]) * Y0, model=ContactModel(parameters))
    series = backbone_series(8, parameters=parameters)
    np.testing.assert_allclose(series.frequency_at_app_hz(exact.app_m), exact.frequency_hz,
                               rtol=1e-6)


# -- the forced response against RK4 of the full model ---------------------------------

def _rk4_app(branch, order, parameters, pa_frac, truncation):
    orbit = series_orbits(branch, order, parameters, truncation=truncation)
    found = steady_states(branch.frequency_hz, pa_frac * parameters.Q_n,
                          model=ContactModel(parameters), y_init_m=orbit.y_start_m,
                          v_init_m_s=orbit.v_start_m_s, app_guess_m=branch.app_m)
    assert found.settled.all()
    return found.app_m


@pytest.mark.parametrize("m2, l, pa_frac, band", [
    (1.5, 0.5, 0.04, (1200.0, 1320.0)),  # f_n0 1286 Hz; Eq. 2.6's bends too little
    (2.5, 1.5, 0.03, (1500.0, 1700.0)),  # f_n0 1661 Hz; Eq. 2.6's bends too much
])
def test_forced_response_against_rk4(m2, l, pa_frac, band):
    """Consistent order 8 within 0.05 % of RK4 wherever valid (measured: 0.02 %);
    the paper's truncation, at the same frequencies, flagged wherever it is off by more
    than its tolerance."""
    parameters = contact(m2, l)
    frequency = np.linspace(*band, 7)
    response = frequency_response(frequency, pa_frac, 8, parameters=parameters)
    (branch,) = response.branches  # one response: no spurious bistability
    rk4 = _rk4_app(branch, 8, parameters, pa_frac, "consistent")
    assert branch.valid.all()
    assert np.max(np.abs(branch.app_m / rk4 - 1)) < 5e-4
    paper = frequency_response(frequency, pa_frac, 8, parameters=parameters,
                               truncation="paper")
    off = 0
    for b in paper.branches:
        truth = np.interp(b.frequency_hz, frequency, rk4)
        if len(paper.branches) == 1:
            truth = _rk4_app(b, 8, parameters, pa_frac, "paper")
        wrong = np.abs(b.app_m / truth - 1) > 0.01
        assert not (wrong & b.valid).any()
        off += int(wrong.sum())
    assert off >= 2  # the paper's truncation is off there, and says so


def test_paper_model_consistent_is_closer_to_rk4():
    """The paper's contact at 0.05 Q on the bent primary peak: the u u' damping term that
    Eq. 2.6 leaves out, measured against RK4 of the full model."""
    frequency = np.array([1400.0, 1440.0, 1470.0])
    errors = {}
    for truncation in ("paper", "consistent"):
        response = frequency_response(frequency, 0.05, 8, truncation=truncation)
        top = response.branches[0]
        rk4 = _rk4_app(top, 8, PAPER, 0.05, truncation)
        errors[truncation] = np.abs(top.app_m / rk4 - 1)
    assert np.all(errors["consistent"] <= errors["paper"])
    assert np.max(errors["consistent"]) < 1e-3


# -- bad input -------------------------------------------------------------------------

def test_bad_truncation_names_the_argument():
    for call in (lambda: derive(2, "exact"),
                 lambda: frequency_response([1000.0], 0.05, 2, truncation="exact"),
                 lambda: backbone_series(2, "full"),
                 lambda: compile_series(2, "none")):
        with pytest.raises(ValueError, match="`truncation` must be one of"):
            call()


@pytest.mark.parametrize("parameters", [PAPER, contact(1.5, 0.5)])
def test_the_engines_of_a_consistent_response_agree(parameters, monkeypatch):
    """Three routes: the generated kernels of the order and terms ("compiled"), the
    numpy root search on the scheme's numba kernel ("auto" before those are built) and
    on the scheme in numpy ("numpy"): the same branches, roots and flags."""
    f_n0 = eq26_numbers(parameters).f_n0_hz
    frequency = np.linspace(0.93 * f_n0, 0.99 * f_n0, 13)
    compiled = frequency_response(frequency, 0.06, 3, parameters=parameters,
                                  engine="compiled")
    monkeypatch.setattr(frequency_module, "series_kernels_built", lambda *args: False)
    routes = [compiled, *(frequency_response(frequency, 0.06, 3, parameters=parameters,
                                             engine=e) for e in ("auto", "numpy"))]
    assert max(len(r.branches) for r in routes) >= 3  # the bent peak: three roots
    for other in routes[1:]:
        assert len(other.branches) == len(routes[0].branches)
        for a, b in zip(routes[0].branches, other.branches):
            np.testing.assert_array_equal(a.frequency_hz, b.frequency_hz)
            np.testing.assert_allclose(a.omega_rad_s, b.omega_rad_s, rtol=1e-12)
            np.testing.assert_allclose(a.app_m, b.app_m, rtol=1e-9)
            assert np.array_equal(a.valid, b.valid)


@pytest.mark.parametrize("parameters", [PAPER, contact(1.5, 0.5)])
def test_the_generated_kernels_of_a_consistent_series_are_the_scheme(parameters):
    """The straight-line code generated from the closed forms against the scheme in
    numpy, at random points: the residual of the frequency equation and the harmonics
    of orders N, N+1, N+2."""
    order = 3
    truncation = truncation_for("consistent", parameters)
    values = series_values(parameters)
    kernels = series_kernels(order, truncation)
    k_d = np.array(values.coefficients(kernels.COEFFICIENTS))
    rng = np.random.default_rng(5)
    omega = rng.uniform(0.6, 1.2, 500) * values.omega0_rad_s
    Omega = rng.uniform(0.3, 1.3, 500) * values.omega0_rad_s
    G, c = 0.1 * values.Q_n * values.G_per_P_a, values.c_per_s
    a0 = G / np.hypot(omega**2 - Omega**2, 2 * c * Omega)
    residual = np.empty(omega.size)
    kernels.residual_lanes(G, omega, Omega, c, k_d, values.omega0_rad_s, residual)
    scheme = NumericSeries(order, truncation)
    shift = scheme.frequency_shift(a0, omega, Omega, c, *values.coefficients(
        scheme.coefficients))
    np.testing.assert_allclose(residual, omega**2 - values.omega0_rad_s**2 - shift,
                               rtol=1e-11)
    shape = (3, kernels.TOP_HARMONIC + 1, omega.size)
    real, imag = np.empty(shape), np.empty(shape)
    kernels.harmonics_lanes(a0, omega, Omega, c, k_d, real, imag)
    for m in range(3):
        later = NumericSeries(order + m, truncation)
        expected = later.harmonics(later.amplitudes(a0, omega, Omega, c, *values.coefficients(
            later.coefficients)))
        got = (real[m] + 1j * imag[m]).T
        np.testing.assert_allclose(got[:, :expected.shape[1]], expected, rtol=0,
                                   atol=1e-11 * np.abs(expected).max())


def test_the_derivation_study_of_a_consistent_series():
    """Step by step in the engine's names: its b_2 is the series' closed form (the phase
    of u_1's harmonic 2 written as the study writes it, psi_1_2 + theta_2)."""
    from perturb import derivation_latex, derivation_text
    from perturb.series import series_symbols as sym

    series = derive(2, parameters=contact(1.5, 0.5))
    text = derivation_text(series)
    assert "in the engine's names" in text and "(Eq. 2." not in text
    line = next(x for x in text.splitlines() if x.strip().startswith("b_2 = "))
    study = sp.sympify(line.split("=", 1)[1], locals={
        name: sp.Symbol(name, real=True) for name in
        ("A_0_1", "A_1_0", "A_1_2", "phi_0_1", "psi_1_2", "theta_2", "h", "k_3", "d_1",
         "d_2", "Omega")})
    closed = series.b_closed_form(2).subs(sym.phase(1, 2), sp.Symbol("psi_1_2", real=True)
                                          + sp.Symbol("theta_2", real=True))
    names = {s: sp.Symbol(str(s), real=True) for s in closed.free_symbols}
    assert sp.simplify(study - closed.xreplace(names)) == 0
    assert r"\tag{" not in derivation_latex(series)


# -- printing --------------------------------------------------------------------------

def test_the_consistent_series_prints_its_coefficients(tmp_path):
    """Text, LaTeX and JSON name k_j and d_j and give their closed forms; the command
    line writes them for the contact of --set."""
    import json

    from perturb import latex_report, series_json, text_report
    from perturb.__main__ import main

    series = derive(2, parameters=contact(1.5, 0.5))
    text = text_report(series)
    assert "k_3 = S*c_n*m2*y0**(m2 - 3)*(m2**2 - 3*m2 + 2)/(6*M)" in text
    assert "b_2 = 3*A_0_1**2*k_3/4" in text  # the textbook 3/4 k3 a^2 of the cubic spring
    assert r"d_{2} u^{2} \dot u" in latex_report(series)
    data = series_json(series)
    assert data["truncation"] == "consistent" and "paper_names" not in data
    assert set(data["coefficients"]) == {"h", "k_3", "d_1", "d_2"}
    out = tmp_path / "s.json"
    assert main(["--quiet", "derive", "--order", "2", "--set", "m2=1.5", "--set", "l=0.5",
                 "--json", str(out)]) == 0
    assert json.loads(out.read_text())["coefficients"] == data["coefficients"]


def test_cli_backbone_at_amplitudes(tmp_path):
    import json

    from perturb.__main__ import main

    out = tmp_path / "b.json"
    parameters = contact(1.5)
    exact = exact_backbone(np.array([0.2]) * Y0, model=ContactModel(parameters))
    sets = [f"--set=c_n={parameters.c_n!r}", "--set=m2=1.5"]
    assert main(["--quiet", "backbone", "--order", "8", *sets, "--app-m",
                 repr(float(exact.app_m[0])), "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["app_m"] == [float(exact.app_m[0])]
    assert data["frequency_hz"][0] == pytest.approx(exact.frequency_hz[0], rel=1e-6)


def test_series_orbits_refuses_a_branch_of_the_other_truncation():
    # A branch does not record its truncation: its roots tell (Eq. 2.7 holds for one).
    frequency = np.array([1000.0, 1420.0])
    branch = frequency_response(frequency, 0.05, 6, truncation="paper").branches[0]
    series_orbits(branch, 6, truncation="paper")
    with pytest.raises(ValueError, match="`branch` is not a branch of the 'consistent'"):
        series_orbits(branch, 6)


def test_a_scene_on_eq26_solves_eq26s_series():
    from numerics.scenes import SceneError, parse_scene

    text = ('effects = "{}"\n[excitation]\npa_frac = 0.05\nfrequency_hz = [800.0]\n'
            '[study]\nkind = "analytic_response"\n')
    assert parse_scene(text.format("eq26")).options["truncation"] == "paper"
    assert parse_scene(text.format("full")).options["truncation"] == "consistent"
    with pytest.raises(SceneError, match='truncation = \\"paper\\"'):
        parse_scene(text.format("linear"))


def test_backbone_frequency_is_nan_past_contact_loss():
    """Past loss of contact the free oscillation is not the law's: no frequency."""
    series = backbone_series(8)
    exact = exact_backbone(np.array([0.5, 1.2]) * Y0)
    found = series.frequency_at_app_hz(exact.app_m)
    assert np.isfinite(found[0]) and not exact.contact_lost[0]
    assert np.isnan(found[1]) and exact.contact_lost[1]


def test_a_derivation_scene_derives_the_series_of_its_truncation():
    from numerics.scenes import parse_scene, run_scene

    text = '{}[model]\nm2 = 1.5\n[study]\nkind = "derivation"\norder = 2\n'
    consistent = run_scene(parse_scene(text.format("")))
    paper = run_scene(parse_scene(text.format('effects = "eq26"\n')))
    assert "k_3" in consistent.text and consistent.effects["spring"] == "power"
    assert "in the paper's names" in paper.text and "k_3" not in paper.text
