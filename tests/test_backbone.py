"""The exact backbone against independent routes: the linear limit, the hand-derived
Lindstedt coefficient, the closed-form contact-loss level, a tight solve_ivp of the
conservative ODE written from the model's expressions, and the project's RK4."""

import json

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from numerics import Backbone, exact_backbone, simulate
from numerics.backbone.restoring import restoring_force
from numerics.cli import main
from perturb import EQ_2_6, ContactModel, ContactParameters, eq26_numbers
from perturb import symbols as sym
from perturb.common import load

EXPONENTS = (1.0, 1.5, 2.0, 2.5, 3.0)


def model_with(m2: float, **changes) -> ContactModel:
    return ContactModel(ContactParameters(m2=m2, **changes))


def y0_of(model: ContactModel) -> float:
    return model.evaluate(model.static_deflection)


# -- the linear limit -------------------------------------------------------------------
@pytest.mark.parametrize("m2", EXPONENTS)
@pytest.mark.parametrize("level", [1e-14, 1e-9, 1e-6])
def test_small_amplitude_limit_is_f_n0(m2, level):
    # A naive E - V(y) loses every digit at 1e-14 y0; the quadrature must not.
    model = model_with(m2)
    backbone = exact_backbone([level * y0_of(model)], model=model)
    f_n0 = eq26_numbers(model.parameters).f_n0_hz
    error = abs(backbone.frequency_hz[0] / f_n0 - 1)
    assert error < 1e-9, f"m2={m2}, u/y0={level}: relative error {error:.2e}"
    assert abs(backbone.f_n0_hz / f_n0 - 1) < 1e-12
    # Linear vibration: A_pp = 2 a1 = 2 u_max.
    assert backbone.app_m[0] == pytest.approx(2 * level * y0_of(model), rel=1e-6)
    assert backbone.a1_m[0] == pytest.approx(level * y0_of(model), rel=1e-6)


@pytest.mark.parametrize("m2", [1.5, 2.0, 2.5, 3.0])
def test_leading_amplitude_correction_is_lindstedt(m2):
    # For u'' + w0^2 u + a2 u^2 + a3 u^3 = 0 (Nayfeh and Mook, 1995, Sec. 4.1):
    # w/w0 = 1 + (9 a3 w0^2 - 10 a2^2) / (24 w0^4) a1^2. Here, scaled by y0 and
    # sqrt(y0/g): w0^2 = m2, a2 = m2 (m2-1)/2, a3 = m2 (m2-1)(m2-2)/6. For m2 = 2
    # it is -5/48: the series of Eq. 2.7 at its first non-zero order.
    a2, a3 = m2 * (m2 - 1) / 2, m2 * (m2 - 1) * (m2 - 2) / 6
    expected = (9 * a3 * m2 - 10 * a2**2) / (24 * m2**2)
    model = model_with(m2)
    y0 = y0_of(model)
    backbone = exact_backbone(y0 * np.array([1e-3, 2e-3]), model=model)
    ratio = (backbone.frequency_hz / backbone.f_n0_hz - 1) / (backbone.a1_m / y0) ** 2
    # The next term is O(a1^2): extrapolate the two levels to a1 = 0.
    a = (backbone.a1_m / y0) ** 2
    limit = (ratio[0] * a[1] - ratio[1] * a[0]) / (a[1] - a[0])
    assert limit == pytest.approx(expected, rel=1e-6), f"m2={m2}: {limit} vs {expected}"


# -- contact loss ------------------------------------------------------------------------
def test_contact_loss_level_is_sqrt3_y0_for_m2_2():
    # Hand derivation for m2 = 2: D(s) = s^2 + s^3/3, D(-1) = 2/3, so the level
    # that just reaches y = 0 has (1 + s+)^3 = 3 (1 + s+): y_max = sqrt(3) y0, y_min = 0.
    backbone = exact_backbone([1e-7])
    y0 = backbone.y0_m
    assert backbone.contact_loss_app_m == pytest.approx(np.sqrt(3) * y0, rel=1e-14)


@pytest.mark.parametrize("m2", EXPONENTS)
def test_contact_loss_is_where_ymin_crosses_zero(m2):
    model = model_with(m2)
    y0 = y0_of(model)
    loss_app = exact_backbone([y0], model=model).contact_loss_app_m
    u_loss = loss_app - y0  # y_max - y0 when y_min = 0
    around = u_loss * (1 + np.array([-1e-6, -1e-9, 1e-9, 1e-6]))
    backbone = exact_backbone(around, model=model)
    assert np.all(backbone.contact_lost == [False, False, True, True])
    assert np.all(np.sign(backbone.ymin_m) == [1, 1, -1, -1]), backbone.ymin_m
    assert np.all(np.abs(backbone.ymin_m) < 1e-5 * y0)
    # The two regimes (contact / bouncing) meet continuously at the edge.
    jump = abs(backbone.frequency_hz[2] / backbone.frequency_hz[1] - 1)
    assert jump < 1e-8, f"m2={m2}: frequency jumps by {jump:.2e} across contact loss"


