"""The multistability atlas (issue 13, item 5): the census over a grid of (f_e, P_a), run
through any concurrent.futures.Executor, bit-identical however it is run."""

import json
import logging
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from numerics import Atlas, atlas, attractor_census
from numerics.steady import multistability as atlas_module
from perturb.common import GLOSSARY, Status, load

#: Three frequencies across the paper's points of multi-stability (490 Hz at 0.5 Q: four
#: attractors; 740 Hz at 0.15 Q: two) and two amplitudes: six cells, 588 lanes.
SMALL = dict(fmin_hz=490.0, fmax_hz=740.0, pa_min=0.15, pa_max=0.5, grid=(3, 2))
#: Two cells per task (196 lanes), so that even the small atlas is three tasks, handed
#: out to more than one worker.
TASK_LANES = 2 * 98


@pytest.fixture(scope="module")
def small():
    return atlas(**SMALL, workers=1, task_lanes=TASK_LANES)


def results(found: Atlas) -> str:
    """Everything the atlas computed, as JSON text (bit for bit: floats are written as
    the shortest text that reads back the same), without the wall times."""
    data = found.as_dict()
    del data["elapsed_s"], data["cell_time_s"]
    return json.dumps(data)


def test_every_cell_is_the_census_at_its_point(small):
    assert small.settings["tasks"] == 3 and (small.status == Status.SUCCESS).all(), small
    for i, pa_frac in enumerate(small.pa_frac):
        for j, frequency_hz in enumerate(small.frequency_hz):
            census = attractor_census(frequency_hz, pa_frac)
            assert small.attractor_count[i, j] == len(census.attractors)
            assert small.attractor_periods[i][j] == [a.period for a in census.attractors]
            assert small.attractor_labels[i][j] == [a.label for a in census.attractors]
            assert small.not_settled_fraction[i, j] == census.not_settled_fraction
    # The paper's points are in it: four attractors at 490 Hz, 0.5 Q; two at 740, 0.15.
    assert small.attractor_count[1, 0] == 4 and small.attractor_count[0, 2] == 2, small


def test_a_local_pool_gives_the_same_bits(small):
    assert results(atlas(**SMALL, workers=2, task_lanes=TASK_LANES)) == results(small)


def test_a_dask_cluster_gives_the_same_bits(small):
    # Issue 13: "a test runs the atlas on a LocalCluster with two workers and checks that
    # the result equals the local run bit for bit".
    distributed = pytest.importorskip("dask.distributed")
    # (silence_logs: a worker that loses the scheduler as the cluster closes logs it.)
    with (distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=logging.CRITICAL)
          as cluster,
          distributed.Client(cluster) as client):
        found = atlas(**SMALL, executor=client.get_executor(), task_lanes=TASK_LANES)
        ran_on = client.run(lambda: True)  # the workers that were up
    assert len(ran_on) == 2
    assert results(found) == results(small)


def test_a_different_cut_gives_the_same_bits():
    # Every lane iterates Newton until it converges itself, whatever its batch does, so a
    # lane's result does not depend on the lanes beside it. At rest (P_a = 0) App is
    # round-off, the most sensitive number there is: when a batch iterated until all its
    # lanes had converged, it came out 3.7e-22 m alone and 1.0e-21 m in one batch with
    # the 0.5 Q cell.
    cells = dict(fmin_hz=490.0, fmax_hz=490.0, pa_min=0.0, pa_max=0.5, grid=(1, 2), workers=1)
    alone = atlas(**cells, task_lanes=98)
    together = atlas(**cells, task_lanes=196)
    assert (alone.settings["tasks"], together.settings["tasks"]) == (2, 1)
    assert alone.attractor_labels == together.attractor_labels
    assert alone.attractor_labels[0] == [["rest"]]
    assert alone.attractor_app_m == together.attractor_app_m


def test_the_cut_into_tasks_depends_on_the_cells_alone():
    # The cut does not follow the workers (the module's docstring). Cells of 98 lanes at
    # 128 steps: a task ends with the cell that reaches 2048 lanes, the 21st.
    sizes = [t.size for t in atlas_module.task_cells(np.full(100, 128), 98)]
    assert sizes == [21, 21, 21, 21, 16], sizes
    # Lanes with many steps keep their orbits (y at every step): fewer per task, and a
    # cell larger than a task is a task alone.
    assert [t.size for t in atlas_module.task_cells(np.full(4, 2**15), 98)] == [1, 1, 1, 1]


