"""The computations the paper's checks share, each done once and timed.

``PaperScene(quick, out)`` computes on first use. The paper's figures are scenes
(``paper_checks/scenes/*.toml``), each run once by ``numerics.scenes.run_scene``,
which writes its figures into ``out`` (none without it): the sweeps of Fig. 2 and 3,
the attractor censuses at the paper's points of multi-stability, Fig. 4, Fig. 5, the
exact backbone, the analytic-against-numerical comparison and the work-precision
study. The linear check and the perturbation series are direct calls. ``quick`` uses
coarser grids (for the tests), in variants of the scenes made by
``dataclasses.replace``.

The scenes are independent: ``PaperScene.start(executor)`` hands them all to worker
processes (``worker_pool``), one job per scene (the work-precision study: one per
method of ``WORK_PARTS``, see ``_submit``), longest first, each drawing its own
figures there, and the properties then wait for theirs; an error in a worker is
raised where a result of its scene is asked for. Those that run no RK4
(``KERNEL_FREE``) start at once: beside the compilation of the kernels, in the workers,
as does the derivation of the series' formulas (written to the cache on disk, where
the work-precision study and the comparison find them); or, when the kernels are
compiled already, in a process forked while this one loads them (``ForkedJobs``). The
others start when the kernels are loaded. The work-precision study is three jobs there,
one per method (``WORK_PARTS``), merged and drawn here. Without ``start`` every scene
runs in this process when first asked for.
"""

from __future__ import annotations

import multiprocessing
import time
from collections.abc import Iterable, Iterator
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from numerics import steady_states
from numerics.kernels import compiled_kernels
from numerics.kernels.codegen import kernels_built
from numerics.scenes import Scene, SceneRun, read_scene, run_scene
from perturb import (
    EQ_2_6,
    PAPER,
    PAPER_BAND_HZ,
    PAPER_COEXISTENCE,
    PAPER_PANEL_FRACTIONS,
    ContactModel,
    derive,
    eq26_numbers,
)
from perturb.common import tied_to_this_process
from perturb.series.compiled import lambdified_series

from .forked import ForkedJobs, forks
from .work_precision import ERROR_ORDERS, SERIES_ORDERS, WorkPrecision, scene_methods

__all__ = ["PaperScene", "COEXISTENCE_POINTS", "SCENES", "CENSUS_SCENES", "SCENE_FILES",
           "KERNEL_FREE", "paper_scene", "worker_pool"]

#: The folder of the paper's scenes.
SCENES = Path(__file__).parent / "scenes"
#: Section 3.3: (f_e [Hz], P_a / Q) where the paper reports coexisting solutions.
COEXISTENCE_POINTS = PAPER_COEXISTENCE
#: The scene of each point of COEXISTENCE_POINTS.
CENSUS_SCENES = {"740 Hz, 0.15Q": "census-740hz.toml", "490 Hz, 0.50Q": "census-490hz.toml"}
#: The scene of the work-precision study.
WORK_PRECISION_SCENE = "work-precision.toml"
#: Every scene of the report, longest first, as the workers take them: the comparison
#: 2.6 s, Fig. 2 + 3 2.2 s, the work-precision study (in the parts of WORK_PARTS), Fig. 4
#: 0.5 s, then under 0.3 s each with their figures (measured once by hand, 2026-11-23,
#: the kernels cached and no sweep driver built, as in `make paper` run twice in a
#: fresh clone).
SCENE_FILES = ("comparison.toml", "fig2-fig3.toml", WORK_PRECISION_SCENE, "fig4.toml",
               *CENSUS_SCENES.values(), "backbone.toml", "fig5.toml")
#: The scenes that run no RK4: they need no compiled kernels.
KERNEL_FREE = ("fig4.toml", "backbone.toml")
#: The models whose compiled kernels the scenes share (the full model; Eq. 2.6 for the
#: comparison and the series' reference), compiled before the scenes start.
KERNEL_MODELS = (ContactModel(), ContactModel(effects=EQ_2_6))
#: Section 3.1's "very small amplitude of the excitation force", as P_a / Q.
TINY_FORCE_FRAC = 1e-3
#: Force amplitudes at which the series is compared with RK4 (the series needs contact).
COMPARED_FRACTIONS = (0.05, 0.10, 0.15)
#: What ``quick`` changes: energy levels of the backbone, orders of the comparison,
#: frequency step of the band [Hz] (5 Hz in the scenes).
QUICK_BACKBONE_POINTS = 60
QUICK_ORDERS = (2, 4, 6)
QUICK_STEP_HZ = 10.0
#: The work-precision figure, drawn from the study's text (no scene draws it).
WORK_PRECISION_FIGURE = "work-precision.png"
#: Its methods, each measured in a job of its own when the scenes run in workers, longest
#: first: DOP853 0.67 s, the series 0.34 s, RK4 0.06 s, of which 0.045 s is the reference
#: orbit that the DOP853 job computes too. As one job of 1.1 s the study was the last to
#: end, after the other worker had run out of scenes (0.8 s before it, at a load of
#: 0.5). Measured once by hand, 2026-11-24.
WORK_PARTS = ("DOP853", "series", "RK4")


