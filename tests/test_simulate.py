"""simulate(): effects, observables, bad input and failing lanes."""

import math

import numpy as np
import pytest

from numerics import simulate
from perturb import EQ_2_6, LINEAR, ContactModel, ContactParameters, eq26_numbers


def test_fractional_exponents_run_through_contact_loss(weight):
    # m2 = 1.5 and l = 0.5 would give NaN for y < 0 if a negative base were ever raised.
    model = ContactModel(ContactParameters(m2=1.5, l=0.5))
    y0 = eq26_numbers(model.parameters).y0_m
    run = simulate([490.0, 1200.0], 0.5 * weight, periods=30, model=model,
                   y_init_m=[3 * y0, -2 * y0], record=("final", "minmax"), record_periods=30)
    assert run.ymin_m.min() < 0, "the run must lose contact"
    assert np.isfinite(run.y_final_m).all() and not run.failed.any()


def test_minmax_run_stores_no_history(weight):
    run = simulate(1000.0, 0.1 * weight, periods=3, record=("minmax",))
    assert run.history_y_m is None and run.extrema is None
    assert run.ymin_m is not None


def test_extrema_lie_between_min_and_max_and_alternate(weight):
    run = simulate(740.0, 0.15 * weight, periods=200, record=("extrema",), record_periods=1)
    rows = run.extrema[0]
    assert len(rows) >= 2
    assert np.all(np.diff(rows[:, 2]) != 0), "maxima and minima must alternate"
    assert rows[:, 1].max() == run.ymax_m[0] and rows[:, 1].min() == run.ymin_m[0]


def test_history_matches_final_state(weight):
    run = simulate(1000.0, 0.1 * weight, periods=4, record=("history", "final"), record_periods=2)
    assert run.history_y_m.shape == (1, 2 * 128)
    assert run.history_y_m[0, -1] == run.y_final_m[0]
    assert run.history_phase[-1] == 2.0


def test_minmax_refines_extrema_between_steps(weight):
    # Linear oscillator in steady state: App = 2 |G / (omega0^2 - Omega^2 + 2 i c Omega)|.
    # The sampled max misses the crest by up to 1 - cos(pi/N), second order; the
    # Hermite-refined extremum keeps RK4's fourth order.
    k = eq26_numbers()
    omega = 2 * np.pi * 1000.0
    transfer = 1 / (k.omega0_rad_s**2 - omega**2 + 2j * k.c_per_s * omega)
    exact = 2 * abs(k.G_per_P_a * weight * transfer)
    steps, refined = [48, 96, 192], []
    for n in steps:
        run = simulate(1000.0, weight, periods=150, steps_per_period=n,
                       model=ContactModel(effects=LINEAR), record=("minmax", "history"))
        sampled_error = abs((run.history_y_m.max() - run.history_y_m.min()) / exact - 1)
        refined.append(abs(run.app_m[0] / exact - 1))
        assert refined[-1] < sampled_error / 10, (n, refined[-1], sampled_error)
    slope = -np.polyfit(np.log(steps), np.log(refined), 1)[0]
    assert slope > 3.7, f"measured order {slope:.3f}; errors {refined}"


def test_a_failing_lane_does_not_stop_the_batch(weight):
    # Eq. 2.6's quadratic spring has no floor: a strong push sends u to -infinity.
    model = ContactModel(effects=EQ_2_6)
    run = simulate([1000.0, 1000.0], [0.05 * weight, 20 * weight], periods=50, model=model)
    assert run.failed.tolist() == [False, True]
    assert np.isfinite(run.app_m[0])
    assert run.message[0] == "" and "non-finite" in run.message[1]
    with pytest.raises(RuntimeError, match="lane 1"):
        simulate([1000.0, 1000.0], [0.05 * weight, 20 * weight], periods=50, model=model,
                 throw=True)


def test_an_unstable_step_is_caught_and_explained(weight):
    # m2 = 1 with the paper's c_n makes a very stiff contact (omega0 dt ~ 109 at 128
    # steps per period), and l = 0 a strongly overdamped one: its fastest rate, c +
    # sqrt(c^2 - omega0^2), gives rate*dt = 1.17e4. Regression: the state grew to
    # -5e18 m without being flagged.
    model = ContactModel(ContactParameters(m2=1.0, l=0.0))
    run = simulate(1000.0, 0.1 * weight, periods=5, model=model)
    assert run.failed[0] and "rate*dt = 1.17e+04" in run.message[0]


def test_a_diverging_bounce_is_flagged_and_resolved_by_finer_steps(weight):
    # m2 = 1.5, l = 0.5 released from 3 um above the slideway at 490 Hz, 0.5 Q: at 64
    # steps the impact is under-resolved and y runs away (to -8.4e6 m), flagged. (At 128
    # steps, with each switch located in its step, y reaches -2 cm: within the divergence
    # limit, 1e3 g / f_e^2 = 4 cm, and so not flagged; before, it ran to -83 m.)
    model = ContactModel(ContactParameters(m2=1.5, l=0.5))
    coarse, fine = (simulate(490.0, 0.5 * weight, periods=50, model=model, y_init_m=-3e-6,
                             steps_per_period=n, record="minmax", record_periods=50)
                    for n in (64, 1024))
    assert coarse.failed[0] and not fine.failed[0]
    assert -4e-6 < fine.ymin_m[0] < 0


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"steps_per_period": 3}, "`steps_per_period`.*3"),
        ({"steps_per_period": 10.5}, "`steps_per_period`.*10.5"),
        ({"steps_per_period": math.nan}, "`steps_per_period`.*nan"),
        ({"steps_per_period": math.inf}, "`steps_per_period`.*inf"),
        ({"steps_per_period": None}, "`steps_per_period`.*None"),
        ({"periods": "5"}, "`periods`.*'5'"),
        ({"frequency_hz": []}, "`frequency_hz`.*non-empty"),
        ({"p_a_n": -1.0}, "`p_a_n`.*-1.0"),
        ({"p_a_n": math.nan}, "`p_a_n`.*nan"),
        ({"frequency_hz": 0.0}, "`frequency_hz`.*0.0"),
        ({"frequency_hz": -5.0}, "`frequency_hz`.*-5.0"),
        ({"frequency_hz": math.inf}, "`frequency_hz`.*inf"),
        ({"periods": 0}, "`periods`.*0"),
        ({"record": ("spectrum",)}, "`record`.*'spectrum'"),
        ({"y_init_m": math.nan}, "`y_init_m`"),
        ({"frequency_hz": [1.0, 2.0], "p_a_n": [1.0, 2.0, 3.0]}, "broadcast"),
        ({"model": "full"}, "`model`"),
    ],
)
def test_bad_input_is_named(kwargs, message):
    arguments = {"frequency_hz": 1000.0, "p_a_n": 0.1, "periods": 2} | kwargs
    with pytest.raises(ValueError, match=message):
        simulate(**arguments)
