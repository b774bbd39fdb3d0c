"""`python -m paper_checks --quick`: the report the test suite can afford; and the
paper's figures as scenes (paper_checks/scenes), which repeat perturb's numbers exactly."""

import dataclasses
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from numerics import sweep
from numerics.scenes import run_scene
from paper_checks import scene as scene_module
from paper_checks.forked import ForkedJobs, forks
from paper_checks.scene import (
    CENSUS_SCENES,
    COMPARED_FRACTIONS,
    KERNEL_FREE,
    SCENES,
    PaperScene,
    paper_scene,
    worker_pool,
)
from perturb import (
    EQ_2_6,
    FULL,
    PAPER,
    PAPER_BAND_HZ,
    PAPER_COEXISTENCE,
    PAPER_HYSTERESIS_POINT,
    PAPER_PANEL_FRACTIONS,
)


def test_paper_checks_quick_writes_the_report(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "paper_checks", "--quick", "--out", str(tmp_path)],
        capture_output=True, text=True)
    report = json.loads((tmp_path / "report.json").read_text())
    assert len(report["claims"]) == 11 and all(
        {"id", "statement", "passed", "measured"} <= set(c) for c in report["claims"])
    failed = [c["id"] for c in report["claims"] if not c["passed"]]
    assert not failed and done.returncode == 0, (failed, done.stdout)
    text = (tmp_path / "report.md").read_text()
    for figure in report["figures"].values():
        assert (tmp_path / figure).stat().st_size > 10_000 and f"]({figure})" in text


