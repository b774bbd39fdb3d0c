"""`make paper`'s job, `python -m paper_checks`: the whole command with an empty kernel
cache and again with it filled, and the time to draw each figure (issue 12, item 4).

Baseline, measured in the same run: the old route, the tree of BASELINE_COMMIT (before
issue 12: every scene and figure in one process, each PNG saved by ``savefig``),
extracted with `git archive` and run with the same interpreter. The two routes run in
turn, so that a drift in the machine's load falls on both alike; each cold run has an
empty cache folder of its own (CONTACT_RESONANCES_CACHE), each warm run the folder of
its route's first cold run (the kernels compiled and the series' formulas written,
no sweep driver or response kernel built: `make paper` run twice in a fresh clone).
Without git (or that commit), the figures measured before the change are printed as
the baseline instead, and the header says so. The new route also runs warm with
`--jobs 1`, its scenes one after another in one process: the same code without the
worker processes (the default is one worker per processor, each taking the next scene
of `SCENE_FILES`).

The drawing times are CPU seconds of one process that draws each figure of the report
again from the same results (the scenes run once, then each plotting call is repeated),
in each route: they do not include the overlap with the computations that the new route
gains by drawing in worker processes; the whole command does. Last, what each change
to the drawing saves on the Fig. 2 figure, in this process: the figure as drawn, and
with one change undone (constrained layout instead of ``fixed_layout``, titles placed
by matplotlib, every spine in the layout, the minor ticks of the decades off view,
a mathtext parser per renderer, ``savefig``) and all undone, the variants in turn. And
the command's start before it forks the workers (imports, kernels loaded) with the
garbage collector on, against off as the command runs it.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from contextlib import ExitStack, contextmanager
from pathlib import Path
from unittest import mock

from ._timing import header, row
from .bench_commands import BASELINE_COMMIT, ROOT, cpu_of_children, old_tree

GOALS = {"cold": 12.0, "warm": 5.0}  # issue 12 [s]
REPEATS = 3
DRAW_ROUNDS, DRAW_REPEATS = 2, 3  # drawing runs per route, in turn; draws of each figure
CHANGE_REPEATS = 7  # of each variant of the Fig. 2 figure, in turn
GC_REPEATS = 8  # of the command's start, garbage collector on and off, in turn
#: The new route with its scenes run one after another in one process (`--jobs 1`).
SERIAL = "new, --jobs 1"
#: The old route's wall times [s] as this benchmark measured them before the change
#: (2026-11-23, medians of 3, the shared 2-core machine at a load of about 1.4): the
#: baseline printed when the old route cannot run here.
MEASURED_BEFORE = {"cold": 24.1, "warm": 16.4}

#: Run in a route's tree: run every scene of the report once, then draw each of its
#: figures again (argument: how many times) from the same results; print
#: {figure: [CPU seconds]}.
_DRAW_EACH_FIGURE = r"""
import json, sys, tempfile, time
from pathlib import Path

import numerics.plots as plots
from numerics.scenes import run_scene
try:
    from paper_checks.figures import plot_work_precision
    from paper_checks.scene import SCENES, paper_scene
    from paper_checks.work_precision import WorkPrecision
except ImportError:  # a route's tree from before its modules had public names
    from paper_checks._figures import plot_work_precision
    from paper_checks._scene import SCENES, paper_scene
    from paper_checks._work_precision import WorkPrecision

repeats = int(sys.argv[1])
calls = []  # (draw, args, kwargs) of every figure the scenes drew


def recorded(draw):
    def wrapper(*args, **kwargs):
        calls.append((draw, args, kwargs))
        return draw(*args, **kwargs)
    return wrapper


for name in [n for n in dir(plots) if n.startswith("plot_")]:
    setattr(plots, name, recorded(getattr(plots, name)))  # the scenes look them up here
with tempfile.TemporaryDirectory() as out:
    out = Path(out)
    for path in sorted(SCENES.glob("*.toml")):
        run = run_scene(paper_scene(path.name), out=out)
        if path.name == "work-precision.toml":
            work = WorkPrecision.from_text(run.text)
            calls.append((plot_work_precision, (work, out / "work-precision.png"), {}))
    seconds = {}
    for draw, args, kwargs in calls:
        figure = Path(args[1] if len(args) > 1 else kwargs["path"]).name
        for _ in range(repeats):
            start = time.process_time()
            draw(*args, **kwargs)
            seconds.setdefault(figure, []).append(time.process_time() - start)
