"""Every figure of the report: the scenes' files, and the one no scene draws.

The paper's figures are drawn by their scenes (``paper_checks/scenes``) as they run;
the work-precision figure is drawn beside its scene (``_scene.run_job``, or
``_scene.merged_work_precision`` from its parts) by
``plot_work_precision``, from its result (matplotlib Agg, no pyplot).
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from numerics.plots.figure import finish, fixed_layout

from .scene import CENSUS_SCENES, WORK_PRECISION_FIGURE, WORK_PRECISION_SCENE, PaperScene
from .work_precision import WorkPrecision

__all__ = ["draw_figures", "plot_work_precision", "SCENE_FIGURES"]

#: The report's figures that scenes draw: caption -> (scene file, figure kind).
SCENE_FIGURES = {
    "Fig. 2: A_pp against f_e, ten amplitudes, up and down": ("fig2-fig3.toml", "app"),
    "Fig. 3: local extrema against f_e (minima light, maxima dark grey)": (
        "fig2-fig3.toml", "extrema"),
    "Fig. 4: natural frequency against the height of steel bodies": (
        "fig4.toml", "natural_frequency"),
    "Fig. 5: hysteresis loop at 1600 Hz, 0.40Q": ("fig5.toml", "hysteresis"),
    "The exact backbone (period quadrature)": ("backbone.toml", "backbone"),
    "Analytic against numerical: backbones and resonance curves": (
        "comparison.toml", "comparison"),
    **{f"Coexisting steady states at {point}": (scene, "census")
       for point, scene in CENSUS_SCENES.items()},  # Section 3.3
}


def plot_work_precision(result: WorkPrecision, path=None) -> Figure:
    """Error against time, log-log, one line per method, each point labelled."""
    figure = Figure(figsize=(6.4, 4.6))
    ax = figure.add_subplot()
    styles = {"RK4": "o-", "series": "s-", "DOP853": "^--"}
    for method in result.methods:
        seconds = np.asarray(method.seconds)
        errors = np.maximum(np.asarray(method.errors), 1e-16)
        ax.loglog(seconds, errors, styles.get(method.name, "o-"),
                  label=f"{method.name} ({method.setting})")
        for s, e, label in zip(seconds, errors, method.settings):
            ax.annotate(f"{label:g}", (s, e), fontsize=6, xytext=(3, 3),
                        textcoords="offset points")
    ax.set_xlabel("wall time [s] (best of 3; DOP853: one run)")
    ax.set_ylabel("largest relative error of A_pp")
    ax.set_title("What accuracy costs", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    # The margins [in] as constrained layout placed them (2026-11-23).
    fixed_layout(figure, [[ax]], right=0.074, top=0.232, bottom=0.501)
    return finish(figure, path)


def draw_figures(scene: PaperScene) -> dict[str, str]:
    """Run every scene not run yet (each draws its figures into ``scene.out``, the
    work-precision scene its figure too); return {caption: file name}."""
    if scene.out is None:
        raise ValueError("`scene.out` is None: the scenes draw their figures into it.")
    runs = scene.run_scenes()
    figures = {}
    # The figure kind `work_precision` has no drawer in numerics.scenes: drawn beside it.
    captions = {**SCENE_FIGURES, "What accuracy costs (work-precision)": (
        WORK_PRECISION_SCENE, None)}
    for caption, (name, kind) in captions.items():
        file = runs[name].settings["figures"][kind] if kind else WORK_PRECISION_FIGURE
        if file not in runs[name].files:
            raise RuntimeError(f"scene {name} did not write {file} (wrote {runs[name].files})")
        figures[caption] = file
    scene.timings["figures"] = {"seconds": scene.figure_seconds[WORK_PRECISION_SCENE],
                                "settings": "1 PNG file (the scenes draw the other "
                                            f"{len(SCENE_FIGURES)})"}
    return figures
