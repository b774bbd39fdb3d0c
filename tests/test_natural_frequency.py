"""Fig. 4: natural frequency against the height of a steel body."""

import json
import math

import numpy as np
import pytest

from numerics import HeightSweep, natural_frequency_vs_height
from numerics.contact.natural_frequency import steel_density
from perturb import PAPER_CUBE_SIDE_M, PAPER_F_N0_HZ, ContactModel, ContactParameters, eq26_numbers
from perturb.common import load

# The paper's numbers as Section 2 states them, typed here and not imported: a steel
# cube of 30 mm (width, length and height), M = 0.2106 kg, on S = 30 mm x 30 mm, with
# c_n = 4.52693e16 N/m^(m2+2), m2 = 2 and g = 9.81 m/s^2.
CUBE_SIDE_M = 30e-3
CUBE_MASS_KG = 0.2106
C_N, M2, G = 4.52693e16, 2.0, 9.81


def test_density_of_the_paper_cube():
    # 0.2106 kg / (30 mm)^3 = 7800 kg/m^3, and it is steel's: 7750-8050 kg/m^3 for
    # carbon and stainless steels (7850 is the usual handbook value).
    rho = steel_density()
    assert rho == pytest.approx(CUBE_MASS_KG / CUBE_SIDE_M**3, rel=1e-12)
    assert rho == pytest.approx(7800.0, rel=1e-12)
    assert 7750 <= rho <= 8050
    assert natural_frequency_vs_height([0.01]).density_kg_m3 == rho


def test_the_cube_is_the_paper_body():
    sweep = natural_frequency_vs_height([CUBE_SIDE_M])
    assert sweep.mass_kg[0] == pytest.approx(CUBE_MASS_KG, rel=1e-12)
    # omega0^2 = S c_n m2 y0^(m2-1) / M with y0 = (M g / (S c_n))^(1/m2): 1485.59 Hz.
    area = CUBE_SIDE_M**2
    y0 = (CUBE_MASS_KG * G / (area * C_N)) ** (1 / M2)
    f_n0 = math.sqrt(area * C_N * M2 * y0 ** (M2 - 1) / CUBE_MASS_KG) / (2 * math.pi)
    assert sweep.f_n0_hz[0] == pytest.approx(f_n0, rel=1e-12)
    # The paper rounds f_n0 to 1485 Hz (Section 3).
    assert sweep.f_n0_hz[0] == pytest.approx(PAPER_F_N0_HZ, abs=1.0)
    assert sweep.paper_height_m == CUBE_SIDE_M == PAPER_CUBE_SIDE_M


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
    assert sweep.f_n0_hz[50] == pytest.approx(eq26_numbers(middle).f_n0_hz, rel=1e-13)


def test_round_trip_through_strict_json(tmp_path):
    sweep = natural_frequency_vs_height(points=7)
    data = sweep.as_dict()
    json.dumps(data, allow_nan=False)
    sweep.to_json(tmp_path / "fig4.json")
    back = load(tmp_path / "fig4.json")
    assert isinstance(back, HeightSweep) and back.as_dict() == data
    assert ContactModel.from_dict(back.model) == ContactModel()
    assert back.settings == {"points": 7}
    assert "\n" not in repr(sweep) and len(repr(sweep)) < 200


@pytest.mark.parametrize(
    "kwargs, name",
    [({"height_m": [0.0]}, "height_m"), ({"height_m": [np.nan]}, "height_m"),
     ({"height_m": []}, "height_m"), ({"points": 1}, "points"), ({"points": 2.5}, "points"),
     ({"parameters": ContactModel()}, "parameters")],
)
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        natural_frequency_vs_height(**kwargs)