print(json.dumps(seconds))
"""


def _paper(tree: Path, cache: Path, out: Path, *args: str) -> tuple[float, float]:
    """Wall time and CPU time (with the worker processes) of `python -m paper_checks`."""
    env = os.environ | {"PYTHONPATH": str(tree), "CONTACT_RESONANCES_CACHE": str(cache)}
    cpu, start = cpu_of_children(), time.perf_counter()
    subprocess.run([sys.executable, "-m", "paper_checks", "--out", str(out), "--quiet", *args],
                   cwd=tree, env=env, check=True, capture_output=True)
    return time.perf_counter() - start, cpu_of_children() - cpu


def _drawing(tree: Path, cache: Path) -> dict[str, list[float]]:
    """{figure: [CPU seconds to draw it, DRAW_REPEATS times]} in ``tree``."""
    env = os.environ | {"PYTHONPATH": str(tree), "CONTACT_RESONANCES_CACHE": str(cache)}
    done = subprocess.run([sys.executable, "-c", _DRAW_EACH_FIGURE, str(DRAW_REPEATS)],
                          cwd=tree, env=env, check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _drawings(trees: dict[str, Path], caches: dict[str, Path]) -> dict[str, dict]:
    """{route: {figure: median CPU seconds}}, the routes' drawing runs in turn."""
    seconds = {name: {} for name in trees}
    for _ in range(DRAW_ROUNDS):
        for name, tree in trees.items():
            for figure, times in _drawing(tree, caches[name]).items():
                seconds[name].setdefault(figure, []).extend(times)
    return {name: {figure: statistics.median(times) for figure, times in figures.items()}
            for name, figures in seconds.items()}


def _whole_command(trees: dict[str, Path], folder: Path) -> tuple[dict, dict[str, Path]]:
    """{route: {"cold"/"warm": [(wall, cpu), ...]}}, the routes in turn (and the new one
    with `--jobs 1`, warm); and the kernel cache each route's warm runs used."""
    times = {name: {"cold": [], "warm": []} for name in [*trees, SERIAL]}
    warm_cache = {}
    for _ in range(REPEATS):
        for name, tree in trees.items():
            cold = Path(tempfile.mkdtemp(dir=folder))
            times[name]["cold"].append(_paper(tree, cold, Path(tempfile.mkdtemp(dir=folder))))
            warm_cache.setdefault(name, cold)  # the first cold run filled it
        for name, tree, args in [*((n, t, ()) for n, t in trees.items()),
                                 (SERIAL, trees["new"], ("--jobs", "1"))]:
            cache = warm_cache[name if name != SERIAL else "new"]
            out = Path(tempfile.mkdtemp(dir=folder))
            times[name]["warm"].append(_paper(tree, cache, out, *args))
    return times, warm_cache


@contextmanager
def _constrained_layout():
    from numerics.plots import sweep

    with mock.patch.object(sweep, "fixed_layout", lambda figure, grid, **margins:
                           figure.set_layout_engine("constrained")):
        yield


@contextmanager
def _titles_by_matplotlib():
    from numerics.plots import sweep

    with mock.patch.object(sweep, "panel_title",
                           lambda ax, text, **kwargs: ax.set_title(text, **kwargs)):
        yield


@contextmanager
def _every_spine_in_layout():
    from numerics.plots import figure as figure_module

    with mock.patch.object(figure_module, "_spines_out_of_layout", lambda figure: None):
        yield


@contextmanager
def _every_minor_tick():
    from numerics.plots import figure as figure_module

    with mock.patch.object(figure_module, "_minor_log_ticks_in_view", lambda figure: None):
        yield


@contextmanager
def _parser_per_renderer():
    from matplotlib.backends.backend_agg import RendererAgg

    from numerics.plots import figure as figure_module

    # As matplotlib does: a renderer of its own, and so a parser, to measure each axis.
    with mock.patch.object(figure_module, "_share_mathtext", lambda renderer: None), \
            mock.patch.object(figure_module, "_measuring_renderer",
                              lambda: RendererAgg(1, 1, figure_module.DPI)):
        yield


@contextmanager
def _savefig():
    from numerics.plots import figure as figure_module

    with mock.patch.object(figure_module, "_write_png",
                           lambda figure, path: figure.savefig(path, dpi=figure_module.DPI)):
        yield


#: The Fig. 2 figure with one change to its drawing undone, or all of them.
UNDONE = {"constrained layout (no fixed_layout)": (_constrained_layout,),
          "titles placed by matplotlib": (_titles_by_matplotlib,),
          "every spine in the layout": (_every_spine_in_layout,),
          "minor ticks of the decades off view": (_every_minor_tick,),
          "a mathtext parser per renderer (labels parsed again)": (_parser_per_renderer,),
          "savefig (a draw to lay out, then one to render)": (_savefig,)}
UNDONE["all undone"] = tuple(change for changes in UNDONE.values() for change in changes)


def _each_change(folder: Path) -> dict[str, float]:
    """{variant: median CPU seconds of plot_app on the paper's Fig. 2 sweep}."""
    from numerics.plots import plot_app
    from numerics.scenes import run_scene
    from paper_checks.scene import paper_scene

    result = run_scene(paper_scene("fig2-fig3.toml")).outcomes[0]
    variants = {"as drawn": (), **UNDONE}
    seconds = {name: [] for name in variants}
    plot_app(result, folder / "warm-up.png")
    for _ in range(CHANGE_REPEATS):
        for name, changes in variants.items():
            with ExitStack() as undone:
                for change in changes:
                    undone.enter_context(change())
                start = time.process_time()
                plot_app(result, folder / "fig2.png")
                seconds[name].append(time.process_time() - start)
    return {name: statistics.median(times) for name, times in seconds.items()}