# -- solve_ivp of the conservative ODE from the model's own expressions ------------------
def conservative_rhs(model: ContactModel):
    """Eq. 2.4 with F_d = 0 (h_n -> 0) and P = 0, lambdified from perturb."""
    acceleration = model.acceleration(sp.Integer(0)).subs(sym.h_n, 0).subs(model.values)
    function = sp.lambdify((sym.y, sym.v), acceleration, modules="math")
    return lambda t, state: (state[1], function(state[0], state[1]))


def free_oscillation(model: ContactModel, u_max: float, periods: int = 3) -> dict:
    """Period, turning points and fundamental amplitude of a free run from rest at y0 + u."""
    y0 = y0_of(model)
    omega0 = np.sqrt(model.evaluate(sym.g * sym.m2 / model.static_deflection))
    top, bottom = (lambda t, s: s[1]), (lambda t, s: s[1])
    top.direction, bottom.direction = -1, 1
    run = solve_ivp(
        conservative_rhs(model), (0, periods * 60 * np.pi / omega0), [y0 + u_max, 0.0],
        method="DOP853", rtol=1e-13, atol=[1e-14 * y0, 1e-14 * y0 * omega0],
        events=[top, bottom], dense_output=True,
    )
    tops = run.t_events[0][-(periods + 1):]
    period = (tops[-1] - tops[0]) / periods
    samples = run.sol(tops[0] + period * np.arange(4096) / 4096)[0]
    return {
        "frequency": 1 / period,
        "ymin": run.y_events[1][-1, 0],
        "a1": 2 * abs(np.fft.rfft(samples)[1]) / samples.size,
    }


@pytest.mark.parametrize("m2", [2.0, 2.5])
@pytest.mark.parametrize("level", [0.01, 0.7, 1.0, 2.5])
def test_agrees_with_tight_solve_ivp(m2, level):
    model = model_with(m2)
    y0 = y0_of(model)
    backbone = exact_backbone([level * y0], model=model)
    free = free_oscillation(model, level * y0)
    assert backbone.frequency_hz[0] / free["frequency"] - 1 == pytest.approx(0, abs=1e-10)
    assert (backbone.ymin_m[0] - free["ymin"]) / backbone.app_m[0] == pytest.approx(0, abs=1e-10)
    assert backbone.a1_m[0] / free["a1"] - 1 == pytest.approx(0, abs=1e-9)


# -- the project's RK4, with damping made negligible --------------------------------------
def rk4_frequency_error(level: float, steps: tuple[int, ...], periods: int = 4) -> np.ndarray:
    """|f_RK4 / f_exact - 1| after ``periods`` periods started from rest at y_max.

    The run is phase-locked to the exact frequency, so it should end where it
    started; the time it is off, |v_end / y''(y_max)|, over the time run is the
    relative error of the frequency.
    """
    model = model_with(2.0, h_n=1e-3)  # damping ratio ~ 1e-16: conservative in effect
    y0 = y0_of(model)
    backbone = exact_backbone([level * y0], model=model)
    r = restoring_force(model)
    acceleration_at_top = -r(np.array([level])) * model.evaluate(sym.g)
    errors = []
    for n in steps:
        run = simulate(backbone.frequency_hz, 0.0, periods=periods, steps_per_period=n,
                       model=model, y_init_m=y0 + level * y0, v_init_m_s=0.0, record=("final",))
        errors.append(abs(run.v_final_m_s[0] / acceleration_at_top[0]) * backbone.frequency_hz[0])
    return np.array(errors) / periods


def test_rk4_converges_to_backbone_with_order_4_in_contact():
    steps = (32, 64, 128, 256)
    errors = rk4_frequency_error(0.3, steps)
    slope = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 3.8 < slope < 4.2, f"order {slope:.2f}, errors {errors}"
    assert errors[-1] < 1e-8


def test_rk4_converges_to_backbone_while_bouncing():
    # The force has a kink in its derivative at y = 0, which caps RK4's order.
    steps = (64, 128, 256)
    errors = rk4_frequency_error(1.0, steps)
    slope = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert slope > 2.5, f"order {slope:.2f}, errors {errors}"
    assert errors[-1] < 1e-7