def paper_scene(name: str) -> Scene:
    """The paper's scene ``name`` (a file of ``paper_checks/scenes``), read and checked."""
    return read_scene(SCENES / name)


@dataclass
class SceneJob:
    """A scene as ``run_job`` ran it: its run, and its time with its figures [s].

    ``figure_seconds`` is the time of the figure drawn beside the scene (the
    work-precision figure), or None.
    """

    run: SceneRun
    seconds: float
    figure_seconds: float | None = None


def run_job(scene: Scene, out: Path | None) -> SceneJob:
    """Run ``scene``, its figures into ``out``; the work-precision study's figure too."""
    start = time.perf_counter()
    run = run_scene(scene, out=out)
    job = SceneJob(run, time.perf_counter() - start)
    if out is not None and scene.study == "work_precision":
        _draw_work_precision(job, out)
    return job


def _draw_work_precision(job: SceneJob, out: Path) -> None:
    """Draw the work-precision figure of ``job`` into ``out``, timed."""
    from .figures import plot_work_precision

    start = time.perf_counter()
    plot_work_precision(WorkPrecision.from_text(job.run.text), out / WORK_PRECISION_FIGURE)
    job.figure_seconds = time.perf_counter() - start
    job.run.files.append(WORK_PRECISION_FIGURE)


def merged_work_precision(parts: list[SceneJob], scene: Scene, out: Path | None) -> SceneJob:
    """The work-precision scene ``scene`` as one job, from ``parts`` that measured some
    of its methods each (its figure drawn into ``out``, when given)."""
    work = WorkPrecision.merged([WorkPrecision.from_text(part.run.text) for part in parts])
    wanted = scene_methods(scene)
    if [m.name for m in work.methods] != list(wanted):
        raise ValueError(f"the parts measured {[m.name for m in work.methods]}, "
                         f"the scene asks for {list(wanted)}")
    run = replace(parts[0].run, text=work.to_text(), files=[], settings=scene.as_dict(),
                  elapsed_s=sum(part.run.elapsed_s for part in parts))
    job = SceneJob(run, sum(part.seconds for part in parts))
    if out is not None:
        _draw_work_precision(job, out)
    return job


def _compile(model: ContactModel) -> None:
    compiled_kernels(model)  # the module stays in the worker: it does not pickle


def _derive_formulas() -> None:
    """The series' formulas of every order the work-precision study and the comparison
    evaluate, derived once into the cache on disk (or found there). Not kept in this
    worker's memory: the study that may run here next times each order's first call."""
    for order in range(max(SERIES_ORDERS) + ERROR_ORDERS + 1):
        lambdified_series.__wrapped__(order)


@contextmanager
def worker_pool(jobs: int) -> Iterator[Executor | None]:
    """``jobs`` worker processes for the scenes, or None for one job (run here).

    On Linux the workers are forked: they start at once with what this process has
    imported, where spawned ones would import it all again each (elsewhere they are
    spawned). On an error the scenes not started are cancelled; when this process ends,
    killed or not, the workers end with it (``common.tied_to_this_process``).
    """
    if jobs <= 1:
        yield None
        return
    method = "fork" if forks() else None
    pool = ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context(method),
                               initializer=tied_to_this_process())
    try:
        yield pool
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()


