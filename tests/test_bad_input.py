"""Bad input is a ValueError (a KeyError for a lookup) that names the argument and its
value, never a bare ZeroDivisionError, IndexError or StopIteration (issue 9, item 4)."""

from functools import partial as _partial

import numpy as np
import pytest

from numerics import attractor_census, compare, hysteresis_loop, simulate, steady_states, sweep
from perturb import frequency_response

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: steady_states(1000.0, 0.1, period_guess=0), "`period_guess`"),
        (lambda: steady_states(1000.0, 0.1, period_guess=9), "`period_guess`"),
        (lambda: steady_states(1000.0, 0.1, method="euler"), "`method`"),
        (lambda: steady_states([1000.0, 900.0], [0.1, 0.2, 0.3]), "broadcast"),
        (lambda: attractor_census(740.0, 0.15, grid={"y_over_y0": [1.0]}), "`grid`"),
        (lambda: attractor_census(740.0, [0.1, 0.2]), "`pa_frac` must be one real number"),
        (lambda: attractor_census([740.0, 750.0], 0.1), "`frequency_hz` must be one real number"),
        (lambda: sweep([1000.0, 900.0], 0.1), "`frequency_hz` must be strictly increasing"),
        (lambda: sweep([1000.0], 0.1, direction="sideways"), "`direction`"),
        (lambda: simulate(1000.0, 0.1, periods=0), "`periods`"),
        (lambda: simulate(1000.0, 0.1, periods=2, record="spectrum"), "`record`"),
        (lambda: frequency_response([800.0], 0.05, omega_range=(0.6,)), "`omega_range`"),
        (lambda: frequency_response([800.0], [0.05, 0.1]), "`pa_frac`"),
        (lambda: hysteresis_loop(1600.0, [0.4]), "`pa_frac`"),
        (lambda: compare((2, -1), 0.05), "`orders`"),
    ],
)
def test_bad_input_is_a_value_error_that_names_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_a_lookup_of_what_is_not_there_lists_what_is():
    result = sweep(np.array([1000.0, 1010.0]), 0.05, direction="up")
    with pytest.raises(KeyError, match=r"available: \[\(0\.05, 'up'\)\]"):
        result.run(0.05, "down")


@pytest.mark.parametrize("work", ["response", "backbone", "numbers"])
def test_a_contact_with_no_finite_equilibrium_is_named(work):
    # c_n = 1e-308 at m2 = 1: y0 = M g / (S c_n) overflows. Once a ZeroDivisionError
    # deep in the backbone, and 0 branches with RuntimeWarnings in the response.
    from perturb import ContactParameters, backbone_series, eq26_numbers

    contact = ContactParameters(c_n=1e-308, m2=1.0, h_n=1e-300)
    calls = {"response": lambda: frequency_response([800.0], 0.05, 2, parameters=contact),
             "backbone": lambda: backbone_series(2, "consistent", contact),
             "numbers": lambda: eq26_numbers(contact)}
    with pytest.raises(ValueError, match=r"`parameters` give no finite equilibrium .*y0_m = inf"):
        calls[work]()
