"""Sweeps: the paper's method, its jumps, its JSON and its figures."""

import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest

from numerics import sweep
from perturb import EQ_2_6, PAPER, ContactModel, eq26_numbers
from perturb.common import Status


def test_shooting_sweep_jumps_where_time_marching_jumps():
    # The bent primary peak at 0.05 Q (bi-stable), and at 0.15 Q the bouncing branch
    # that the down sweep follows to about 360 Hz, on the paper's 5 Hz grid.
    grid = np.arange(330.0, 1505.0, 5.0)
    fast = sweep(grid, [0.05, 0.15])
    paper = sweep(grid, [0.05, 0.15], method="march", tol=1e-8)
    for a, b in zip(fast.runs, paper.runs):
        assert a.jumps() == b.jumps(), (a.pa_frac, a.direction, a.jumps(), b.jumps())
        assert np.allclose(a.app_m, b.app_m, rtol=1e-4)
    assert all(run.jumps() for run in fast.runs)


def test_up_and_down_differ_inside_the_bistable_band():
    # Section 3.3: the bent primary peak makes the response depend on the history.
    result = sweep(np.linspace(1350.0, 1450.0, 21), [0.05])
    up, down = result.run(0.05, "up"), result.run(0.05, "down")
    assert up.jumps() and down.jumps()
    at_1400_up = up.app_m[up.frequency_hz.tolist().index(1400.0)]
    at_1400_down = down.app_m[down.frequency_hz.tolist().index(1400.0)]
    assert at_1400_down > 2 * at_1400_up


def _softer_contact() -> ContactModel:
    """m2 = 1.5, l = 0.5 with the paper's y0 and c (c_n and h_n rescaled)."""
    y0 = eq26_numbers().y0_m
    return ContactModel(dataclasses.replace(
        PAPER, m2=1.5, l=0.5, c_n=PAPER.Q_n / (PAPER.S * y0**1.5), h_n=PAPER.h_n * y0**0.5))


def _one_jump_in_the_fine_grids_step(coarse, fine) -> None:
    """Each run of ``coarse`` has one jump, in the step that holds the one of ``fine``."""
    for a, b in zip(coarse.runs, fine.runs):
        (c,), (f,) = a.jumps(), b.jumps()
        lo, hi = sorted(a.frequency_hz[[c - 1, c]])
        assert lo <= min(b.frequency_hz[[f - 1, f]]) and max(b.frequency_hz[[f - 1, f]]) <= hi


def test_a_jump_is_where_the_sweep_leaves_its_branch_on_coarse_and_fine_grids():
    # The bent primary peak at 0.05 Q: one jump each way, and the 5-point grid's jump is
    # the step that holds the 41-point grid's (1425 Hz up, 1370 Hz down). App changes by
    # more than 1.3x at every step of the coarse grid: the ratio alone said "jumps at"
    # four steps of four.
    coarse, fine = (sweep(np.linspace(1300.0, 1500.0, n), 0.05) for n in (5, 41))
    _one_jump_in_the_fine_grids_step(coarse, fine)
    assert "jumps at [1450.0] Hz" in str(coarse)


def test_a_bistable_band_narrower_than_the_grid_step_is_a_jump():
    # The softer contact at 0.05 Q is bistable over some 9 Hz near 1235 Hz (a 161-point
    # grid of that step jumps at 1239.9 Hz up and 1231.1 Hz down), inside one 64 Hz step
    # of an 11-point grid: at both ends of that step one orbit only. Each sweep of the
    # coarse grid has its jump there, found by halving the step.
    model = _softer_contact()
    f_n0 = eq26_numbers(model.parameters).f_n0_hz
    grid = np.linspace(0.7 * f_n0, 1.2 * f_n0, 11)
    coarse = sweep(grid, 0.05, model=model)
    fine = sweep(np.linspace(grid[5], grid[6], 161), 0.05, model=model)
    _one_jump_in_the_fine_grids_step(coarse, fine)


def test_a_smooth_peak_on_a_coarse_grid_has_no_jump():
    # The softer contact at 0.03 Q: App up to 201 nm, more than 1.3x between 7 of the 10
    # pairs of neighbours on an 11-point grid; on a 401-point grid no step is larger
    # than 1.3x: no fold lies anywhere.
    model = _softer_contact()
    f_n0 = eq26_numbers(model.parameters).f_n0_hz
    coarse, fine = (sweep(np.linspace(0.7 * f_n0, 1.2 * f_n0, n), 0.03, model=model)
                    for n in (11, 401))
    for run, fine_run in zip(coarse.runs, fine.runs):
        with np.errstate(divide="ignore"):
            steps = np.maximum(run.app_m[1:] / run.app_m[:-1], run.app_m[:-1] / run.app_m[1:])
        assert (steps > 1.3).sum() == 7
        assert run.jumps() == [] and run.jumped is not None and fine_run.jumps() == []
        assert np.all(np.diff(np.log(fine_run.app_m)) < np.log(1.3))
    assert "jumps at []" in str(coarse)


def test_sweep_json_has_the_documented_keys(tmp_path):
    target = tmp_path / "sweep.json"
    subprocess.run([sys.executable, "-m", "numerics", "sweep", "--pa-frac", "0.05", "0.1",
                    "--fmin", "700", "--fmax", "800", "--points", "5", "--direction", "both",
                    "--json", str(target), "--plot", str(tmp_path / "fig.png"), "--quiet"],
                   check=True, capture_output=True)
    data = json.loads(target.read_text())
    assert set(data) == {"kind", "model", "settings", "runs", "elapsed_s", "provenance"}
    assert len(data["runs"]) == 4
    run = data["runs"][1]
    landed = {"pa_frac", "direction", "frequency_hz", "app_m", "ymin_m", "ymax_m", "maxima_m",
              "minima_m", "period", "settled"}
    # Issue 9: the landed keys stay, and every point gains its status and message.
    assert landed | {"status", "message"} <= set(run)
    assert run["direction"] == "down" and run["frequency_hz"] == [800, 775, 750, 725, 700]
    assert all(len(run[k]) == 5 for k in ("app_m", "maxima_m", "period", "settled"))
    assert (tmp_path / "fig.png").exists() and (tmp_path / "fig-extrema.png").exists()