# -- shape, speed and input --------------------------------------------------------------
def test_frequency_falls_with_amplitude_and_fast():
    backbone = exact_backbone(points=300)
    assert np.all(np.diff(backbone.app_m) > 0)
    assert np.all(np.diff(backbone.frequency_hz) <= 1e-9 * backbone.f_n0_hz)
    assert np.array_equal(backbone.contact_lost, backbone.ymin_m < 0)
    again = exact_backbone(points=300)
    assert again.elapsed_s < 1.0, f"{again.elapsed_s:.3f} s for 300 points"


def test_quadrature_converges_geometrically():
    # Measured: 7e-8, 2e-11, 2e-14 at 8, 16, 24 nodes; algebraic convergence
    # (an unremoved endpoint singularity) would fall by a fixed power instead.
    reference = exact_backbone(points=100, nodes=128)
    errors = [
        np.max(np.abs(exact_backbone(reference.u_max_m, nodes=n).frequency_hz
                      / reference.frequency_hz - 1))
        for n in (8, 16, 24)
    ]
    assert errors[1] < 1e-3 * errors[0] and errors[2] < 1e-13, errors


@pytest.mark.parametrize(
    "kwargs, name",
    [({"u_max_m": [-1e-9]}, "u_max_m"), ({"u_max_m": []}, "u_max_m"),
     ({"points": 0}, "points"), ({"points": 2.5}, "points"), ({"nodes": 4}, "nodes"),
     ({"model": ContactModel(effects=EQ_2_6)}, "model"),
     ({"app_range_m": (1e-7,)}, "app_range_m"), ({"app_range_m": (2e-7, 1e-7)}, "app_range_m"),
     ({"app_range_m": (0.0, 1e-7)}, "app_range_m"), ({"app_range_m": 1e-7}, "app_range_m"),
     ({"u_max_m": [1e-8], "app_range_m": (1e-8, 1e-7)}, "app_range_m")],
)
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        exact_backbone(**kwargs)


# -- an A_pp range: up to the bouncing branches of Fig. 2 ---------------------------------
@pytest.mark.parametrize("m2", [1.0, 1.5, 2.0, 3.0])
def test_app_range_ends_at_the_asked_amplitudes(m2):
    # From 1e-9 y0 (linear) to 100 y0 (bouncing; for m2 = 2, 22.5 um, Fig. 2's scale).
    model = model_with(m2)
    ends = (1e-9 * y0_of(model), 100 * y0_of(model))
    backbone = exact_backbone(app_range_m=ends, model=model, points=40)
    assert backbone.app_m[0] == pytest.approx(ends[0], rel=1e-12)
    assert backbone.app_m[-1] == pytest.approx(ends[1], rel=1e-12)
    assert np.all(np.diff(backbone.app_m) > 0)
    assert not backbone.contact_lost[0] and backbone.contact_lost[-1]
    assert backbone.settings["app_range_m"] == list(ends)
    # The same levels, given directly, give the same backbone.
    again = exact_backbone(backbone.u_max_m, model=model)
    assert np.array_equal(again.frequency_hz, backbone.frequency_hz)


def test_app_range_at_25_um_agrees_with_tight_solve_ivp():
    # The top of the bouncing branches of Fig. 2 (A_pp = 25 um): y_min is about -100 y0,
    # a long flight; the exact route against a free DOP853 run of the model's own ODE.
    backbone = exact_backbone(app_range_m=(1e-6, 2.5e-5), points=2)
    free = free_oscillation(ContactModel(), backbone.u_max_m[-1])
    assert backbone.frequency_hz[-1] / free["frequency"] - 1 == pytest.approx(0, abs=1e-9)
    assert backbone.ymin_m[-1] == pytest.approx(free["ymin"], rel=1e-9)


# -- the result contract -----------------------------------------------------------------
def test_round_trip_through_strict_json(tmp_path):
    backbone = exact_backbone(app_range_m=(1e-8, 2.5e-5), points=9)
    data = backbone.as_dict()
    json.dumps(data, allow_nan=False)
    backbone.to_json(tmp_path / "backbone.json")
    back = load(tmp_path / "backbone.json")
    assert isinstance(back, Backbone) and back.as_dict() == data
    assert back.contact_lost.dtype == bool and back.app_m.dtype == float
    assert ContactModel.from_dict(back.model) == ContactModel()
    assert back.settings == {"points": 9, "nodes": 48, "app_range_m": [1e-8, 2.5e-5]}
    assert "\n" not in repr(backbone) and len(repr(backbone)) < 200
    assert str(backbone).splitlines()[0] == backbone.summary()
    assert "contact lost" in backbone.table()