def test_an_unusable_output_folder_is_refused_before_any_work(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    done = subprocess.run([sys.executable, "-m", "paper_checks", "--quick", "--out",
                           str(blocker)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "argument --out" in done.stderr


#: The paper's band on the 5 Hz grid of Fig. 2 and 3.
BAND_5HZ = np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + 2.5, 5.0)
#: What each paper scene repeats of perturb's constants: (f_e grid [Hz], P_a / Q, options).
PAPER_NUMBERS = {
    "fig2-fig3.toml": (BAND_5HZ, PAPER_PANEL_FRACTIONS, {"direction": "both"}),
    **{scene: ([PAPER_COEXISTENCE[point][0]], (PAPER_COEXISTENCE[point][1],), {})
       for point, scene in CENSUS_SCENES.items()},
    "fig4.toml": ([], (), {"points": 100}),
    "fig5.toml": ([PAPER_HYSTERESIS_POINT[0]], (PAPER_HYSTERESIS_POINT[1],),
                  {"periods": 400, "steps_per_period": 512}),
    "backbone.toml": ([], (), {"points": 200}),
    "comparison.toml": (BAND_5HZ, COMPARED_FRACTIONS,
                        {"orders": (2, 4, 6, 8), "steps_per_period": 128}),
    "work-precision.toml": ([], (), {"quick": False}),
}


#: The report's figure files (as before the scenes): all but work-precision.png are theirs.
FIGURE_FILES = {"fig2-app.png", "fig3-extrema.png", "fig4-natural-frequency.png",
                "fig5-hysteresis.png", "backbone.png", "analytic-vs-numerical.png",
                "census-740hz.png", "census-490hz.png"}


def test_every_paper_scene_reads_and_says_what_it_is():
    assert sorted(p.name for p in SCENES.glob("*.toml")) == sorted(PAPER_NUMBERS)
    assert set(CENSUS_SCENES) == set(PAPER_COEXISTENCE)
    files = set()
    for name in PAPER_NUMBERS:
        scene = paper_scene(name)  # raises a SceneError naming the key if one is wrong
        assert scene.title and len(scene.description) > 100, name
        files |= set(scene.figures.values())
    assert files == FIGURE_FILES


@pytest.mark.parametrize("name", sorted(PAPER_NUMBERS))
def test_a_paper_scene_repeats_perturbs_numbers_exactly(name):
    # The paper's numbers live in perturb/model/parameters.py; a scene file repeats some of
    # them as data, and this is where the two are held equal.
    frequency_hz, pa_frac, options = PAPER_NUMBERS[name]
    scene = paper_scene(name)
    assert np.array_equal(scene.frequency_hz, frequency_hz), name
    assert scene.pa_frac == tuple(pa_frac), name
    assert {k: scene.options[k] for k in options} == options, name
    # Fig. 4 is f_n0 of Eq. 2.6 in closed form: its scene's effects are Eq. 2.6's.
    effects = EQ_2_6 if scene.study == "natural_frequency" else FULL
    assert scene.parameters == PAPER and not scene.overrides and scene.effects == effects, name


def test_the_fig2_fig3_scene_is_the_papers_sweep_bit_for_bit():
    scene = paper_scene("fig2-fig3.toml")
    grid = scene.frequency_hz[[0, 98, 170, 230, 300]]  # 250, 740, 1100, 1400, 1750 Hz
    run = run_scene(dataclasses.replace(scene, frequency_hz=grid)).outcomes[0]
    direct = sweep(grid, PAPER_PANEL_FRACTIONS)
    assert len(run.runs) == len(direct.runs) == 2 * len(PAPER_PANEL_FRACTIONS)
    for got, want in zip(run.runs, direct.runs):
        assert (got.pa_frac, got.direction) == (want.pa_frac, want.direction)
        for field in ("app_m", "status", "ymin_m"):
            assert np.array_equal(getattr(got, field), getattr(want, field), equal_nan=True), \
                (field, got.pa_frac, got.direction)


#: Run in a fresh interpreter (no kernel loaded yet): every way to compiled RK4 (the
#: kernels' module, and the compiled walk's, which holds its own RK4 steps) refused, then
#: the scenes of KERNEL_FREE, as `make paper` runs them; and, the negative control,
#: Fig. 5's scene (400 periods of RK4), which must hit the refusal.
_NO_KERNELS = """
import numerics.kernels.codegen as codegen, numerics.kernels.walk_codegen as walk_codegen
from numerics.scenes import run_scene
from paper_checks.scene import KERNEL_FREE, paper_scene

class Refused(Exception):
    pass

def refuse(*args, **kwargs):
    raise Refused("a compiled RK4 module was loaded")

codegen.load_generated = walk_codegen.load_generated = refuse
for name in KERNEL_FREE:
    run_scene(paper_scene(name))
    print("ran", name)
try:
    run_scene(paper_scene("fig5.toml"))
except Refused:
    print("refused fig5.toml")
"""


def test_the_kernel_free_scenes_load_no_compiled_rk4():
    # paper_checks starts KERNEL_FREE's scenes beside the kernels' compilation, before
    # they exist: were one of them to run RK4, it would compile the kernels itself (or
    # wait for them). Some 2 s (measured 0.3 s for fig4, 0.08 s for the backbone).
    done = subprocess.run([sys.executable, "-c", _NO_KERNELS], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:-1] == [
        *(f"ran {name}" for name in KERNEL_FREE), "refused fig5.toml"], done.stdout


# -- make paper's processes: the kernel-free scenes forked beside the kernels' loading


def _square(x: int) -> int:
    if x < 0:
        raise ValueError(f"no square of a negative number here: {x}")
    return x * x


@pytest.mark.skipif(not forks(), reason="ForkedJobs forks (Linux)")
def test_forked_jobs_give_each_result_or_error_where_it_is_asked_for():
    jobs = ForkedJobs(_square, {"a": (3,), "b": (-1,), "c": (4,)})
    assert jobs.future("c").result() == 16 and jobs.result("a") == 9  # in any order
    with pytest.raises(ValueError, match="negative number here: -1") as raised:
        jobs.result("b")
    assert "_square" in str(raised.value.__cause__)  # the child's traceback
    jobs.join()
    assert jobs.result("c") == 16


class _Unloadable(Exception):
    """An error that pickles but does not unpickle (its __init__ needs two arguments)."""

    def __init__(self, first, second):
        super().__init__(first)


def _raise_unloadable(message):
    raise _Unloadable(message, "second")


@pytest.mark.skipif(not forks(), reason="ForkedJobs forks (Linux)")
def test_a_forked_error_that_does_not_unpickle_comes_back_as_its_message():
    # A review found such an error breaking the parent's receive, and the jobs after it
    # lost. It comes back as a RuntimeError with its message; or whole, where something
    # has taught pickle to rebuild exceptions without __init__ (dask.distributed installs
    # tblib's reducers: in the whole suite, after the atlas tests).
    jobs = ForkedJobs(_raise_unloadable, {"bad": ("the message",), "next": ("x",)})
    for name, message in (("bad", "the message"), ("next", "x")):  # the next one too
        with pytest.raises((RuntimeError, _Unloadable), match=message):
            jobs.result(name)
    jobs.join()
    assert jobs._receiver.closed


@pytest.mark.skipif(not forks(), reason="ForkedJobs forks (Linux)")
def test_a_forked_process_that_dies_is_an_error_not_a_wait():
    jobs = ForkedJobs(os._exit, {"exit": (3,)})
    with pytest.raises(RuntimeError, match=r"exit code 3\) without the result of 'exit'"):
        jobs.result("exit")


@pytest.mark.skipif(not forks(), reason="the kernel-free scenes are forked on Linux")
def test_with_the_kernels_built_the_kernel_free_scenes_run_forked_not_in_the_pool(
        tmp_path):
    # The kernels compiled already, start() runs KERNEL_FREE's scenes in a process forked
    # before it loads them (no kernel to load here), none in the workers; they give what
    # they give here, figures byte for byte.
    here = PaperScene(quick=True, out=tmp_path / "here", kernel_models=())
    there = PaperScene(quick=True, out=tmp_path / "there", kernel_models=())
    with worker_pool(2) as pool:
        there.start(pool, KERNEL_FREE)
        assert len(there.forked) == 1 and not pool._processes  # no worker started
        assert np.array_equal(there.heights.f_n0_hz, here.heights.f_n0_hz)
        assert np.array_equal(there.backbone.app_m, here.backbone.app_m)
    there.check_background()
    for name in KERNEL_FREE:
        for figure in paper_scene(name).figures.values():
            assert (tmp_path / "there" / figure).read_bytes() == \
                (tmp_path / "here" / figure).read_bytes()


def test_importing_the_package_or_its_command_leaves_the_heavy_modules_and_the_gc():
    # `python -m paper_checks` turns the garbage collector off before it imports the
    # checks (paper_checks/__main__.py): the package imports them at first use, and the
    # command's module turns it off only when run as the command.
    code = ("import gc, sys, paper_checks, paper_checks.__main__; "
            "heavy = [m for m in ('sympy', 'matplotlib', 'numba', 'paper_checks.scene') "
            "if m in sys.modules]; assert not heavy and gc.isenabled(), heavy; "
            "assert paper_checks.PaperScene.__name__ == 'PaperScene'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_work_precision_study_measured_in_parts_is_the_study_measured_whole():
    # `make paper` measures each method in a job of its own (_scene.WORK_PARTS) and
    # merges them: the same methods in the same order, with the same settings and
    # errors (the errors are deterministic; the times are not).
    from paper_checks.work_precision import METHODS, WorkPrecision, work_precision

    whole = work_precision(quick=True)
    parts = [work_precision(quick=True, methods=(name,)) for name in scene_module.WORK_PARTS]
    merged = WorkPrecision.merged(parts)
    assert [m.name for m in merged.methods] == [m.name for m in whole.methods] == list(METHODS)
    for got, want in zip(merged.methods, whole.methods):
        assert (got.setting, got.settings, got.errors) == (want.setting, want.settings,
                                                           want.errors), got.name
    assert merged.elapsed_s == sum(part.elapsed_s for part in parts)
    with pytest.raises(ValueError, match="distinct methods"):
        WorkPrecision.merged(parts[:1] * 2)
    with pytest.raises(ValueError, match="`methods`"):
        work_precision(quick=True, methods=("Euler",))


def test_the_report_merges_the_work_precision_parts_the_workers_measured(tmp_path):
    scene = PaperScene(quick=True, out=tmp_path)
    with worker_pool(2) as pool:
        scene.start(pool, names=[scene_module.WORK_PRECISION_SCENE])
        parts = scene._started[scene_module.WORK_PRECISION_SCENE]
        assert len(parts) == len(scene_module.WORK_PARTS)
        work = scene.work_precision
    run = scene.runs[scene_module.WORK_PRECISION_SCENE]
    assert [m.name for m in work.methods] == ["RK4", "series", "DOP853"]
    assert run.settings["options"]["method"] == "all"
    assert run.files == [scene_module.WORK_PRECISION_FIGURE]
    assert (tmp_path / scene_module.WORK_PRECISION_FIGURE).stat().st_size > 10_000


def test_a_work_precision_part_that_fails_raises_where_the_study_is_asked_for(
        tmp_path, monkeypatch):
    from paper_checks import work_precision as work_precision_module

    def broken(*args):  # _series(quick, truncation)
        raise RuntimeError("the series part broke")

    monkeypatch.setattr(work_precision_module, "_series", broken)  # the forked workers too
    scene = PaperScene(quick=True, out=tmp_path)
    with worker_pool(2) as pool:
        scene.start(pool, names=[scene_module.WORK_PRECISION_SCENE])
        with pytest.raises(RuntimeError, match="the series part broke"):
            assert scene.work_precision is None  # never reached: the property raises
    assert "accuracy against time" not in scene.timings
    assert not (tmp_path / scene_module.WORK_PRECISION_FIGURE).exists()