_REAL_TASK = atlas_module._run_task


def _fails_at_half_q(frequency_hz, pa_frac, *args):
    """The atlas's task, made to raise for the tasks holding P_a = 0.5 Q (module level:
    a worker process finds it by name)."""
    if 0.5 in pa_frac:
        raise RuntimeError("injected failure")
    return _REAL_TASK(frequency_hz, pa_frac, *args)


@pytest.mark.parametrize("where", ["worker processes", "threads", "this process"])
def test_a_failed_task_is_reported_and_the_others_complete(where, small, monkeypatch):
    monkeypatch.setattr(atlas_module, "_run_task", _fails_at_half_q)
    if where == "threads":
        with ThreadPoolExecutor(2) as threads:  # any Executor will do
            found = atlas(**SMALL, executor=threads, task_lanes=TASK_LANES)
    else:
        found = atlas(**SMALL, workers=2 if where == "worker processes" else 1,
                      task_lanes=TASK_LANES)
    failed = found.status == Status.FAILED
    # The tasks are cells (0, 1), (2, 3), (4, 5) in row-major order (P_a, then f_e):
    # 0.5 Q is in the second and the third.
    assert failed.tolist() == [[False, False, True], [True, True, True]], found
    assert all(found.message[i][j] == "RuntimeError: injected failure"
               for i, j in zip(*np.nonzero(failed)))
    assert found.message[0][:2] == ["", ""]
    assert (found.attractor_count[failed] == -1).all()
    assert np.isnan(found.not_settled_fraction[failed]).all()
    # The task that ran gives what it gives in the atlas where all ran.
    assert (found.attractor_count[0, :2] == small.attractor_count[0, :2]).all()
    assert found.attractor_basins[0][:2] == small.attractor_basins[0][:2]
    assert "failed (4 cells): RuntimeError: injected failure" in str(found)
    assert found.settings["tasks_retried"] == 0  # a task's own error is not run again


@pytest.mark.parametrize("change, match", [
    ({"grid": (3,)}, "`grid` must be two integers"),
    ({"grid": (0, 2)}, r"`grid\[0\]` must be an integer >= 1"),
    ({"grid": (3, 2.5)}, r"`grid\[1\]` must be an integer >= 1"),
    ({"fmin_hz": 0.0}, "`fmin_hz` must be"),
    ({"fmax_hz": 400.0}, "`fmax_hz` must be above `fmin_hz`"),
    ({"pa_max": 0.1}, "`pa_max` must be above `pa_min`"),
    ({"pa_min": -0.1}, "`pa_min` must be"),
    ({"grid": (1, 2)}, "`fmax_hz` must equal `fmin_hz` with one point"),
    ({"grid": (3000, 4000)}, "1176000000 lanes, more than the limit of 2000000"),
    ({"grid": (10**9, 10**9)}, "lanes, more than the limit"),  # before allocating the axes
    ({"workers": 0}, "`workers` must be an integer >= 1"),
    ({"executor": "dask"}, "`executor` must be a concurrent.futures.Executor"),
    ({"executor": ThreadPoolExecutor(1), "workers": 2}, "not both"),
    ({"initial_states": {"y_over_y0": [1.0]}}, "`initial_states`: `grid` must have exactly"),
    ({"tol": -1.0}, "`tol` must be"),
    ({"task_lanes": 0}, "`task_lanes` must be"),
])
def test_bad_input_is_refused_before_any_work(change, match, monkeypatch):
    monkeypatch.setattr(atlas_module, "_run", _no_work)
    with pytest.raises(ValueError, match=match):
        atlas(**(SMALL | change))


def _no_work(*args):
    raise AssertionError("work started")


def test_the_atlas_keeps_the_result_contract(small, tmp_path):
    small.to_json(tmp_path / "atlas.json")
    back = load(tmp_path / "atlas.json")
    assert isinstance(back, Atlas) and results(back) == results(small)
    data = json.loads((tmp_path / "atlas.json").read_text())
    assert {"attractor_count", "attractor_periods", "attractor_labels", "not_settled_fraction",
            "status", "message", "cell_time_s"} <= set(data) <= set(GLOSSARY)
    assert set(small.settings) <= set(GLOSSARY) and small.model["parameters"]
    assert "\n" not in repr(small) and len(repr(small)) < 200


