"""The attractor census at the paper's points of multi-stability (Section 3.3)."""

import json
import subprocess
import sys

import pytest

from numerics import attractor_census


def test_primary_and_half_superharmonic_coexist_at_740_hz():
    census = attractor_census(740.0, 0.15)
    labels = [a.label for a in census.attractors]
    assert "primary" in labels and "1/2 superharmonic" in labels, census
    assert abs(sum(a.basin_fraction for a in census.attractors)
               + census.not_settled_fraction - 1) < 1e-12


def test_three_resonances_coexist_at_490_hz():
    census = attractor_census(490.0, 0.5)
    period_one = {a.label for a in census.attractors if a.period == 1}
    assert period_one == {"primary", "1/2 superharmonic", "1/3 superharmonic"}, census
    # Beyond the paper: exactly one more, a period-2 bouncing orbit with a small basin
    # (measured: App 19.9 um, basin 2.0 %; see docs/tutorial-fig2.md).
    (two,) = [a for a in census.attractors if a.period != 1]
    assert two.period == 2 and two.contact_lost, census
    assert 15e-6 < two.app_m < 25e-6 and two.basin_fraction < 0.05, census


def test_attractors_json_has_the_documented_keys(tmp_path):
    target = tmp_path / "a.json"
    subprocess.run([sys.executable, "-m", "numerics", "attractors", "--pa-frac", "0.15",
                    "--fe", "740", "--json", str(target), "--quiet"], check=True,
                   capture_output=True)
    data = json.loads(target.read_text())
    assert {"attractors", "settings", "elapsed_s", "not_settled_fraction", "lanes"} <= set(data)
    keys = {"period", "app_m", "ymin_m", "ymax_m", "basin_fraction", "contact_lost",
            "dominant_harmonic", "label", "multipliers"}
    assert all(keys <= set(a) for a in data["attractors"])
    assert [a["label"] for a in data["attractors"]] == ["1/2 superharmonic", "primary"]


def test_the_old_name_of_the_census_warns_and_gives_the_same_census():
    # `attractors()` returned a Census: it is `attractor_census()` now, and the old name
    # stays for one release as a deprecated alias.
    from numerics import attractors

    with pytest.warns(DeprecationWarning, match="attractor_census"):
        old = attractors(1000.0, 0.1, grid={"y_over_y0": [1.0], "v_over_omega0_y0": [0.0]})
    new = attractor_census(1000.0, 0.1, grid={"y_over_y0": [1.0], "v_over_omega0_y0": [0.0]})
    assert [a.as_dict() for a in old.attractors] == [a.as_dict() for a in new.attractors]