# -- the command line --------------------------------------------------------------------
def test_cli_writes_the_landed_keys(tmp_path, capsys):
    path = tmp_path / "backbone.json"
    assert main(["backbone", "--points", "7", "--json", str(path), "--quiet"]) == 0
    payload = json.loads(path.read_text(encoding="utf-8"))
    for key in ("app_m", "a1_m", "frequency_hz", "contact_lost", "ymin_m", "ymax_m"):
        assert len(payload[key]) == 7, key
    assert payload["contact_lost"][0] is False and payload["contact_lost"][-1] is True
    assert isinstance(load(path), Backbone)
    out = capsys.readouterr()
    assert "contact lost" in out.out and out.err == ""


def test_cli_app_range_covers_a_bouncing_branch(tmp_path, capsys):
    path = tmp_path / "backbone.json"
    assert main(["backbone", "--app-min", "1e-8", "--app-max", "2.5e-5", "--points", "30",
                 "--json", str(path)]) == 0
    payload = json.loads(path.read_text(encoding="utf-8"))
    assert payload["app_m"][0] == pytest.approx(1e-8, rel=1e-12)
    assert payload["app_m"][-1] == pytest.approx(2.5e-5, rel=1e-12)
    assert payload["contact_lost"][0] is False and payload["contact_lost"][-1] is True
    assert payload["ymin_m"][-1] < 0
    err = capsys.readouterr().err
    assert "backbone: 30 energy levels" in err and "2.5e-05" in err


@pytest.mark.parametrize(
    "options, named",
    [(["--points", "0"], "--points"), (["--points", "-2"], "--points"),
     (["--points", "x"], "--points"), (["--app-min", "0", "--app-max", "1e-6"], "--app-min"),
     (["--app-min", "2e-6", "--app-max", "1e-6"], "--app-max"),
     (["--app-min", "1e-6", "--app-max", "1e-6"], "--app-max"),
     (["--app-min", "1e-6"], "--app-max"), (["--app-max", "1e-6"], "--app-min")],
)
def test_cli_bad_input_is_an_argparse_error(options, named, capsys):
    # Regression: --points 0 or -2 ended in a traceback from exact_backbone.
    with pytest.raises(SystemExit) as exit_info:
        main(["backbone", *options, "--quiet"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert f"argument {named}" in err and "Traceback" not in err


# -- the analytic-against-numerical figure -------------------------------------------------
def test_comparison_figure_draws_the_backbone_over_the_curves_shown():
    from types import SimpleNamespace

    from numerics.plots.compare import _covering_backbone

    # Curves from 20 nm up to a bouncing branch at 9 um (NaN: a point that did not settle).
    curves = [SimpleNamespace(app_m=np.array([2e-8, np.nan, 9e-6])),
              SimpleNamespace(app_m=np.array([5e-7]))]
    comparison = SimpleNamespace(curves=curves,
                                 backbone=SimpleNamespace(model=ContactModel().as_dict()))
    backbone = _covering_backbone(comparison, None)
    assert backbone.app_m[0] == pytest.approx(2e-8, rel=1e-12)
    assert backbone.app_m[-1] == pytest.approx(9e-6, rel=1e-12)
    assert backbone.contact_lost[-1]
    # A backbone given must cover them: the default levels stop at A_pp = 4.8 um.
    with pytest.raises(ValueError, match="`backbone` must cover"):
        _covering_backbone(comparison, exact_backbone(points=10))
    assert _covering_backbone(comparison, backbone) is backbone


def test_a_backbone_in_chunks_is_the_backbone_at_once():
    # Levels are integrated 10,000 at a time so that memory stays bounded (some 400 MB at
    # the most levels, 100,000, measured): the same numbers, to round-off (vector lengths
    # change the last bit of 2 % of them, measured).
    chunked = exact_backbone(app_range_m=(1e-9, 2e-5), points=2_500)
    smaller = exact_backbone(app_range_m=(1e-9, 2e-5), points=2_500, levels_per_chunk=1_000)
    for name in ("frequency_hz", "app_m", "a1_m", "ymin_m"):
        np.testing.assert_allclose(getattr(chunked, name), getattr(smaller, name), rtol=1e-14)
    with pytest.raises(ValueError, match="`points` must be an integer <= 100000"):
        exact_backbone(points=100_001)