#: Run in the new tree: `python -m paper_checks`'s work before it forks the workers (its
#: imports, the kernels loaded), the garbage collector on or off (argument); print the
#: CPU seconds.
_START_OF_COMMAND = r"""
import gc, sys, time
if sys.argv[1] == "off":
    gc.disable()
try:
    import paper_checks.report
    from numerics.kernels import compiled_kernels
    from paper_checks.scene import KERNEL_MODELS
except ImportError:  # a route's tree from before the concept folders and public names
    import paper_checks._report
    from numerics import compiled_kernels
    from paper_checks._scene import KERNEL_MODELS

for model in KERNEL_MODELS:
    compiled_kernels(model)
print(time.process_time())
"""


def _start_without_gc(cache: Path) -> dict[str, float]:
    """{"on"/"off": median CPU seconds of the command's start, garbage collector on/off},
    in turn."""
    env = os.environ | {"PYTHONPATH": str(ROOT), "CONTACT_RESONANCES_CACHE": str(cache)}
    seconds = {"on": [], "off": []}
    for _ in range(GC_REPEATS):
        for state in seconds:
            done = subprocess.run([sys.executable, "-c", _START_OF_COMMAND, state], cwd=ROOT,
                                  env=env, check=True, capture_output=True, text=True)
            seconds[state].append(float(done.stdout.split()[-1]))
    return {state: statistics.median(times) for state, times in seconds.items()}


def main() -> None:
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        old = old_tree(folder / "old")
        trees = {"new": ROOT, **({"old": old} if old is not None else {})}
        whole, caches = _whole_command(trees, folder)
        drawing = _drawings(trees, caches)
        changes = _each_change(folder)
        start = _start_without_gc(caches["new"])
    source = (f"old route ({BASELINE_COMMIT}) in this run" if old is not None
              else f"measured before, 2026-11-23 ({BASELINE_COMMIT}; no git tree here)")
    header(f"`python -m paper_checks` (make paper), new process each, median of {REPEATS}; "
           f"baseline: {source}")
    for kind, what in (("cold", "first run, empty kernel cache"),
                       ("warm", "second run, kernels cached")):
        wall, cpu = (statistics.median(c) for c in zip(*whole["new"][kind]))
        if old is None:
            row(f"{what}: wall [s]", wall, MEASURED_BEFORE[kind], "s", higher_is_better=False)
        else:
            old_wall, old_cpu = (statistics.median(c) for c in zip(*whole["old"][kind]))
            row(f"{what}: wall [s]", wall, old_wall, "s", higher_is_better=False)
            row(f"{what}: CPU, all processes [s]", cpu, old_cpu, "s", higher_is_better=False)
        row(f"{what}: wall [s] against the goal", wall, GOALS[kind], "s",
            higher_is_better=False)
    serial_wall, serial_cpu = (statistics.median(c) for c in zip(*whole[SERIAL]["warm"]))
    warm_wall, warm_cpu = (statistics.median(c) for c in zip(*whole["new"]["warm"]))
    row("second run: wall [s] against --jobs 1 (same code)", warm_wall, serial_wall, "s",
        higher_is_better=False)
    row("second run: CPU [s] against --jobs 1 (same code)", warm_cpu, serial_cpu, "s",
        higher_is_better=False)
    if old is not None:
        header(f"Drawing each figure again from the same results, one process, CPU seconds, "
               f"median of {DRAW_ROUNDS * DRAW_REPEATS}; baseline: old route "
               f"({BASELINE_COMMIT})")
        for figure, seconds in drawing["new"].items():
            row(figure, seconds, drawing["old"].get(figure, float("nan")), "s",
                higher_is_better=False)
        row("all figures", sum(drawing["new"].values()), sum(drawing["old"].values()), "s",
            higher_is_better=False)
    header("What each change saves on the Fig. 2 figure (plot_app), this process, CPU "
           f"seconds, median of {CHANGE_REPEATS}; baseline: the change undone")
    for name in UNDONE:
        row(f"as drawn vs {name}", changes["as drawn"], changes[name], "s",
            higher_is_better=False)
    header("The command's start before the workers (imports, kernels loaded), CPU seconds, "
           f"median of {GC_REPEATS}, in turn; baseline: the garbage collector on")
    row("garbage collector off (as `python -m paper_checks` runs)", start["off"],
        start["on"], "s", higher_is_better=False)
    print(f"goals: cold <= {GOALS['cold']:g} s, warm <= {GOALS['warm']:g} s; "
          f"{os.cpu_count()} processors; load average {load:.1f} before this benchmark, "
          f"{os.getloadavg()[0]:.1f} after (worker processes gain only on processors the "
          "machine's other work leaves idle)")


if __name__ == "__main__":
    main()
