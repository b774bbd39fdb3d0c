"""Tables out: every tabular result writes CSV (``to_csv``, ``--csv FILE``), a row a
point, the glossary's names (units in them) as the header, floats to the last bit."""

import csv
import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from numerics import attractor_census, sweep
from perturb.common import GLOSSARY, Result


def _read(path):
    with open(path, newline="", encoding="utf-8") as file:
        return list(csv.DictReader(file))


def test_a_sweep_is_one_row_per_point_with_its_run_and_units(tmp_path):
    found = sweep([1300.0, 1400.0, 1500.0], [0.05, 0.1], direction="both")
    found.to_csv(tmp_path / "sweep.csv")
    rows = _read(tmp_path / "sweep.csv")
    assert len(rows) == sum(run.status.size for run in found.runs) == 12
    assert {"run", "pa_frac", "direction", "frequency_hz", "app_m", "ymin_m", "status",
            "multipliers_0_real", "multipliers_0_imag"} <= set(rows[0])
    assert set(rows[0]) - {"run", "multipliers_0_real", "multipliers_0_imag",
                           "multipliers_1_real", "multipliers_1_imag"} <= set(GLOSSARY)
    app = np.array([float(row["app_m"]) for row in rows])
    np.testing.assert_array_equal(app, np.concatenate([run.app_m for run in found.runs]))
    assert [row["direction"] for row in rows[:3]] == ["up"] * 3


def test_a_census_is_one_row_per_attractor(tmp_path):
    census = attractor_census(740.0, 0.15)
    census.to_csv(tmp_path / "census.csv")
    rows = _read(tmp_path / "census.csv")
    assert [row["label"] for row in rows] == [a.label for a in census.attractors]
    assert [float(row["basin_fraction"]) for row in rows] == [
        a.basin_fraction for a in census.attractors]


def test_a_value_that_could_not_be_computed_is_an_empty_cell(tmp_path):
    from numerics import simulate

    run = simulate([1.0], 0.1, periods=5, steps_per_period=4)  # 1 Hz at 4 steps: it fails
    assert np.isnan(run.app_m[0]) and run.status[0] == -1
    run.to_csv(tmp_path / "run.csv")
    (row,) = _read(tmp_path / "run.csv")
    assert row["ymin_m"] == "" and row["status"] == "-1"  # NaN: not computed
    assert row["message"] == run.message[0] != ""


def test_a_result_that_is_no_table_says_so():
    @dataclasses.dataclass  # not @result: a class of this test, not of the toolkit's files
    class Note(Result):
        text: str

    with pytest.raises(ValueError, match="a Note is not a table"):
        Note(text="x").to_csv("unused.csv")


def test_the_commands_write_csv_and_refuse_stdout_for_it(tmp_path):
    done = subprocess.run([sys.executable, "-m", "numerics", "sweep", "--pa-frac", "0.05",
                           "--fmin", "1300", "--fmax", "1500", "--points", "3", "--quiet",
                           "--csv", str(tmp_path / "s.csv")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert len(_read(tmp_path / "s.csv")) == 6
    refused = subprocess.run([sys.executable, "-m", "perturb", "response", "--order", "2",
                              "--pa-frac", "0.05", "--csv", "-"], capture_output=True,
                             text=True)
    assert refused.returncode == 2 and "--csv" in refused.stderr


def test_an_atlas_is_one_row_per_cell_and_a_height_sweep_one_per_height(tmp_path):
    from numerics import atlas, natural_frequency_vs_height

    found = atlas(480.0, 500.0, 0.5, 0.5, grid=(2, 1), workers=1)
    found.to_csv(tmp_path / "atlas.csv")
    rows = _read(tmp_path / "atlas.csv")
    assert [(float(r["frequency_hz"]), int(r["attractor_count"])) for r in rows] == [
        (480.0, 4), (500.0, 4)]
    assert rows[0]["attractor_labels"].split(";") == found.attractor_labels[0][0]
    heights = natural_frequency_vs_height()
    heights.to_csv(tmp_path / "heights.csv")
    rows = _read(tmp_path / "heights.csv")
    assert [float(r["height_m"]) for r in rows] == heights.height_m.tolist()
    assert {"f_n0_hz", "mass_kg", "density_kg_m3"} <= set(rows[0])
