"""Continuation of periodic orbits in f_e, with stability (issue 13, items 1, 2, 7).

Two independent routes to the same orbits: the sweeps (time marching and Newton, the
paper's method, which see only stable orbits) and the series of Eq. 2.6 (which see
the unstable middle root too) against the continued branch.
"""

import json
import subprocess
import sys
from functools import partial as _partial

import numpy as np
import pytest

from numerics import continue_orbits, simulate, sweep
from perturb import EQ_2_6, PAPER, ContactModel, eq26_numbers, frequency_response
from perturb.common import Status, load

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")


@pytest.fixture(scope="module")
def primary_005():
    return continue_orbits(0.05, 1300.0, 1600.0)


@pytest.fixture(scope="module")
def band_005():
    return continue_orbits(0.05, 250.0, 1800.0)


@pytest.fixture(scope="module")
def branch_015():
    return continue_orbits(0.15, 250.0, 1800.0)


def _app_at(branch, f_hz, *, stable_only):
    """App of the branch where it crosses f_hz, by linear interpolation on each segment
    that brackets it (both ends stable, with ``stable_only``)."""
    f, app, stable = branch.frequency_hz, branch.app_m, branch.stable
    lo, hi = f[:-1], f[1:]
    inside = (np.minimum(lo, hi) <= f_hz) & (f_hz <= np.maximum(lo, hi))
    if stable_only:
        inside &= stable[:-1] & stable[1:]
    out = []
    for k in np.flatnonzero(inside):
        share = 0.0 if hi[k] == lo[k] else (f_hz - lo[k]) / (hi[k] - lo[k])
        out.append(app[k] + share * (app[k + 1] - app[k]))
    return np.array(out)


def _worst_mismatch(continuation, run, *, skip=lambda f: False):
    """The largest relative distance of a settled sweep state to the nearest stable
    continued App at its f_e, and the frequencies with no stable branch there."""
    worst, missing = 0.0, []
    for f, app in zip(run.frequency_hz, run.app_m):
        if skip(f):
            continue
        near = np.concatenate([_app_at(b, f, stable_only=True) for b in continuation.branches])
        if not near.size:
            missing.append(float(f))
            continue
        worst = max(worst, float(np.min(np.abs(near - app)) / app))
    return worst, missing


def test_the_folds_at_005q_are_where_the_sweeps_jump(primary_005):
    # Measured: folds at 1420.39 and 1372.97 Hz; a 1 Hz sweep jumps up between 1420
    # and 1421 Hz and down between 1373 and 1372 Hz: each fold within its grid step.
    folds = sorted(b.frequency_hz for b in primary_005.folds())
    assert len(folds) == 2, primary_005
    grid = np.arange(1300.0, 1600.5, 1.0)
    runs = sweep(grid, 0.05)
    up, down = runs.run(0.05, "up"), runs.run(0.05, "down")
    (jump_up,), (jump_down,) = up.jumps(), down.jumps()
    assert up.frequency_hz[jump_up - 1] <= folds[1] <= up.frequency_hz[jump_up], folds
    assert down.frequency_hz[jump_down] <= folds[0] <= down.frequency_hz[jump_down - 1], folds


def test_every_stable_sweep_state_at_005q_lies_on_a_stable_branch(band_005):
    # Measured: at most 0.34 % (ds_max = 0.02: linear interpolation between branch
    # points 30 Hz apart far from the peak); the sweep's own App tolerance is 0.5 %.
    runs = sweep(np.arange(250.0, 1800.5, 5.0), 0.05)
    for run in runs.runs:
        assert run.settled.all()
        worst, missing = _worst_mismatch(band_005, run)
        assert not missing, (run.direction, missing)
        assert worst < 5e-3, (run.direction, worst)


def test_the_015q_branch_passes_the_bouncing_fold_and_holds_every_stable_sweep_state(
        monkeypatch):
    # At 512 steps, each contact switch located within its step, the walk up goes through
    # the fold at 1332.8 Hz, back along the middle branch of bouncing orbits, and through
    # the bouncing fold at 352.4 Hz: one branch, no walk again at 1024 steps (without the
    # events the 512-step walk stopped at a corner of the piecewise smooth map, and
    # "auto" walked again at 1024 steps).
    # The 5 Hz sweep down (at its own, coarser N) jumps off that branch at 355 Hz: the
    # fold within one grid step of the jump. Every settled sweep state lies on a stable
    # continued branch (the sweep's App tolerance is 0.5 %).
    from numerics.continuation import walk as walk_module

    made, band_walk = [], walk_module._band_walk
    monkeypatch.setattr(walk_module, "_band_walk", lambda shoot, *args: made.append(
        (shoot.steps, args[-1])) or band_walk(shoot, *args))
    run = continue_orbits(0.15, 250.0, 1800.0)
    assert run.settings["steps_per_period"] == 512
    assert made == [(512, 1)]
    (branch,) = run.branches
    assert branch.status == Status.SUCCESS
    assert [round(b.frequency_hz) for b in run.folds()] == [1333, 352]
    # Both folds are located by Brent's method to its xtol, LOCATE_TOL in z: 1e-8 f_n0
    # (1.4856e-5 Hz); the bouncing one's frequency on the maps of 512 and 2048 steps:
    # tests/test_events.py.
    from numerics.continuation.walk import LOCATE_TOL

    f_n0 = eq26_numbers().f_n0_hz
    assert [b.located for b in run.folds()] == [True, True]
    assert all(b.frequency_tol_hz == pytest.approx(LOCATE_TOL * f_n0, rel=5e-8)
               for b in run.folds())
    runs = sweep(np.arange(250.0, 1800.5, 5.0), 0.15)
    down = runs.run(0.15, "down")
    jumps = [float(down.frequency_hz[j]) for j in down.jumps()]
    assert any(abs(f - run.folds()[1].frequency_hz) <= 5.0 for f in jumps), jumps
    for sweep_run in runs.runs:
        worst, missing = _worst_mismatch(run, sweep_run)
        assert not missing, (sweep_run.direction, missing)
        assert worst < 2e-3, (sweep_run.direction, worst)


