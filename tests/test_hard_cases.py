"""Hard cases stay sound, or say clearly that they cannot (issue 10).

Each test names the defect it guards against. RuntimeWarnings are errors in the
whole suite (pyproject.toml), so none of these may print one either.
"""

import json
import subprocess
import sys

import numpy as np

from numerics import Status, attractors, sweep


def test_a_failed_point_does_not_poison_the_sweep():
    # Regression: at 1 Hz the default step makes omega0*dt far too large; the lane
    # diverged to a huge but finite state, the next point started from it, and every
    # later point came back NaN and "not settled".
    alone = sweep(np.array([300.0, 310.0, 320.0]), 0.1, direction="up").runs[0]
    after = sweep(np.array([1.0, 300.0, 310.0, 320.0]), 0.1, direction="up").runs[0]
    assert after.status.tolist() == [Status.FAILED, 0, 0, 0]
    assert "omega0*dt" in after.message[0] and "raise steps_per_period" in after.message[0]
    assert np.array_equal(after.app_m[1:], alone.app_m)


def test_the_sweep_json_says_which_point_failed(tmp_path):
    target = tmp_path / "s.json"
    subprocess.run([sys.executable, "-m", "numerics", "sweep", "--pa-frac", "0.1", "--fmin", "1",
                    "--fmax", "301", "--points", "2", "--direction", "up", "--json", str(target),
                    "--quiet"], check=True, capture_output=True)
    run = json.loads(target.read_text())["runs"][0]  # json.loads rejects bare NaN tokens
    assert run["status"] == [-1, 0] and run["app_m"][0] is None and run["settled"] == [False, True]


def test_the_census_counts_rest_once():
    # Regression: at P_a = 0 the census listed 39 copies of the rest state, each with
    # its own "superharmonic" label read from round-off.
    census = attractors(1000.0, 0.0)
    assert [a.label for a in census.attractors] == ["rest"]
    assert census.attractors[0].basin_fraction == 1.0


def test_a_tiny_force_gives_one_primary_response():
    census = attractors(1000.0, 1e-6)
    assert [a.label for a in census.attractors] == ["primary"]
