"""The attractor census at the paper's points of multi-stability (Section 3.3)."""

import json
import subprocess
import sys

from numerics import attractors


def test_primary_and_half_superharmonic_coexist_at_740_hz():
    census = attractors(740.0, 0.15)
    labels = [a.label for a in census.attractors]
    assert "primary" in labels and "1/2 superharmonic" in labels, census
    assert abs(sum(a.basin_fraction for a in census.attractors)
               + census.not_settled_fraction - 1) < 1e-12


def test_three_resonances_coexist_at_490_hz():
    census = attractors(490.0, 0.5)
    labels = {a.label for a in census.attractors}
    assert {"primary", "1/2 superharmonic", "1/3 superharmonic"} <= labels, census
    # Beyond the paper: a period-2 bouncing orbit with a small basin (see README).
    assert len(census.attractors) >= 3


def test_attractors_json_has_the_documented_keys(tmp_path):
    target = tmp_path / "a.json"
    subprocess.run([sys.executable, "-m", "numerics", "attractors", "--pa-frac", "0.15",
                    "--fe", "740", "--json", str(target), "--quiet"], check=True,
                   capture_output=True)
    data = json.loads(target.read_text())
    assert {"attractors", "settings", "elapsed_s"} <= set(data)
    keys = {"period", "app_m", "ymin_m", "ymax_m", "basin_fraction", "contact_lost"}
    assert all(keys <= set(a) for a in data["attractors"])
