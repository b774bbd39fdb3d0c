"""The computations the paper's checks share, each done once and timed.

``PaperScene(quick, out)`` computes on first use. The paper's figures are scenes
(``paper_checks/scenes/*.toml``), each run once by ``numerics.scenes.run_scene``,
which writes its figures into ``out`` (none without it): the sweeps of Fig. 2 and 3,
the attractor censuses at the paper's points of multi-stability, Fig. 4, Fig. 5, the
exact backbone, the analytic-against-numerical comparison and the work-precision
study. The linear check and the perturbation series are direct calls. ``quick`` uses
coarser grids (for the tests), in variants of the scenes made by
``dataclasses.replace``.
"""

from __future__ import annotations

import time
from dataclasses import replace
from functools import cached_property
from pathlib import Path

import numpy as np

from numerics import steady_states
from numerics.scenes import Scene, SceneRun, read_scene, run_scene
from perturb import (
    PAPER,
    PAPER_BAND_HZ,
    PAPER_COEXISTENCE,
    PAPER_PANEL_FRACTIONS,
    derive,
    eq26_numbers,
)

from ._work_precision import WorkPrecision

__all__ = ["PaperScene", "COEXISTENCE_POINTS", "SCENES", "CENSUS_SCENES", "paper_scene"]

#: The folder of the paper's scenes.
SCENES = Path(__file__).parent / "scenes"
#: Section 3.3: (f_e [Hz], P_a / Q) where the paper reports coexisting solutions.
COEXISTENCE_POINTS = PAPER_COEXISTENCE
#: The scene of each point of COEXISTENCE_POINTS.
CENSUS_SCENES = {"740 Hz, 0.15Q": "census-740hz.toml", "490 Hz, 0.50Q": "census-490hz.toml"}
#: Section 3.1's "very small amplitude of the excitation force", as P_a / Q.
TINY_FORCE_FRAC = 1e-3
#: Force amplitudes at which the series is compared with RK4 (the series needs contact).
COMPARED_FRACTIONS = (0.05, 0.10, 0.15)


def paper_scene(name: str) -> Scene:
    """The paper's scene ``name`` (a file of ``paper_checks/scenes``), read and checked."""
    return read_scene(SCENES / name)


class PaperScene:
    """Shared, lazily computed results, with the time and settings of each.

    ``runs`` holds each scene's ``SceneRun`` by file name, once it has run.
    """

    def __init__(self, quick: bool = False, out: str | Path | None = None) -> None:
        self.quick = quick
        self.out = None if out is None else Path(out)
        self.timings: dict[str, dict] = {}
        self.runs: dict[str, SceneRun] = {}

    def _timed(self, name: str, settings: str, compute):
        start = time.perf_counter()
        result = compute()
        self.timings[name] = {"seconds": time.perf_counter() - start, "settings": settings}
        return result

    def _run(self, name: str, quick_changes: dict | None = None) -> SceneRun:
        """Run the scene ``name`` (with ``quick_changes`` when quick): its figures go to out."""
        scene = paper_scene(name)
        if self.quick and quick_changes:
            changes = dict(quick_changes)
            options = {**scene.options, **changes.pop("options", {})}
            scene = replace(scene, options=options, **changes)
        self.runs[name] = run_scene(scene, out=self.out)
        return self.runs[name]

    @cached_property
    def info(self) -> dict:
        return eq26_numbers().as_dict()

    @cached_property
    def grid_hz(self) -> np.ndarray:
        # The paper's band on a 5 Hz grid, the grid of scenes/fig2-fig3.toml and
        # comparison.toml (tests/test_paper_checks.py holds them equal); 10 Hz when quick,
        # and then given to those scenes.
        step = 10.0 if self.quick else 5.0
        return np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + step / 2, step)

    @cached_property
    def sweep(self):
        """Fig. 2 and 3: ten amplitudes, swept up and down (scenes/fig2-fig3.toml)."""
        run = self._timed(
            "sweep (Fig. 2, 3)",
            f"scenes/fig2-fig3.toml: {len(PAPER_PANEL_FRACTIONS)} amplitudes x up/down x "
            f"{self.grid_hz.size} points; 128 steps/period, tol 1e-6 (App within 0.5 %); "
            "with its figures",
            lambda: self._run("fig2-fig3.toml", {"frequency_hz": self.grid_hz}))
        return run.outcomes[0]

    @cached_property
    def censuses(self) -> dict:
        """Section 3.3: {point: Census}, one scene per point of COEXISTENCE_POINTS."""
        return self._timed(
            "attractor censuses", "scenes/census-*.toml: 98 initial states each; "
            "128 steps/period, tol 1e-6; with their figures",
            lambda: {point: self._run(CENSUS_SCENES[point]).outcomes[0]
                     for point in COEXISTENCE_POINTS})

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
        run = self._timed("natural frequency (Fig. 4)",
                          "scenes/fig4.toml: 100 heights, closed form; with its figure",
                          lambda: self._run("fig4.toml"))
        return run.outcomes[0]

    @cached_property
    def hysteresis(self):
        """Fig. 5: the hysteresis loop at 1600 Hz, 0.40Q (scenes/fig5.toml)."""
        run = self._timed("hysteresis loop (Fig. 5)",
                          "scenes/fig5.toml: 400 periods, 512 steps/period; with its figure",
                          lambda: self._run("fig5.toml"))
        return run.outcomes[0]

    @cached_property
    def backbone(self):
        points = 60 if self.quick else 200
        run = self._timed("exact backbone", f"scenes/backbone.toml: {points} energy levels, "
                          "period quadrature; with its figure",
                          lambda: self._run("backbone.toml", {"options": {"points": points}}))
        return run.outcomes[0]

    @cached_property
    def comparison(self):
        """Series of orders 2..8 against the exact backbone and RK4 (Eq. 2.6 and full)."""
        orders = (2, 4, 6) if self.quick else (2, 4, 6, 8)
        run = self._timed(
            "analytic against numerical", f"scenes/comparison.toml: orders {orders}, "
            f"P_a = 0.05, 0.10, 0.15 Q, {self.grid_hz.size} frequencies, up and down, both "
            "models; with its figure",
            lambda: self._run("comparison.toml", {"frequency_hz": self.grid_hz,
                                                  "options": {"orders": orders}}))
        return run.outcomes[0]

    @cached_property
    def work_precision(self) -> WorkPrecision:
        """What accuracy costs (scenes/work-precision.toml); its measurement is the text."""
        run = self._timed("accuracy against time",
                          "scenes/work-precision.toml: every point measured",
                          lambda: self._run("work-precision.toml", {"options": {"quick": True}}))
        return WorkPrecision.from_text(run.text)

    @cached_property
    def series(self):
        return self._timed("perturbation series, order 4", "symbolic derivation (sympy)",
                           lambda: derive(4))

    def run_scenes(self) -> dict[str, SceneRun]:
        """Run every scene not run yet; {scene file: SceneRun}."""
        for name in ("sweep", "heights", "hysteresis", "backbone", "comparison", "censuses",
                     "work_precision"):
            getattr(self, name)
        return self.runs
