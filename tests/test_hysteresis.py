"""Fig. 5: the hysteresis loop of the contact (y against contact pressure), and the
reference integrator it is checked against."""

import json

import numpy as np
import pytest

from numerics import HysteresisLoop, hysteresis_loop
from numerics.simulation import reference_last_period
from perturb import EQ_2_6, PAPER, PAPER_HYSTERESIS_POINT, ContactModel, eq26_numbers
from perturb.common import load

# The caption of Fig. 5: f_e = 1600 Hz, P_a = 0.40 Q.
FIG5 = PAPER_HYSTERESIS_POINT  # (f_e [Hz], P_a / Q)


@pytest.fixture(scope="module")
def fig5_loop():
    return hysteresis_loop(*FIG5)


def polygon_factor(steps: int) -> float:
    """Shoelace area of ``steps`` points spaced evenly in time on an ellipse, over its area.

    A loop traced by a harmonic motion is an ellipse; the polygon through N points
    evenly spaced in phase has N/2 sin(2 pi/N) times the area over pi:
    sin(x)/x with x = 2 pi / N, 1 - 2.51e-5 at N = 512. The shoelace formula is
    the trapezoidal rule of the closed integral of R dy, second order in 1/N.
    """
    x = 2 * np.pi / steps
    return np.sin(x) / x


def test_loop_is_closed_over_one_period(fig5_loop):
    # 400 periods from rest are ~ 40 decay times of the linearised system.
    assert fig5_loop.closure < 1e-9, fig5_loop.closure
    assert fig5_loop.phase[-1] == 1.0 and fig5_loop.y_m.size == 512


def test_loop_area_is_energy_dissipated_by_damping(fig5_loop):
    # Two routes: the area by the shoelace formula in the (y, R) plane, and the
    # dissipation by the rectangle rule of F_d ydot over one period (exact to
    # rounding for a smooth periodic integrand). The shoelace's own error is its
    # polygon factor (above): measured, area / dissipation - 1 = -2.510e-5 at 512
    # steps per period, -1.004e-4 at 256 (second order); with the factor taken out
    # the two agree to 2.3e-10 (measured), so 2e-9 is asked.
    assert fig5_loop.loop_area_j / fig5_loop.dissipated_j - 1 == pytest.approx(
        polygon_factor(512) - 1, rel=1e-4)
    assert fig5_loop.loop_area_j == pytest.approx(
        fig5_loop.dissipated_j * polygon_factor(512), rel=2e-9)
    assert fig5_loop.dissipated_j > 0


@pytest.mark.parametrize("frequency_hz", [FIG5[0], 1400.0])
def test_drive_supplies_what_damping_dissipates(frequency_hz):
    # At 1400 Hz the slider loses contact (y_min < 0); the balance still holds.
    # Measured: drive / dissipation - 1 = 7e-10 (1600 Hz) and 2.2e-6 (1400 Hz, the
    # kink of the contact law at y = 0 spoils the rectangle rule's spectral accuracy);
    # loop area against dissipation (polygon factor out): 2.3e-10 and 3.7e-8.
    loop = hysteresis_loop(frequency_hz, FIG5[1])
    assert loop.drive_work_j == pytest.approx(loop.dissipated_j, rel=2e-5)
    assert loop.loop_area_j == pytest.approx(loop.dissipated_j * polygon_factor(512), rel=4e-7)
    assert np.all(loop.pressure_pa[loop.y_m <= 0] == 0)
    assert (loop.y_m.min() < 0) == (frequency_hz == 1400.0)


def test_loop_agrees_with_dop853(fig5_loop):
    # An independent integrator (scipy's DOP853, rtol 1e-10, restarted at every
    # crossing of y = 0) over the same 400 periods from rest at y0, sampled at the
    # loop's phases (every 8th of 4097 samples). Measured: they differ by 4.6e-10 of
    # A_pp (RK4's step error at 512 steps per period; 7.9e-8 at 1400 Hz, where the
    # kink of the contact law at y = 0 lowers RK4's order).
    numbers = eq26_numbers()
    phase, y = reference_last_period(ContactModel(), FIG5[0], FIG5[1] * numbers.Q_n,
                                     numbers.y0_m, 0.0, 400, samples=8 * 512 + 1)
    assert np.allclose(phase[8::8], fig5_loop.phase, rtol=0, atol=1e-12)
    difference = np.max(np.abs(y[8::8] - fig5_loop.y_m)) / np.ptp(fig5_loop.y_m)
    assert difference < 5e-9, difference


def test_pressure_is_reaction_over_area(fig5_loop):
    # Mean pressure over a period carries the weight (the mean of m yddot vanishes).
    weight_pressure = PAPER.Q_n / PAPER.S
    assert np.mean(fig5_loop.pressure_pa) == pytest.approx(weight_pressure, rel=1e-6)


def test_round_trip_through_strict_json(fig5_loop, tmp_path):
    data = fig5_loop.as_dict()
    json.dumps(data, allow_nan=False)
    fig5_loop.to_json(tmp_path / "loop.json")
    back = load(tmp_path / "loop.json")
    assert isinstance(back, HysteresisLoop) and back.as_dict() == data
    assert (back.frequency_hz, back.pa_frac) == FIG5
    assert back.p_a_n == pytest.approx(FIG5[1] * PAPER.Q_n, rel=1e-15)
    assert ContactModel.from_dict(back.model) == ContactModel()
    assert back.settings == {"periods": 400, "steps_per_period": 512}
    assert "\n" not in repr(fig5_loop) and len(repr(fig5_loop)) < 300


@pytest.mark.parametrize(
    "kwargs, name",
    [({"pa_frac": -0.1}, "pa_frac"), ({"pa_frac": [0.1, 0.2]}, "pa_frac"),
     ({"steps_per_period": 2}, "steps_per_period"), ({"periods": 1}, "periods"),
     ({"frequency_hz": -5.0}, "frequency_hz"), ({"frequency_hz": float("nan")}, "frequency_hz"),
     ({"model": "paper"}, "model")],
)
def test_bad_input_is_named(kwargs, name):
    arguments = {"frequency_hz": FIG5[0], "pa_frac": FIG5[1], **kwargs}
    with pytest.raises(ValueError, match=f"`{name}`"):
        hysteresis_loop(**arguments)


# -- the reference integrator ------------------------------------------------------------
def test_reference_raises_when_solve_ivp_fails():
    # Eq. 2.6's quadratic spring has a saddle at u = -2 y0 (m2 = 2): started beyond
    # it, the slider escapes to y -> -infinity in finite time, and DOP853's step
    # shrinks to nothing. It used to return the unfilled samples as a result.
    y0 = eq26_numbers().y0_m
    with pytest.raises(RuntimeError, match="solve_ivp .* failed at t = .*step size"):
        reference_last_period(ContactModel(effects=EQ_2_6), 1000.0, 0.0, -2 * y0, 0.0, 10)


@pytest.mark.parametrize(
    "index, value, name",
    [(1, 0.0, "frequency_hz"), (2, -1.0, "p_a_n"), (3, float("nan"), "y_init_m"),
     (5, 0, "periods")],
)
def test_reference_bad_input_is_named(index, value, name):
    arguments = [ContactModel(), 1000.0, 0.0, 2e-7, 0.0, 2]
    arguments[index] = value
    with pytest.raises(ValueError, match=f"`{name}`"):
        reference_last_period(*arguments)