def test_progress_goes_to_stderr_unless_quiet(tmp_path):
    # stderr is a pipe here: the bar is drawn because the environment asks for it (on a
    # terminal it is drawn by default), and never with --quiet.
    import os

    command = [sys.executable, "-m", "numerics", "sweep", "--pa-frac", "0.05", "--points", "3",
               "--fmin", "700", "--fmax", "800"]
    asked = os.environ | {"CONTACT_RESONANCES_PROGRESS": "always"}
    plain = {k: v for k, v in os.environ.items() if k != "CONTACT_RESONANCES_PROGRESS"}
    loud = subprocess.run(command, check=True, capture_output=True, text=True, env=asked)
    piped = subprocess.run(command, check=True, capture_output=True, text=True, env=plain)
    quiet = subprocess.run(command + ["--quiet"], check=True, capture_output=True, text=True,
                           env=asked)
    assert "sweep:" in loud.stderr and "sweep:" not in piped.stderr and quiet.stderr == ""


def test_a_lane_that_blows_up_restarts_from_rest():
    # Regression: Eq. 2.6's quadratic spring has no floor; at 0.15 Q the down sweep's
    # state escapes to -infinity near the bent peak, and the next point used to raise
    # on a NaN initial state. It is now not settled, and the sweep goes on from rest.
    result = sweep(np.linspace(250.0, 1800.0, 156), [0.15], direction="down",
                   model=ContactModel(effects=EQ_2_6))
    run = result.runs[0]
    assert not all(run.settled)
    assert run.settled[-1] and np.isfinite(run.app_m[-1])


@pytest.mark.parametrize(
    "args, kwargs, message",
    [(([1.0, 2.0], [0.1]), {"direction": "sideways"}, "`direction`"),
     (([2.0, 1.0], [0.1]), {}, "increasing"),
     (([1.0, 2.0], [-0.1]), {}, "`pa_frac`")],
)
def test_bad_input_is_named(args, kwargs, message):
    with pytest.raises(ValueError, match=message):
        sweep(*args, **kwargs)


def test_the_bouncing_down_branch_is_an_attractor_for_an_independent_integrator(weight):
    # The down sweeps from 0.2 Q on stay on a bouncing orbit (App ~ 60 y0) far below the
    # primary peak. Route 2: scipy's DOP853 (rtol 1e-11), Eq. 2.4 typed here, started on
    # the toolkit's orbit, must stay on it: same App after 60 periods.
    from scipy.integrate import solve_ivp

    from perturb import PAPER as p

    run = sweep(np.arange(300.0, 1805.0, 5.0), [0.3], direction="down").runs[0]
    assert run.ymin_m[-1] < 0 and run.app_m[-1] > 40 * eq26_numbers().y0_m
    f, p_a, periods = 300.0, 0.3 * weight, 60

    def rhs(t, state):
        y, v = state
        contact = -p.S * p.c_n * y**p.m2 - p.S * p.h_n * y**p.l * v if y > 0 else 0.0
        return (v, (contact + p.M * p.g + p_a * np.cos(2 * np.pi * f * t)) / p.M)

    solution = solve_ivp(rhs, (0.0, periods / f), (run.y_start_m[-1], run.v_start_m_s[-1]),
                         method="DOP853", rtol=1e-11, atol=1e-18, dense_output=True,
                         max_step=1 / (400 * f))
    last = solution.sol(np.linspace((periods - 1) / f, periods / f, 20001))[0]
    assert abs(np.ptp(last) / run.app_m[-1] - 1) < 1e-3


def test_a_sweep_past_the_checked_steps_says_it_was_not_checked():
    # More candidate steps than the bound: no run is checked, each says so (jumped None)
    # and its jumps are App's ratio alone, as for a run made without the check.
    result = sweep(np.linspace(1300.0, 1500.0, 5), 0.05, max_checked_steps=1)
    for run in result.runs:
        assert run.jumped is None
        ratio = np.maximum(run.app_m[1:] / run.app_m[:-1], run.app_m[:-1] / run.app_m[1:])
        assert run.jumps() == (np.flatnonzero(ratio > 1.3) + 1).tolist()


def test_app_at_the_round_off_of_y_is_under_resolved_and_never_a_jump():
    # At 1e-14 Q App is some 1e-20 m, a few hundred units in the last place of y (about
    # y0, 2.25e-7 m): every point is under-resolved, and its noise from point to point is no
    # jump. At 1e-9 and 1e-8 Q the response is linear: App scales with P_a to 1e-6.
    result = sweep([1000.0, 1200.0, 1400.0], [1e-14, 1e-9, 1e-8], direction="up", quiet=True)
    noise, small, larger = result.runs
    assert (noise.status == Status.UNDER_RESOLVED).all() and noise.jumps() == []
    assert "max App (none settled)" in result.table()
    assert (small.status == Status.SUCCESS).all() and (larger.status == Status.SUCCESS).all()
    np.testing.assert_allclose(larger.app_m / small.app_m, 10.0, rtol=1e-6)
    assert "max App  1.9" in result.table()  # not printed as 0.0 nm