def test_near_the_bouncing_fold_the_walk_gives_up_stalled_newtons_and_creeping_steps():
    # Regression, for the continuation's speed goal. Near the bouncing fold at 0.15 Q the map's
    # corners made Newton stall (all 12 iterations and their line searches, then a failed
    # step) and the steps creep towards corners where the branch turns back, ever shorter,
    # down to 1e-9. The contraction test (WalkOptions.contraction) and the stall
    # hand-over to a step in f alone (WalkOptions.stall_ds) took the Python walk at
    # N = 1024 from 37,603 evaluations of R to 17,629, with the same folds; with the
    # shrink by the turn (WalkOptions.turn_share), 35,132 without them and 17,409 with
    # them; with Newton's stop by estimate (period_map.near_enough) and steps past
    # ds_max on the bouncing arcs (walk.largest_step), 9,822; with the corner's
    # step grown with the orbit's size as the largest step is (walk.corner_step)
    # and a step that fails below it shrunk by 4 (WalkOptions.corner_shrink), 6,553;
    # with each contact switch located within its step (a map smooth between switches,
    # with no corners), 2,584 (measured).
    from unittest import mock

    from numerics.continuation.period_map import PeriodMap

    with mock.patch.object(PeriodMap, "residual", autospec=True,
                           side_effect=PeriodMap.residual) as spy:
        run = continue_orbits(0.15, 250.0, 1800.0, steps_per_period=1024, engine="python")
    assert [round(b.frequency_hz, 2) for b in run.folds()] == [1332.84, 352.42]
    assert run.branches[0].status == Status.SUCCESS
    assert spy.call_count <= 2_720  # measured 2,584: 5 % more is seen


def test_newtons_stop_by_estimate_keeps_the_walk_on_the_branch():
    # The walk's arclength steps stop Newton once the steps still to come, at the rate of
    # the last two, add up to less than newton_tol (period_map.near_enough): that
    # saves the evaluation of R which would only show the next step below it. Route 2, the
    # exact test alone: at 0.05 Q the same 120 points, stability and folds (measured
    # within 1.8e-12 Hz; the points themselves lie up to 6e-8 apart along the branch, as
    # the tangents, taken a step before the root, steer the steps), 388 evaluations of R
    # against 347 (Python walk).
    from unittest import mock

    from numerics.continuation import WalkOptions
    from numerics.continuation.period_map import PeriodMap

    runs, calls = {}, {}
    for estimated in (True, False):
        with mock.patch.object(PeriodMap, "residual", autospec=True,
                               side_effect=PeriodMap.residual) as spy:
            runs[estimated] = continue_orbits(0.05, 1300.0, 1600.0, engine="python",
                                              options=WalkOptions(stop_by_estimate=estimated))
        calls[estimated] = spy.call_count
    (a,), (b,) = runs[True].branches, runs[False].branches
    assert a.frequency_hz.size == b.frequency_hz.size == 120
    assert np.array_equal(a.stable, b.stable)
    for x, y in zip(runs[True].bifurcations, runs[False].bifurcations, strict=True):
        assert x.kind == y.kind and abs(x.frequency_hz - y.frequency_hz) < 1e-11
    assert calls[True] < 0.95 * calls[False], calls  # measured 347 against 388


def test_every_point_of_the_015q_branch_is_a_root_of_the_shooting_residual(branch_015):
    # Newton's stop by estimate (near_enough) leaves each point as near the root as the
    # exact test did: |R| in z at most 4.9e-13 over the 1971 points (measured; 5.5e-13
    # over the 2493 points before ``corner_step``, 6.0e-13
    # with the exact test alone, the round-off of one period of RK4 being some 1e-13).
    from numerics.continuation.period_map import PeriodMap

    model = ContactModel()
    shoot = PeriodMap(model, 0.15 * model.parameters.Q_n,
                      branch_015.settings["steps_per_period"], 1)
    (branch,) = branch_015.branches
    z = np.column_stack([branch.y_start_m, branch.v_start_m_s, branch.frequency_hz])
    residuals = [np.abs(shoot.residual(point)[0]).max() for point in z / shoot.scale]
    assert max(residuals) < 2e-12, max(residuals)


def test_steps_grow_past_ds_max_only_where_large_orbits_run_straight(branch_015, band_005):
    # walk.largest_step: where the tangent turns little, a step may be ds_max
    # times the orbit's size |(y, v)| in z over 2 (a bouncing orbit), up to 20 ds_max.
    # Measured: at 0.15 Q the longest step, 0.23 in z (11.5 ds_max), on an orbit of
    # |(y, v)| = 25; at 0.05 Q, where every orbit stays in contact, none past ds_max (a
    # chord is at most 0.13 % longer than its step along the tangent).
    y0, omega0 = eq26_numbers().y0_m, eq26_numbers().omega0_rad_s
    ds_max = branch_015.settings["ds_max"]
    longest = {}
    for run in (branch_015, band_005):
        (branch,) = run.branches
        z = np.column_stack([branch.y_start_m / y0, branch.v_start_m_s / (omega0 * y0)])
        chords = np.linalg.norm(np.diff(np.column_stack(
            [z, branch.frequency_hz / eq26_numbers().f_n0_hz]), axis=0), axis=1)
        size = np.hypot(z[:-1, 0], z[:-1, 1])
        assert (chords <= 1.01 * ds_max * np.clip(size / 2, 1.0, 20.0)).all()
        longest[run.pa_frac] = chords.max() / ds_max
    assert longest[0.15] > 10 and longest[0.05] < 1.01, longest