class PaperScene:
    """Shared, lazily computed results, with the time and settings of each.

    ``runs`` holds each scene's ``SceneRun`` by file name, once it has run;
    ``kernel_models`` the models whose kernels ``start`` compiles before the scenes
    (``KERNEL_MODELS``).
    """

    def __init__(self, quick: bool = False, out: str | Path | None = None,
                 kernel_models: tuple[ContactModel, ...] = KERNEL_MODELS) -> None:
        self.quick = quick
        self.kernel_models = kernel_models
        self.out = None if out is None else Path(out)
        self.timings: dict[str, dict] = {}
        self.runs: dict[str, SceneRun] = {}
        self.figure_seconds: dict[str, float] = {}
        self._started: dict[str, Future | list[Future]] = {}
        #: Tasks whose result nothing asks for (the formulas' derivation): ``check_background``.
        self.background: list[Future] = []
        #: The forked processes of ``start``, joined by ``check_background``.
        self.forked: list[ForkedJobs] = []

    def _timed(self, name: str, settings: str, compute):
        start = time.perf_counter()
        result = compute()
        self.timings[name] = {"seconds": time.perf_counter() - start, "settings": settings}
        return result

    def variant(self, name: str, **options) -> Scene:
        """The scene ``name`` as this report runs it (coarser when quick), with the study's
        ``options`` changed."""
        scene = paper_scene(name)
        quick = {"fig2-fig3.toml": {"frequency_hz": self.grid_hz},
                 "backbone.toml": {"options": {"points": QUICK_BACKBONE_POINTS}},
                 "comparison.toml": {"frequency_hz": self.grid_hz,
                                     "options": {"orders": QUICK_ORDERS}},
                 WORK_PRECISION_SCENE: {"options": {"quick": True}}}
        changes = quick.get(name, {}) if self.quick else {}
        if not changes and not options:
            return scene
        options = {**scene.options, **changes.pop("options", {}), **options}
        return replace(scene, options=options, **changes)

    def _submit(self, executor: Executor, name: str) -> Future | list[Future]:
        """Hand the scene ``name`` to ``executor``: one job, or the work-precision study's
        jobs, one per method, writing no file (``merged_work_precision``)."""
        if name != WORK_PRECISION_SCENE:
            return executor.submit(run_job, self.variant(name), self.out)
        return [executor.submit(run_job, self.variant(name, method=method), None)
                for method in WORK_PARTS]

    def start(self, executor: Executor, names: Iterable[str] = SCENE_FILES) -> None:
        """Hand the scenes ``names`` (default: all) to ``executor``, one job each (the
        work-precision study: one per method, ``_submit``), in the order of ``SCENE_FILES``.

        The kernels the scenes share are compiled first, each by one worker at once
        (with an empty cache, every worker would otherwise compile each of them); the
        scenes of ``KERNEL_FREE`` and the series' formulas go meanwhile to a worker that
        is free, the other scenes once the kernels are compiled. Kernels already built
        are loaded here, before the first task forks the workers, which then find them
        loaded (numba's start and the loads, some 0.5 s, once instead of in each
        process; this process needs them too, for the linear check); the scenes of
        ``KERNEL_FREE`` then run meanwhile in a process forked before the loading.
        """
        names = set(names)
        wanted = [name for name in SCENE_FILES
                  if name in names and name not in self.runs | self._started]
        built = [model for model in self.kernel_models if kernels_built(model)]
        kernel_free = [name for name in wanted if name in KERNEL_FREE]
        if len(built) == len(self.kernel_models) and kernel_free and forks():
            forked = ForkedJobs(run_job, {name: (self.variant(name), self.out)
                                          for name in kernel_free})
            self._started |= {name: forked.future(name) for name in kernel_free}
            self.forked.append(forked)
            wanted = [name for name in wanted if name not in kernel_free]
        for model in built:
            compiled_kernels(model)
        compiled = [executor.submit(_compile, model) for model in self.kernel_models
                    if model not in built]
        # With nothing to compile, the scenes go longest first; else those that need no
        # kernels and the formulas go first, to the worker that compiles the least.
        early = [name for name in wanted if name in KERNEL_FREE] if compiled else []
        for name in early:
            self._started[name] = self._submit(executor, name)
        if compiled and {WORK_PRECISION_SCENE, "comparison.toml"} & set(wanted):
            self.background.append(executor.submit(_derive_formulas))
        for done in compiled:
            done.result()
        for name in [name for name in wanted if name not in early]:
            self._started[name] = self._submit(executor, name)

    def check_background(self) -> None:
        """Wait for the background tasks; raise the error of one that failed. Join the
        forked processes (their results are received by then)."""
        for task in self.background:
            task.result()
        for forked in self.forked:
            forked.join()

    def _run(self, timing: str, settings: str, *names: str) -> list[SceneRun]:
        """The runs of the scenes ``names`` (waited for, or run here), timed as ``timing``:
        the time each took with its figures, wherever it ran."""
        jobs = []
        for name in names:
            started = self._started.pop(name, None)
            if isinstance(started, list):
                job = merged_work_precision([part.result() for part in started],
                                            self.variant(name), self.out)
            elif started is not None:
                job = started.result()
            else:
                job = run_job(self.variant(name), self.out)
            self.runs[name] = job.run
            if job.figure_seconds is not None:
                self.figure_seconds[name] = job.figure_seconds
            jobs.append(job)
        self.timings[timing] = {"seconds": sum(j.seconds for j in jobs), "settings": settings}
        return [job.run for job in jobs]

    @cached_property
    def info(self) -> dict:
        return eq26_numbers().as_dict()

    @cached_property
    def grid_hz(self) -> np.ndarray:
        # The paper's band on a 5 Hz grid, the grid of scenes/fig2-fig3.toml and
        # comparison.toml (tests/test_paper_checks.py holds them equal); 10 Hz when quick,
        # and then given to those scenes.
        step = QUICK_STEP_HZ if self.quick else 5.0
        return np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + step / 2, step)

    @cached_property
    def sweep(self):
        """Fig. 2 and 3: ten amplitudes, swept up and down (scenes/fig2-fig3.toml)."""
        run, = self._run(
            "sweep (Fig. 2, 3)",
            f"scenes/fig2-fig3.toml: {len(PAPER_PANEL_FRACTIONS)} amplitudes x up/down x "
            f"{self.grid_hz.size} points; 128 steps/period, tol 1e-6 (App within 0.5 %); "
            "with its figures", "fig2-fig3.toml")
        return run.outcomes[0]

    @cached_property
    def censuses(self) -> dict:
        """Section 3.3: {point: Census}, one scene per point of COEXISTENCE_POINTS."""
        runs = self._run("attractor censuses", "scenes/census-*.toml: 98 initial states each; "
                         "128 steps/period, tol 1e-6; with their figures",
                         *(CENSUS_SCENES[point] for point in COEXISTENCE_POINTS))
        return {point: run.outcomes[0] for point, run in zip(COEXISTENCE_POINTS, runs)}

    @cached_property
    def tiny_force(self):
        """Steady states at P_a = 1e-3 Q over the band (Section 3.1: linear resonance)."""
        f = self.grid_hz[::4]
        return self._timed(
            "linear check (1e-3 Q)", f"{f.size} frequencies from rest",
            lambda: steady_states(f, TINY_FORCE_FRAC * PAPER.Q_n),
        )

    @cached_property
    def heights(self):
        """Fig. 4: the natural frequency against the body's height (scenes/fig4.toml)."""
        run, = self._run("natural frequency (Fig. 4)",
                         "scenes/fig4.toml: 100 heights, closed form; with its figure",
                         "fig4.toml")
        return run.outcomes[0]

    @cached_property
    def hysteresis(self):
        """Fig. 5: the hysteresis loop at 1600 Hz, 0.40Q (scenes/fig5.toml)."""
        run, = self._run("hysteresis loop (Fig. 5)",
                         "scenes/fig5.toml: 400 periods, 512 steps/period; with its figure",
                         "fig5.toml")
        return run.outcomes[0]

    @cached_property
    def backbone(self):
        points = self.variant("backbone.toml").options["points"]
        run, = self._run("exact backbone", f"scenes/backbone.toml: {points} energy levels, "
                         "period quadrature; with its figure", "backbone.toml")
        return run.outcomes[0]

    @cached_property
    def comparison(self):
        """Series of orders 2..8 against the exact backbone and RK4 (Eq. 2.6 and full)."""
        orders = tuple(self.variant("comparison.toml").options["orders"])
        run, = self._run(
            "analytic against numerical", f"scenes/comparison.toml: orders {orders}, "
            f"P_a = 0.05, 0.10, 0.15 Q, {self.grid_hz.size} frequencies, up and down, both "
            "models; with its figure", "comparison.toml")
        return run.outcomes[0]

    @cached_property
    def work_precision(self) -> WorkPrecision:
        """What accuracy costs (scenes/work-precision.toml); its measurement is the text."""
        parts = isinstance(self._started.get(WORK_PRECISION_SCENE), list)
        run, = self._run("accuracy against time",
                         "scenes/work-precision.toml: every point measured"
                         + (f"; {len(WORK_PARTS)} jobs at once, one per method, their times "
                            "summed" if parts else ""), WORK_PRECISION_SCENE)
        return WorkPrecision.from_text(run.text)

    @cached_property
    def series(self):
        return self._timed("perturbation series, order 4", "symbolic derivation (sympy)",
                           lambda: derive(4, "paper"))

    def run_scenes(self) -> dict[str, SceneRun]:
        """Run every scene not run yet; {scene file: SceneRun}."""
        for name in ("sweep", "heights", "hysteresis", "backbone", "comparison", "censuses",
                     "work_precision"):
            getattr(self, name)
        return self.runs