def test_progress_over_tasks_unless_quiet(monkeypatch, capsys):
    # stderr is captured, not a terminal: the bar is asked for.
    monkeypatch.setenv("CONTACT_RESONANCES_PROGRESS", "always")
    atlas(740.0, 760.0, 0.15, 0.15, grid=(2, 1), workers=1, quiet=False, task_lanes=98)
    assert "atlas tasks" in capsys.readouterr().err
    atlas(740.0, 760.0, 0.15, 0.15, grid=(2, 1), workers=1)
    assert capsys.readouterr().err == ""


def test_the_atlas_imports_and_runs_without_dask():
    # dask is an optional extra: hide it, and the default pool still runs.
    code = ("import sys; sys.modules['dask'] = None; sys.modules['distributed'] = None\n"
            "from numerics import atlas\n"
            "print(atlas(740.0, 760.0, 0.15, 0.15, grid=(2, 1), workers=2).attractor_count)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.strip() == "[[2 2]]", done.stderr


def test_the_command_writes_json_and_the_map(tmp_path):
    target, figure = tmp_path / "atlas.json", tmp_path / "atlas.png"
    done = subprocess.run([sys.executable, "-m", "numerics", "atlas", "--fmin", "740",
                           "--fmax", "760", "--pa-min", "0.15", "--pa-max", "0.15", "--grid",
                           "2", "1", "--workers", "1", "--json", str(target), "--plot",
                           str(figure), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("Atlas of 1 x 2 cells") and done.stderr == ""
    data = json.loads(target.read_text())
    assert data["attractor_count"] == [[2, 2]] and data["settings"]["cells"] == [2, 1]
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_command_runs_on_a_dask_scheduler(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    target = tmp_path / "atlas.json"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None,
                                  silence_logs=logging.CRITICAL) as cluster:
        done = subprocess.run([sys.executable, "-m", "numerics", "atlas", "--fmin", "740",
                               "--fmax", "760", "--pa-min", "0.15", "--pa-max", "0.15",
                               "--grid", "2", "1", "--scheduler", cluster.scheduler_address,
                               "--json", str(target), "--quiet"], capture_output=True,
                              text=True)
    assert done.returncode == 0, done.stderr
    assert json.loads(target.read_text())["attractor_count"] == [[2, 2]]


@pytest.mark.parametrize("options, match", [
    (["--grid", "2"], "--grid: expected 2 arguments"),
    (["--grid", "2", "0"], "--grid: must be an integer >= 1"),
    (["--grid", "2", "2", "--pa-min", "0.3", "--pa-max", "0.2"], "--pa-max: must be above"),
    (["--grid", "1", "2"], "--fmax: must equal --fmin"),
    (["--grid", "2", "2", "--workers", "2", "--scheduler", "tcp://x:1"], "not allowed with"),
    (["--grid", "5000", "5000"], "more than the limit"),
])
def test_bad_command_lines_exit_2_naming_the_option(options, match):
    done = subprocess.run([sys.executable, "-m", "numerics", "atlas", *options, "--quiet"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and match in done.stderr, done.stderr


def test_the_map_shows_failed_cells(small, tmp_path):
    from numerics.plots import plot_atlas

    failed = Atlas(**{**{f: getattr(small, f) for f in small.__dataclass_fields__},
                      "status": np.array([[0, 0, -1], [0, 0, -1]])})
    figure = plot_atlas(failed, tmp_path / "map.png")
    labels = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
    # The counts of the cells that ran (column 2 had 2 and 3 attractors), and the failed.
    assert labels == ["2", "4", "task failed (2)"], labels
    assert (tmp_path / "map.png").exists()


def test_the_bistable_cells_are_those_inside_the_fold_curves(tmp_path):
    # Two independent routes to the bistable region of the primary peak near 0.05 Q:
    # the census's count at each cell, and the fold curves continued in (f_e, P_a)
    # (issue 13, item 4). A cell has two attractors exactly where its f_e lies between
    # the two folds at its P_a. Cells within 0.5 Hz of a fold are left out (the folds are
    # continued at 512 steps per period, the census runs at 128 or more: the folds may
    # move a little): one, 0.50 Hz outside a fold at 0.042 Q. Measured: the 119 others
    # agree, the nearest 0.7 Hz inside a fold (1373.7 Hz at 0.05 Q).
    from numerics import fold_curves
    from numerics.plots import plot_atlas

    found = atlas(1300.0, 1500.0, 0.03, 0.05, grid=(20, 6))
    folds = fold_curves(1300.0, 1500.0, 0.03, 0.05, seed_pa_fracs=[0.05])
    (curve,) = folds.fold_curves
    cusp = int(np.argmin(curve.pa_frac))  # the curve runs fold, cusp, other fold
    checked = 0
    for i, pa_frac in enumerate(found.pa_frac):
        ends = [np.interp(pa_frac, branch_pa, branch_f, left=np.nan) for branch_pa, branch_f in
                ((curve.pa_frac[: cusp + 1][::-1], curve.frequency_hz[: cusp + 1][::-1]),
                 (curve.pa_frac[cusp:], curve.frequency_hz[cusp:]))]
        low, high = sorted(ends) if not np.isnan(ends).any() else (np.inf, -np.inf)
        for j, frequency_hz in enumerate(found.frequency_hz):
            if min(abs(frequency_hz - low), abs(frequency_hz - high)) < 0.5:
                continue
            inside = low < frequency_hz < high
            assert found.attractor_count[i, j] == (2 if inside else 1), (frequency_hz, pa_frac)
            checked += 1
    assert checked == 119 and (found.attractor_count == 2).sum() == 8, found
    figure = plot_atlas(found, tmp_path / "map.png", folds=folds)
    labels = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
    assert labels == ["1", "2", "folds, primary"], labels


def test_beyond_the_fold_curves_end_the_bistable_cells_are_between_the_folds_in_f():
    # The figure of `make figures` (docs/atlas.md): the fold curve of the primary's upper
    # fold stops at 0.061 Q, where its orbit loses contact, yet the census still finds two
    # attractors beyond it. At 0.068 Q continuation in f_e (the third route) has its folds
    # at 1156.06 and 1401.44 Hz (measured); the cells with two attractors are exactly
    # those between them (measured: the 25 cells 1160-1400 Hz; the nearest cell, 1400 Hz,
    # is 1.4 Hz from a fold, more than the 0.5 Hz the folds may move between N = 512 and
    # the census's N).
    from numerics import continue_orbits

    row = atlas(1150.0, 1550.0, 0.068, 0.068, grid=(41, 1))
    low, high = sorted(b.frequency_hz for b in continue_orbits(0.068, 1100.0, 1550.0).folds())
    f = row.frequency_hz
    assert np.abs(f[:, None] - [low, high]).min() > 0.5
    inside = (low < f) & (f < high)
    assert row.attractor_count[0].tolist() == np.where(inside, 2, 1).tolist()
    assert inside.sum() == 25


_KILL = {}  # the marker file and the task runner of the test below, for forked workers


def _killed_once(*task):
    """The atlas's task, but the first to start kills its own worker process."""
    import os
    import signal

    try:
        os.close(os.open(_KILL["marker"], os.O_CREAT | os.O_EXCL))
    except FileExistsError:
        return _KILL["run_task"](*task)
    os.kill(os.getpid(), signal.SIGKILL)


def test_the_atlas_survives_a_lost_worker(monkeypatch, tmp_path):
    # The first task to start kills its own worker process (a marker file, created once,
    # says which): the pool breaks, the tasks lost with it run again on a fresh pool,
    # and the atlas is the undisturbed one, cell for cell, saying how many ran again.
    from numerics.steady import multistability

    args = (400.0, 800.0, 0.1, 0.5)
    undisturbed = atlas(*args, grid=(12, 6), workers=2)
    monkeypatch.setitem(_KILL, "marker", tmp_path / "killed")
    monkeypatch.setitem(_KILL, "run_task", multistability._run_task)
    monkeypatch.setattr(multistability, "_run_task", _killed_once)  # forked workers inherit it
    disturbed = atlas(*args, grid=(12, 6), workers=2)
    assert (tmp_path / "killed").exists() and disturbed.settings["tasks_retried"] >= 1
    assert "run again after a worker was lost" in disturbed.summary()
    disturbed.settings.pop("tasks_retried")
    undisturbed.settings.pop("tasks_retried")
    assert results(disturbed) == results(undisturbed)