def test_the_middle_branch_is_unstable_and_an_orbit_on_it_really_leaves(primary_005):
    branch = primary_005.branches[0]
    folds = sorted(b.frequency_hz for b in primary_005.folds())
    between = (branch.frequency_hz > folds[0] + 5) & (branch.frequency_hz < folds[1] - 5)
    apps = branch.app_m[between]
    # Three orbits in the bent region: the unstable one has the middle App.
    middle = ~branch.stable[between]
    assert middle.any() and branch.stable[between].any()
    assert (np.abs(branch.multipliers[between][middle]).max(axis=1) > 1).all()
    i = np.flatnonzero(between)[np.flatnonzero(middle)[len(np.flatnonzero(middle)) // 2]]
    f, app = branch.frequency_hz[i], branch.app_m[i]
    steps = primary_005.settings["steps_per_period"]
    p_a = 0.05 * PAPER.Q_n
    # Unperturbed, it stays while its start's error (Newton's, some 1e-10 of y0) grows
    # by less than 1e5: ln(1e5) / ln|mu| periods. (Over 3000 periods, round-off alone
    # took it away or not, as the last bits of the branch's first point fell.)
    growth = np.abs(branch.multipliers[i]).max()
    calm = int(np.log(1e5) / np.log(growth))
    stays = simulate(f, p_a, periods=calm, steps_per_period=steps, y_init_m=branch.y_start_m[i],
                     v_init_m_s=branch.v_start_m_s[i]).app_m[0]
    assert abs(stays - app) / app < 1e-3, "the unperturbed orbit must stay (a fixed point)"
    # Slightly perturbed (1e-6 of App), 3000 periods (some 30 e-foldings of the
    # measured largest multiplier 1.01-1.1): it goes to one of the stable orbits.
    kick = 1e-6 * app
    runs = simulate([f, f], p_a, periods=3000, steps_per_period=steps,
                    y_init_m=branch.y_start_m[i] + np.array([kick, -kick]),
                    v_init_m_s=branch.v_start_m_s[i])
    stable_apps = _app_at(branch, f, stable_only=True)
    for left in runs.app_m:
        assert abs(left - app) / app > 0.1, (left, app)
        assert np.min(np.abs(stable_apps - left)) / left < 5e-3, (left, stable_apps)
    assert {bool(a > app) for a in runs.app_m} == {True, False}
    assert apps.size


def _crossings(f_branch, f):
    """How many times the branch passes f (a point exactly at f counted once)."""
    lo, hi = f_branch[:-1], f_branch[1:]
    return int(np.sum((np.minimum(lo, hi) <= f) & (f <= np.maximum(lo, hi)))
               - np.sum(f_branch[1:-1] == f))


@pytest.mark.parametrize("pa_frac", [0.03, 0.05])
def test_on_eq_26_the_branch_is_the_series_response(pa_frac):
    # Measured: App within the series' error estimate + 1.0e-8 (RK4 at N = 512) at every
    # point where the series has a valid root of every crossing (93 of 111 points at
    # 0.05 Q: near the upper fold, 1394 Hz, the series' roots are not valid); the
    # middle root (the series' branch 1) is the unstable part, 24 points at 0.05 Q.
    run = continue_orbits(pa_frac, 1300.0, 1600.0, model=ContactModel(effects=EQ_2_6))
    branch = run.branches[0]
    series = frequency_response(np.unique(branch.frequency_hz), pa_frac)
    compared = middle = 0
    for f, app, stable in zip(branch.frequency_hz, branch.app_m, branch.stable):
        roots = [(abs(b.app_m[k] - app) / app, b.error_estimate[k], j)
                 for j, b in enumerate(series.branches)
                 for k in np.flatnonzero((b.frequency_hz == f) & b.valid)]
        if len(roots) < _crossings(branch.frequency_hz, f):
            continue
        distance, estimate, j = min(roots)
        assert distance <= estimate + 1e-7, (f, distance, estimate)
        assert stable == (j != 1), (f, stable, j)
        compared += 1
        middle += j == 1
    assert compared > 0.8 * branch.frequency_hz.size
    assert (middle > 10) == (pa_frac == 0.05), middle


def test_json_reads_back(primary_005, tmp_path):
    path = tmp_path / "c.json"
    primary_005.to_json(path)
    data = json.loads(path.read_text())
    assert set(data) >= {"branches", "bifurcations", "elapsed_s"}
    assert set(data["branches"][0]) >= {"frequency_hz", "app_m", "stable", "period",
                                        "multipliers"}
    assert {b["kind"] for b in data["bifurcations"]} == {"fold"}
    assert set(data["bifurcations"][0]) >= {"kind", "frequency_hz", "app_m", "pa_frac",
                                            "located", "frequency_tol_hz", "pa_frac_tol"}
    assert [b["located"] for b in data["bifurcations"]] == [True, True]
    back = load(path)
    assert all(isinstance(b.located, bool) for b in back.bifurcations)
    assert json.dumps(back.as_dict(), allow_nan=False) == json.dumps(primary_005.as_dict(),
                                                                    allow_nan=False)
    assert back.branches[0].stable.dtype == bool


def test_a_file_saved_before_the_bifurcations_precision_loads(primary_005, tmp_path):
    # Regression (review): files written before d3a1ac9 have no located, frequency_tol_hz
    # or pa_frac_tol, and no longer loaded. They load with the precision unknown (None,
    # NaN: those files also held bifurcations only marked, not told apart).
    data = primary_005.as_dict()
    for fold in data["bifurcations"]:
        for key in ("located", "frequency_tol_hz", "pa_frac_tol"):
            del fold[key]
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    back = load(path)
    assert [b.frequency_hz for b in back.bifurcations] == [
        b.frequency_hz for b in primary_005.bifurcations]
    for fold in back.bifurcations:
        assert fold.located is None
        assert np.isnan(fold.frequency_tol_hz) and np.isnan(fold.pa_frac_tol)
        assert fold.precision() == "precision unknown (saved before it was recorded)"
    assert "precision unknown" in str(back)
    # Saved again, the unknowns are null in strict JSON, and read back the same.
    back.to_json(tmp_path / "again.json")
    again = json.loads((tmp_path / "again.json").read_text())["bifurcations"][0]
    assert (again["located"], again["frequency_tol_hz"], again["pa_frac_tol"]) == (
        None, None, None)
    assert load(tmp_path / "again.json").bifurcations[0].located is None


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="fmax_hz"):
        continue_orbits(0.05, 1600.0, 1300.0)
    with pytest.raises(ValueError, match="period"):
        continue_orbits(0.05, 1300.0, 1600.0, period=9)
    with pytest.raises(ValueError, match="`max_points` must be an integer <= 250000"):
        continue_orbits(0.05, 1300.0, 1600.0, max_points=250_001)


def test_a_walk_at_its_most_points_stays_near_a_fifth_of_a_gigabyte(monkeypatch):
    # What the walks of a whole run hold per point they keep (their points, tangents and
    # the result), measured on the paper's branch at 0.15 Q: 825 bytes (1,884 when each
    # point was a view into its 256-row chunk, which kept the whole chunk alive).
    import gc
    import tracemalloc

    from numerics.continuation import walk as walk_module
    from numerics.continuation.walk import MAX_WALK_POINTS

    walks, init = [], walk_module.Walk.__init__

    def keep(self, *args, **kwargs):
        init(self, *args, **kwargs)
        walks.append(self)

    monkeypatch.setattr(walk_module.Walk, "__init__", keep)
    continue_orbits(0.15, 250.0, 1800.0)  # the kernels loaded before the count
    walks.clear()
    gc.collect()
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    run = continue_orbits(0.15, 250.0, 1800.0)
    gc.collect()
    held = tracemalloc.get_traced_memory()[0] - before
    tracemalloc.stop()
    per_point = held / sum(len(walk.points) for walk in walks)
    assert run.branches and 300 < per_point < 1000, per_point
    assert per_point * MAX_WALK_POINTS < 0.25e9


def test_the_command_line(tmp_path):
    out = tmp_path / "c.json"
    done = subprocess.run([sys.executable, "-m", "numerics", "continue", "--pa-frac", "0.05",
                           "--fmin", "1350", "--fmax", "1450", "--json", str(out), "--quiet"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "Continuation" in done.stdout and "fold" in done.stdout
    data = json.loads(out.read_text())
    assert data["branches"][0]["status"] == Status.SUCCESS
    bad = subprocess.run([sys.executable, "-m", "numerics", "continue", "--pa-frac", "0.05",
                          "--fmin", "1450", "--fmax", "1350"], capture_output=True, text=True)
    assert bad.returncode == 2
    assert bad.stderr.strip().splitlines()[-1].startswith("python -m numerics continue: error:")


def test_the_down_walks_marks_stay_on_its_own_branch():
    # Regression (review): when the walks up and down did not meet, the down walk's marks
    # were indexed as if joined (off by the up walk's length), so a period doubling
    # pointed into the other branch or past the end.
    from types import SimpleNamespace

    from numerics.continuation.walk import Mark, join_walks

    def walk(f0, df, n, marks, sign):
        return SimpleNamespace(points=[SimpleNamespace(z=np.array([0.0, 0.0, f0 + df * i]))
                                       for i in range(n)], marks=marks, status=Status.FAILED,
                               message="", tangents=[np.array([0.0, 0.0, sign])] * n)

    fold, doubling = Mark(4, "fold", True, 1e-8), Mark(3, "period-doubling", False, 0.01)
    up, down = walk(0.2, 0.01, 10, [fold], 1.0), walk(1.2, -0.01, 5, [doubling], -1.0)
    branches = join_walks([up, down])
    assert [(len(points), marks) for points, marks, *_ in branches] == [
        (10, [fold]), (5, [doubling._replace(index=1)])]  # point 3 of 5, reversed: 1


def test_no_orbit_to_start_from_is_said_not_dropped():
    # Regression (review): a walk with no point was dropped with its message, and the
    # command printed "0 branch(es)" and exited 0. At 0.05 Q there is no stable period-2
    # orbit at either end of 1300-1600 Hz: both walks say so, and the command exits 1.
    run = continue_orbits(0.05, 1300.0, 1600.0, period=2, quiet=True)
    assert [b.frequency_hz.size for b in run.branches] == [0, 0]
    assert all("no stable 2-periodic orbit" in b.message for b in run.branches)


def test_a_band_beyond_the_models_reach_is_refused_before_any_work():
    # Regression (review): --fmin 1e-300 --fmax 1e300 ran, printed RuntimeWarnings and a
    # meaningless one-point branch.
    with pytest.raises(ValueError, match="must lie within 0.149-1.49e"):
        continue_orbits(0.05, 1e-300, 1e300)
    done = subprocess.run([sys.executable, "-m", "numerics", "continue", "--pa-frac", "0.05",
                           "--fmin", "1e-300", "--fmax", "1e300", "--quiet"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "Warning" not in done.stderr


def test_the_command_draws_the_series_stability_over_the_continued_eq26_branch(tmp_path,
                                                                              capsys):
    # Issue 13 item 3: "the comparison shows the series' unstable branch against the
    # continued unstable branch of RK4". --series N continues Eq. 2.6 (the series' model)
    # and draws the series' roots, with their stability, over it. At 0.05 Q the middle
    # root of the bent peak is unstable (40 of its 41 roots on this grid; one unknown).
    from numerics.cli import main

    plot = tmp_path / "series.png"
    assert main(["continue", "--pa-frac", "0.05", "--fmin", "1300", "--fmax", "1500",
                 "--series", "6", "--truncation", "paper", "--quiet", "--plot", str(plot),
                 "--json", str(tmp_path / "c.json")]) == 0
    assert load(tmp_path / "c-series.json").order == 6  # the series' stability, beside
    printed = capsys.readouterr().out
    assert "fold              1394.0" in printed  # Eq. 2.6's fold, not the full model's
    middle = next(line for line in printed.splitlines() if "branch 1:" in line)
    assert " 0 stable" in middle and int(middle.split(" unstable")[0].split()[-1]) >= 30
    assert plot.stat().st_size > 10_000


def test_the_series_over_an_empty_branch_is_drawn_not_raised(tmp_path):
    # Regression (review): with --series and --plot, a walk with no orbit to start from
    # (period 2 at 0.05 Q) raised IndexError in the figure; it exits 1 with the message.
    done = subprocess.run([sys.executable, "-m", "numerics", "continue", "--pa-frac", "0.05",
                           "--fmin", "1300", "--fmax", "1600", "--period", "2", "--series",
                           "2", "--truncation", "paper", "--quiet", "--plot",
                           str(tmp_path / "p.png")],
                          capture_output=True, text=True)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert "no stable 2-periodic orbit" in done.stdout


def test_a_period_doubling_is_where_time_marching_first_shows_period_2(doubling_125):
    # Issue 13: a period doubling found by continuation agrees with where time marching
    # first shows a period-2 orbit. At 1.25 Q the bouncing period-1 orbit doubles near
    # 1557 Hz (a 5 Hz sweep shows period 2 from 775 to 1555 Hz). steady_states runs the
    # same map (the branch's N steps per period, no refinement) down a 0.5 Hz grid from
    # the continued orbit at 1560 Hz, each point from the last (review: from rest, at 512
    # steps and more, a march reaches a coexisting period-4 orbit instead). Below the
    # doubling Newton's orbit is unstable and the march finds the period-2 one. (A march
    # alone, method="march", takes the alternating transient of a multiplier near -1 for
    # period 2 already at 1561 Hz: it repeats after two periods within tol first.)
    from numerics import steady_states

    run, doubling = doubling_125
    steps = run.settings["steps_per_period"]
    (branch,) = [b for b in run.branches if b.frequency_hz.size]
    top = np.argmin(np.abs(branch.frequency_hz - 1560.0))
    y, v = branch.y_start_m[top], branch.v_start_m_s[top]
    grid = np.arange(round(float(branch.frequency_hz[top]) * 2) / 2, 1553.99, -0.5)
    periods = []  # 0: not settled
    for f in grid:
        found = steady_states(f, 1.25 * PAPER.Q_n, steps_per_period=steps, refinements=0,
                              app_rtol=None, y_init_m=y, v_init_m_s=v)
        periods.append(int(found.period[0]) if found.settled[0] else 0)
        if found.settled[0]:
            y, v = found.y_start_m[0], found.v_start_m_s[0]
    periods = np.array(periods)
    last_single, first_double = np.flatnonzero(periods == 1)[-1], np.flatnonzero(periods == 2)[0]
    assert (periods[:last_single + 1] == 1).all() and (periods[first_double:] == 2).all()
    # In between, the orbits converge more slowly than the settling cap (multipliers
    # within 0.01 of -1 above the doubling, of +1 below): measured 1557.5-1556.0 Hz, not
    # settled, as said. (1557.5 Hz settled as period 1 before the march took a p-periodic
    # orbit only where its divisors' lag differences are clearly not zero.)
    assert (periods[last_single + 1:first_double] == 0).all()
    above, below = grid[last_single], grid[first_double]
    assert above - below <= 2.5  # measured: 1558.0 and 1555.5 Hz
    # Measured: 1556.68 Hz at 512 steps, the doubling of the map at these steps; at 1024
    # steps within 1e-5 Hz of it (test_the_doubling_hardly_moves_with_the_step).
    assert below < doubling.frequency_hz < above, (below, doubling.frequency_hz, above)
    # The branch is stable above the doubling and unstable below it (a multiplier past -1).
    above_it = branch.frequency_hz > doubling.frequency_hz
    well_below = branch.frequency_hz < doubling.frequency_hz - 1.0
    assert above_it.any() and well_below.any()
    assert branch.stable[above_it].all() and not branch.stable[well_below].any()


def test_the_doubling_hardly_moves_with_the_step(doubling_125):
    # A bifurcation is that of the RK4 map at the branch's steps per period. With the
    # contact's switches located within the step that map converges at order four
    # through loss of contact, and the doubling at 1024 steps lies 1.1e-6 Hz from the
    # one at 512 (measured; where the steps went straight over y = 0: 0.54 Hz).
    _, doubling = doubling_125
    finer = continue_orbits(1.25, 1540.0, 1600.0, steps_per_period=1024)
    (at_1024,) = [b for b in finer.bifurcations if b.kind == "period-doubling"]
    assert abs(at_1024.frequency_hz - doubling.frequency_hz) < 1e-5


@pytest.fixture(scope="module")
def doubling_125():
    run = continue_orbits(1.25, 1500.0, 1700.0)
    (doubling,) = [b for b in run.bifurcations if b.kind == "period-doubling"]
    return run, doubling


def test_the_switched_branch_is_the_period_2_orbit_that_marching_reaches(doubling_125):
    # A branch can be switched onto the period-doubled branch. It starts
    # at the doubling, and each of its stable orbits, perturbed by 1 % of App, is where a
    # march at the same steps returns to (two routes: shooting and time marching).
    from numerics import steady_states, switch_branch

    run, doubling = doubling_125
    doubled = switch_branch(run, doubling)
    (branch,) = doubled.branches
    assert branch.period == 2 and doubled.settings["switched_at_hz"] == [doubling.frequency_hz]
    assert abs(branch.frequency_hz[0] - doubling.frequency_hz) < 1e-5  # measured: 6.4e-7 Hz
    # No fold on it: the map has no corners between the switches (without the switches
    # located, two folds 0.2 Hz apart were reported within 0.7 Hz of the doubling).
    assert not doubled.bifurcations
    assert branch.frequency_hz.min() == 1500.0  # walked down to the band's end
    # (Nearer the doubling a multiplier nears 1 and marching takes longer than its cap.)
    # (Every second point: with the contact switches located within the step the walk
    # takes longer steps, and every fourth gave 4.)
    check = np.flatnonzero(branch.stable & (branch.frequency_hz < 1555.0))[::2]
    assert check.size >= 5
    nudge = 0.01 * branch.app_m[check]
    marched = steady_states(branch.frequency_hz[check], 1.25 * PAPER.Q_n, method="march",
                            steps_per_period=run.settings["steps_per_period"],
                            refinements=0, app_rtol=None, tol=1e-9,
                            y_init_m=branch.y_start_m[check] + nudge,
                            v_init_m_s=branch.v_start_m_s[check])
    assert marched.settled.all() and (marched.period == 2).all()
    error = np.abs(marched.app_m / branch.app_m[check] - 1)
    assert error.max() < 1e-8, error.max()  # measured 1.5e-9: the march's tol is 1e-9


def test_only_a_period_doubling_of_the_run_is_switched_at(doubling_125, primary_005):
    from numerics import switch_branch

    run, doubling = doubling_125
    with pytest.raises(ValueError, match="`bifurcation` must be one of `run.bifurcations`"):
        switch_branch(run, primary_005.bifurcations[0])
    with pytest.raises(ValueError, match="`run` must be a Continuation"):
        switch_branch(doubling, doubling)


def test_the_command_line_switches_at_each_period_doubling(tmp_path, doubling_125):
    out = tmp_path / "c.json"
    done = subprocess.run([sys.executable, "-m", "numerics", "continue", "--pa-frac", "1.25",
                           "--fmin", "1500", "--fmax", "1700", "--switch", "--json", str(out),
                           "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    data = json.loads(out.read_text())
    assert [b["period"] for b in data["branches"] if b["frequency_hz"]] == [1, 2]
    assert data["settings"]["switched_at_hz"] == [doubling_125[1].frequency_hz]


def test_fig_2_redrawn_from_continued_branches(primary_005, band_005, tmp_path):
    # Issue 13, item 2: Fig. 2 with stable branches solid and unstable dashed, one panel
    # per amplitude (make figures draws the ten; two here).
    from numerics.plots import plot_continued_app

    figure = plot_continued_app([band_005, primary_005], tmp_path / "fig2.png")
    axes = [ax for ax in figure.axes if ax.get_visible()]
    assert len(axes) == 2 and (tmp_path / "fig2.png").stat().st_size > 0
    styles = {line.get_linestyle() for line in axes[0].get_lines()}
    assert {"-", "--"} <= styles  # the middle branch of the bent peak is unstable


def test_continued_in_force_the_folds_are_where_continuation_in_f_folds():
    # Issue 13, item 2: continuation in P_a at one f_e. At 1400 Hz, inside the bistable
    # band of the primary peak at 0.05 Q, the force-response curve folds twice; at each
    # fold's P_a, continuation in f_e has a fold at 1400 Hz (two routes: measured within
    # 1.1e-12 and 4.3e-12 Hz. The allowance, 2e-11 Hz, is round-off (as the fold curves'
    # FOLD_F_RTOL, 2e-14 of f_e), far inside the stated 1.5e-5 Hz: at a fold the
    # parameter is stationary along the branch, so Brent's xtol of 1e-8 in the arclength
    # moves it by its square).
    from numerics import continue_in_force

    run = continue_in_force(1400.0, 0.02, 0.08)
    assert [b.kind for b in run.bifurcations] == ["fold", "fold"]
    up, down = sorted(b.pa_frac for b in run.bifurcations)[::-1]
    assert 0.04 < down < 0.05 < up < 0.07  # measured: 0.0456 and 0.0695 Q
    # Located in P_a by Brent's method, to 1e-8 in z = P_a / Q; f_e was held.
    for fold in run.bifurcations:
        assert fold.located and fold.frequency_tol_hz == 0.0
        assert fold.pa_frac_tol == pytest.approx(1e-8, rel=1e-6)  # round-off of P_a / Q
    for fold in run.bifurcations:
        in_f = continue_orbits(fold.pa_frac, 1300.0, 1500.0)
        gaps = [abs(b.frequency_hz - 1400.0) for b in in_f.folds()]
        assert min(gaps) < 2e-11, gaps
    (branch,) = run.branches
    assert (branch.frequency_hz == 1400.0).all() and branch.pa_frac[0] == 0.02
    middle = (branch.pa_frac > down + 1e-3) & (branch.pa_frac < up - 1e-3)
    assert (~branch.stable[middle]).sum() > 0  # the middle branch, between the folds


def test_continuation_in_force_refuses_bad_input():
    from numerics import continue_in_force

    with pytest.raises(ValueError, match="`pa_max` must be above `pa_min`"):
        continue_in_force(1400.0, 0.08, 0.02)
    with pytest.raises(ValueError, match="`frequency_hz` must lie within"):
        continue_in_force(1e7, 0.02, 0.08)
    with pytest.raises(ValueError, match="`pa_min`"):
        continue_in_force(1400.0, -0.1, 0.08)


def test_a_period_2_start_from_rest_continues_the_orbit_born_at_the_doubling(doubling_125):
    # A period-p start (period=2) from rest, where a period-2 branch exists. At
    # 1.25 Q, below the doubling (1556.68 Hz at 512 steps), the period-2 orbit coexists with a
    # period-4 one (App 2.4 um at 1500 Hz): from rest, a march at the branch's N reaches
    # the period-4 orbit at 1500 Hz and the period-2 one at 1550 Hz. So the walk up has no
    # start, which its (empty) branch says, and the walk down from 1550 Hz covers the
    # band. Two routes: it is the branch switched onto at the doubling, one period apart
    # in phase.
    from numerics import switch_branch

    run = continue_orbits(1.25, 1500.0, 1550.0, period=2)
    walked = [b for b in run.branches if b.frequency_hz.size]
    assert len(walked) == 1
    (branch,) = walked
    assert branch.period == 2 and branch.status == Status.SUCCESS and branch.stable.all()
    assert branch.frequency_hz.min() == 1500.0 and branch.frequency_hz.max() == 1550.0
    for empty in (b for b in run.branches if not b.frequency_hz.size):
        assert "no stable 2-periodic orbit reached from rest at f_e = 1500 Hz" in empty.message
    (switched,) = switch_branch(*doubling_125).branches
    here, there = np.argmin(branch.frequency_hz), np.argmin(switched.frequency_hz)
    assert branch.frequency_hz[here] == switched.frequency_hz[there] == 1500.0
    # Measured 1.8e-15 (App) and 1.5e-13 (multipliers); the allowance: both are Newton's
    # orbit, each to 1e-10 y0 (y0 / App = 0.3 here), so they may differ by some 1e-10.
    assert abs(branch.app_m[here] / switched.app_m[there] - 1) < 1e-9
    assert np.allclose(np.sort_complex(branch.multipliers[here]),
                       np.sort_complex(switched.multipliers[there]), rtol=0, atol=1e-9)
    # The start of one is the other's, or the other's after one excitation period (the
    # same orbit, either of its two phases: which one a walk holds depends on where it
    # began); allowance as above.
    one_period = simulate(1500.0, 1.25 * PAPER.Q_n, periods=1, record=("final",),
                          steps_per_period=run.settings["steps_per_period"],
                          y_init_m=branch.y_start_m[here], v_init_m_s=branch.v_start_m_s[here])
    phases = ((branch.y_start_m[here], branch.v_start_m_s[here]),
              (one_period.y_final_m[0], one_period.v_final_m_s[0]))
    gap = [max(abs(y / switched.y_start_m[there] - 1), abs(v / switched.v_start_m_s[there] - 1))
           for y, v in phases]
    assert min(gap) < 1e-9, gap  # measured 1.8e-14
    # Above the doubling there is no period-2 orbit: both walks say so, nothing is made up.
    above = continue_orbits(1.25, 1560.0, 1600.0, period=2)
    assert [b.frequency_hz.size for b in above.branches] == [0, 0]
    assert all("no stable 2-periodic orbit" in b.message for b in above.branches)


@pytest.fixture(scope="module")
def force_1400():
    from numerics import continue_in_force

    return continue_in_force(1400.0, 0.02, 0.1)


def test_the_command_line_continues_in_the_force_amplitude(force_1400, tmp_path):
    # Issue 13, item 7, for continuation in P_a: `continue --fe` writes the same JSON as
    # continue_in_force (same keys as in f_e, each point's P_a / Q in the branch's
    # pa_frac), with the two folds at 1400 Hz (0.0695 and 0.0456 Q), and draws App
    # against P_a / Q.
    out, plot = tmp_path / "force.json", tmp_path / "force.png"
    done = subprocess.run([sys.executable, "-m", "numerics", "continue", "--fe", "1400",
                           "--pa-min", "0.02", "--pa-max", "0.1", "--json", str(out),
                           "--plot", str(plot), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("ForceContinuation: f_e = 1400 Hz") and done.stderr == ""
    data = json.loads(out.read_text())
    assert data["kind"] == "ForceContinuation" and data["frequency_hz"] == 1400.0
    assert data["settings"]["pa_min"] == 0.02 and data["settings"]["pa_max"] == 0.1
    folds = [round(b["pa_frac"], 4) for b in data["bifurcations"] if b["kind"] == "fold"]
    assert folds == [0.0695, 0.0456]
    # The same computation as the function's: measured identical to the last bit (JSON
    # keeps every digit), and so asked.
    assert [b["pa_frac"] for b in data["bifurcations"]] == [
        b.pa_frac for b in force_1400.bifurcations]
    (branch,) = data["branches"]
    assert branch["pa_frac"][0] == 0.02 and branch["pa_frac"][-1] == 0.1
    assert set(branch["frequency_hz"]) == {1400.0}
    assert plot.stat().st_size > 0
    back = load(out)
    assert back.branches[0].stable.tolist() == force_1400.branches[0].stable.tolist()


def test_the_force_continuation_figure(force_1400, tmp_path):
    # App against P_a / Q: the middle branch between the folds dashed, the rest solid,
    # a marker at each fold.
    from numerics.plots import plot_force_continuation

    figure = plot_force_continuation(force_1400, tmp_path / "f.png")
    (ax,) = figure.axes
    assert ax.get_xlabel() == "P_a / Q" and "1400 Hz" in ax.get_title()
    drawn = [line for line in ax.get_lines() if line.get_xdata().size > 1]
    assert {line.get_linestyle() for line in drawn} == {"-", "--"}
    dashed = np.concatenate([line.get_xdata() for line in drawn if line.get_linestyle() == "--"])
    low, high = sorted(b.pa_frac for b in force_1400.bifurcations)
    # The unstable part lies between the folds (one point either side joins the parts).
    inside = (dashed >= low - 1e-3) & (dashed <= high + 1e-3)
    assert inside.all(), dashed[~inside]
    marks = [line for line in ax.get_lines() if line.get_marker() == "o"]
    assert sorted(float(m.get_xdata()[0]) for m in marks) == [low, high]


def test_a_bifurcation_not_located_is_drawn_hollow_with_its_tolerance(primary_005, tmp_path):
    # A fold only marked within a step (Bifurcation.located false) must not look like one
    # located to 1.5e-5 Hz: a hollow marker, an error bar of its frequency_tol_hz, and its
    # own legend entry. Every bifurcation has its error bar; the located one's is 1.5e-5 Hz
    # wide, too small to see.
    from dataclasses import replace

    from numerics.plots import plot_continuation

    located, other = primary_005.bifurcations
    marked = replace(other, located=False, frequency_tol_hz=0.5)
    run = replace(primary_005, bifurcations=[located, marked])
    (ax,) = plot_continuation(run, tmp_path / "c.png").axes
    folds = {float(line.get_xdata()[0]): line for line in ax.get_lines()
             if line.get_marker() == "o"}
    assert folds[located.frequency_hz].get_markerfacecolor() != "none"
    assert folds[marked.frequency_hz].get_markerfacecolor() == "none"
    bars = [c.get_segments()[0][:, 0] for c in ax.collections if len(c.get_segments()) == 1]
    assert len(bars) == 2

    def bar_at(f):
        return min(bars, key=lambda x: abs(x.mean() - f))

    assert np.allclose(bar_at(marked.frequency_hz), marked.frequency_hz + np.array([-0.5, 0.5]))
    half = located.frequency_tol_hz * np.array([-1.0, 1.0])
    assert np.allclose(bar_at(located.frequency_hz), located.frequency_hz + half, rtol=0,
                       atol=1e-9)
    assert "fold (not located)" in [t.get_text() for t in ax.get_legend().get_texts()]


@pytest.mark.parametrize("options, message", [
    (["--fe", "1400", "--pa-min", "0.1", "--pa-max", "0.02"],
     "argument --pa-max: must be above --pa-min, got 0.1 and 0.02"),
    (["--fe", "1e7", "--pa-min", "0.02", "--pa-max", "0.1"], "argument --fe: must lie within"),
    (["--fe", "1400", "--pa-min", "0.02"], "argument --pa-max: required with --fe"),
    (["--fe", "1400", "--pa-min", "0.02", "--pa-max", "0.1", "--fmax", "1500"],
     "argument --fmax: not with --fe"),
    (["--fe", "1400", "--pa-min", "0.02", "--pa-max", "0.1", "--series", "6"],
     "argument --series: not with --fe"),
    (["--pa-frac", "0.05", "--pa-min", "0.02"], "argument --pa-min: not with --pa-frac"),
    (["--pa-frac", "0.05", "--fe", "1400"], "argument --fe: not allowed with argument --pa-frac"),
    ([], "one of the arguments --pa-frac --fe is required"),
])
def test_bad_force_continuation_command_lines_exit_2_with_one_line(options, message, capsys):
    # Checked before any work, in the command's words (the library's checks, its
    # arguments told as options).
    from numerics.cli import main

    with pytest.raises(SystemExit) as exit_:
        main(["continue", *options, "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2
    assert err[-1].startswith("python -m numerics continue: error: ") and message in err[-1], err


def test_continued_in_force_the_period_doubling_is_where_continuation_in_f_has_it(
        doubling_125):
    # Two routes to one period doubling: continuation in f_e at 1.25 Q has it at
    # 1556.68 Hz; continuation in P_a at that f_e has it at 1.25 Q (measured within
    # 5.0e-11 Q from 0.8 Q). Allowance: each is located to 1e-8 in
    # its parameter (LOCATE_TOL), and 1e-8 f_n0 in f_e moves it by some 8e-9 Q here
    # (dP_a/df_e = 5e-4 Q/Hz: 1.2514 Q at 1560 Hz, 1.2725 Q at 1600 Hz).
    from numerics import continue_in_force
    from numerics.continuation.walk import LOCATE_TOL

    _, doubling = doubling_125
    run = continue_in_force(doubling.frequency_hz, 0.8, 1.5)
    (in_force,) = run.bifurcations
    assert in_force.kind == "period-doubling"
    assert abs(in_force.pa_frac - 1.25) < 2 * LOCATE_TOL, in_force.pa_frac - 1.25
    assert abs(in_force.app_m / doubling.app_m - 1) < 2 * LOCATE_TOL
    (branch,) = run.branches  # stable below the doubling, unstable above it
    assert branch.stable[branch.pa_frac < 1.249].all()
    assert not branch.stable[branch.pa_frac > 1.251].any()


def test_folds_are_located_once_the_walk_knows_which_turns_are_folds():
    # _locate_folds locates only the folds near a turn of f that _significant_folds keeps
    # (without the contact switches located within the step, at 0.15 Q, N = 1024, 2 of
    # the 66 met: the rest were turns of a zigzag about the bouncing fold, made by the
    # map's corners; with them, at N = 512, the walk meets the 2 folds alone). Route 2,
    # every fold met located (the route before): the same bifurcations to the last bit,
    # and the same points in the same order but those that extra locations kept (none
    # now; 61 with the zigzag). Each fold located is where f turns: a point inserted one
    # place off would not be an extreme of f.
    from numerics.continuation import WalkOptions

    run = continue_orbits(0.15, 250.0, 1800.0)
    every = continue_orbits(0.15, 250.0, 1800.0, options=WalkOptions(near_turn=10**9))
    assert [b.as_dict() for b in run.bifurcations] == [b.as_dict() for b in every.bifurcations]
    ours, theirs = run.branches[0], every.branches[0]
    kept = np.isin(theirs.frequency_hz, ours.frequency_hz)
    assert np.array_equal(theirs.frequency_hz[kept], ours.frequency_hz)
    assert np.array_equal(theirs.app_m[kept], ours.app_m)
    assert kept.all()
    f = ours.frequency_hz
    for fold in run.folds():
        (i,) = np.flatnonzero(f == fold.frequency_hz)
        assert (f[i] - f[i - 1]) * (f[i] - f[i + 1]) > 0, fold  # a strict extreme of f


@pytest.mark.parametrize("fixture", ["primary_005", "branch_015"])
def test_stability_changes_at_every_bifurcation_marked(fixture, request):
    # A branch's stable flags come from multipliers computed at its points, its marks
    # from the walk's own monodromies (up to 4.3e-6 apart): a mark must still sit where
    # the flags change, within 2 points either side (measured: every mark at 0.05, 0.1,
    # 0.15, 0.17, 0.2, 0.3, 0.4 and 0.5 Q, 250-1800 Hz, 14 in all).
    run = request.getfixturevalue(fixture)
    assert run.bifurcations
    for mark in run.bifurcations:
        nearest = []
        for branch in run.branches:
            f, app = np.asarray(branch.frequency_hz), np.asarray(branch.app_m)
            gap = (np.abs(f - mark.frequency_hz) / f.max()
                   + np.abs(app - mark.app_m) / np.nanmax(app))
            k = int(np.argmin(gap))
            nearest.append((gap[k], list(branch.stable[max(k - 2, 0):k + 3])))
        flags = min(nearest, key=lambda pair: pair[0])[1]
        assert len(set(flags)) > 1, (mark, flags)
