"""Every figure of the report, drawn from result objects (matplotlib Agg, no pyplot)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from numerics import hysteresis_loop, natural_frequency_vs_height
from numerics.plots import (
    plot_app,
    plot_backbone,
    plot_census,
    plot_comparison,
    plot_extrema,
    plot_hysteresis,
    plot_natural_frequency,
)
from perturb import PAPER_HYSTERESIS_POINT

from ._scene import PaperScene
from ._work_precision import WorkPrecision

__all__ = ["draw_figures", "plot_work_precision"]



def plot_work_precision(result: WorkPrecision, path=None) -> Figure:
    """Error against time, log-log, one line per method, each point labelled."""
    figure = Figure(figsize=(6.4, 4.6), layout="constrained")
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
    if path is not None:
        figure.savefig(path, dpi=150)
    return figure


def draw_figures(scene: PaperScene, work: WorkPrecision | None, out: Path) -> dict[str, str]:
    """Draw every figure into ``out``; return {caption: file name}."""
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    figures = {
        "Fig. 2: A_pp against f_e, ten amplitudes, up and down": (
            "fig2-app.png", lambda p: plot_app(scene.sweep, p)),
        "Fig. 3: local extrema against f_e (minima light, maxima dark grey)": (
            "fig3-extrema.png", lambda p: plot_extrema(scene.sweep, p)),
        "Fig. 4: natural frequency against the height of steel bodies": (
            "fig4-natural-frequency.png",
            lambda p: plot_natural_frequency(natural_frequency_vs_height(), p)),
        "Fig. 5: hysteresis loop at 1600 Hz, 0.40Q": (
            "fig5-hysteresis.png",
            lambda p: plot_hysteresis(hysteresis_loop(*PAPER_HYSTERESIS_POINT), p)),
        "The exact backbone (period quadrature)": (
            "backbone.png", lambda p: plot_backbone(scene.backbone, p)),
        "Analytic against numerical: backbones and resonance curves": (
            "analytic-vs-numerical.png", lambda p: plot_comparison(scene.comparison, p)),
    }
    for name, census in scene.censuses.items():
        slug = name.split(",")[0].replace(" ", "").lower()
        figures[f"Coexisting steady states at {name}"] = (
            f"census-{slug}.png", lambda p, c=census: plot_census(c, p))
    if work is not None:
        figures["What accuracy costs (work-precision)"] = (
            "work-precision.png", lambda p: plot_work_precision(work, p))
    for file, draw in figures.values():
        draw(out / file)
    scene.timings["figures"] = {"seconds": time.perf_counter() - start,
                                "settings": f"{len(figures)} PNG files"}
    return {caption: file for caption, (file, _) in figures.items()}
