"""Fig. 4: natural frequency against the height of a steel body."""

import numpy as np
import pytest

from numerics._natural_frequency import natural_frequency_vs_height, steel_density
from perturb import PAPER, PAPER_CUBE_SIDE_M, PAPER_F_N0_HZ, ContactModel, ContactParameters, Eq26


def test_density_of_the_paper_cube():
    assert steel_density() * PAPER_CUBE_SIDE_M**3 == pytest.approx(PAPER.M, rel=1e-15)


def test_the_cube_is_the_paper_body():
    sweep = natural_frequency_vs_height([PAPER_CUBE_SIDE_M])
    assert sweep.mass_kg[0] == pytest.approx(PAPER.M, rel=1e-14)
    assert sweep.f_n0_hz[0] == pytest.approx(Eq26().numeric()["f_n0_hz"], rel=1e-13)
    # The paper rounds f_n0 to 1485 Hz (Section 3).
    assert sweep.f_n0_hz[0] == pytest.approx(PAPER_F_N0_HZ, abs=1.0)


@pytest.mark.parametrize("m2", [1.5, 2.0, 3.0])
def test_frequency_falls_as_height_to_minus_one_over_two_m2(m2):
    # omega0^2 = g m2 (S c_n / (M g))^(1/m2) is proportional to M^(-1/m2), and
    # M to h_b: f_n0 ~ h_b^(-1/(2 m2)).
    parameters = ContactParameters(m2=m2)
    sweep = natural_frequency_vs_height(parameters=parameters)
    slope = np.polyfit(np.log(sweep.height_m), np.log(sweep.f_n0_hz), 1)[0]
    assert slope == pytest.approx(-1 / (2 * m2), rel=1e-10)
    # Each point is f_n0 of Eq. 2.6 for a body of that mass.
    middle = ContactParameters(m2=m2, M=float(sweep.mass_kg[50]))
    expected = Eq26(ContactModel(middle)).numeric()["f_n0_hz"]
    assert sweep.f_n0_hz[50] == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize(
    "kwargs, name", [({"height_m": [0.0]}, "height_m"), ({"points": 1}, "points")]
)
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        natural_frequency_vs_height(**kwargs)
