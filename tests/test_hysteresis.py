"""Fig. 5: the hysteresis loop of the contact (y against contact pressure)."""

import numpy as np
import pytest

from numerics import hysteresis_loop
from perturb import PAPER_HYSTERESIS_POINT

# The caption of Fig. 5: f_e = 1600 Hz, P_a = 0.40 Q.
FIG5 = PAPER_HYSTERESIS_POINT  # (f_e [Hz], P_a / Q)


@pytest.fixture(scope="module")
def fig5_loop():
    return hysteresis_loop(*FIG5)


def test_loop_is_closed_over_one_period(fig5_loop):
    # 400 periods from rest are ~ 40 decay times of the linearised system.
    assert fig5_loop.closure < 1e-9, fig5_loop.closure
    assert fig5_loop.phase[-1] == 1.0 and fig5_loop.y_m.size == 512


def test_loop_area_is_energy_dissipated_by_damping(fig5_loop):
    # Area by the shoelace formula in the (y, R) plane; dissipation by quadrature
    # of F_d ydot over time: two routes (measured agreement 2.5e-5).
    assert fig5_loop.loop_area_j == pytest.approx(fig5_loop.dissipated_j, rel=0.01)
    assert fig5_loop.dissipated_j > 0


@pytest.mark.parametrize("f_e_hz", [FIG5[0], 1400.0])
def test_drive_supplies_what_damping_dissipates(f_e_hz):
    # At 1400 Hz the slider loses contact (y_min < 0); the balance still holds.
    loop = hysteresis_loop(f_e_hz, FIG5[1])
    assert loop.drive_work_j == pytest.approx(loop.dissipated_j, rel=1e-5)
    assert loop.loop_area_j == pytest.approx(loop.dissipated_j, rel=0.01)
    assert np.all(loop.pressure_pa[loop.y_m <= 0] == 0)


def test_pressure_is_reaction_over_area(fig5_loop):
    # Mean pressure over a period carries the weight (the mean of m yddot vanishes).
    from perturb import PAPER

    weight_pressure = PAPER.weight_n / PAPER.S
    assert np.mean(fig5_loop.pressure_pa) == pytest.approx(weight_pressure, rel=1e-6)


@pytest.mark.parametrize(
    "kwargs, name",
    [({"p_a_frac": -0.1}, "p_a_frac"), ({"steps_per_period": 2}, "steps_per_period"),
     ({"periods": 1}, "periods"), ({"f_e_hz": -5.0}, "f_e_hz")],
)
def test_bad_input_is_named(kwargs, name):
    arguments = {"f_e_hz": FIG5[0], "p_a_frac": FIG5[1], **kwargs}
    with pytest.raises(ValueError, match=f"`{name}`"):
        hysteresis_loop(**arguments)
