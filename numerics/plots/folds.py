"""Fold curves drawn from a ``FoldCurves``: the bistable regions in the (f_e, P_a) plane."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .figure import finish, on_axes

__all__ = ["plot_folds"]

#: One colour per resonance m (0: a curve with no cusp in the box).
_COLOURS = {0: "tab:gray", 1: "tab:red", 2: "tab:blue", 3: "tab:green"}


def plot_folds(folds, path=None, *, ax=None) -> Figure:
    """The fold curves in the (f_e, P_a / Q) plane, one colour per resonance, each
    resonance's bistable region (inside its curve, above its cusp) labelled at its
    lowest cusp, cusps marked; with ``ax``, drawn on it (over an atlas, say)."""
    figure, ax = on_axes(ax, (7.0, 4.2))
    from ..continuation.folds import resonance_name

    labelled = set()
    for curve in folds.fold_curves:
        colour = _COLOURS.get(curve.resonance, "black")
        label = None if curve.resonance in labelled else f"folds, {resonance_name(curve.resonance)}"
        labelled.add(curve.resonance)
        ax.plot(curve.frequency_hz, curve.pa_frac, color=colour, lw=1.2, label=label)
    settings = folds.settings
    ax.set_xlim(settings["fmin_hz"], settings["fmax_hz"])
    top = settings["pa_max"]
    ax.set_ylim(max(0.0, settings["pa_min"] - 0.15 * (top - settings["pa_min"])), top)
    lowest = {}  # each resonance's cusp of least P_a: where it is first bistable
    for cusp in folds.cusps:
        ax.plot([cusp.frequency_hz], [cusp.pa_frac], "v", color=_COLOURS.get(cusp.resonance,
                "black"), ms=6)
        if cusp.resonance not in lowest or cusp.pa_frac < lowest[cusp.resonance].pa_frac:
            lowest[cusp.resonance] = cusp
    for cusp in lowest.values():  # one label each: a resonance's labels would overlap
        ax.annotate(f"{resonance_name(cusp.resonance)}: bistable above\ncusp "
                    f"{cusp.frequency_hz:.1f} Hz, {cusp.pa_frac:.4g} Q",
                    (cusp.frequency_hz, cusp.pa_frac), fontsize=7, textcoords="offset points",
                    **_inside(ax, cusp.frequency_hz, cusp.pa_frac),
                    bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="none", alpha=0.8))
    ax.set_xlabel("f_e [Hz]")
    ax.set_ylabel("P_a / Q")
    ax.set_title("Fold curves of period-1 orbits (cusps: triangles)", fontsize=10)
    ax.grid(True, alpha=0.3)
    if np.any([c.frequency_hz.size for c in folds.fold_curves]):
        ax.legend(fontsize=7, loc="upper right")
    return finish(figure, path)


def _inside(ax, x: float, y: float) -> dict:
    """Where a cusp's label goes so that it stays inside the axes: below the cusp (above
    it near the bottom), centred on it (to its left or right near a side)."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    share_x, share_y = (x - x0) / (x1 - x0), (y - y0) / (y1 - y0)
    ha = "right" if share_x > 0.8 else "left" if share_x < 0.2 else "center"
    low = share_y < 0.25
    return {"xytext": (0, 10 if low else -14), "ha": ha, "va": "bottom" if low else "top"}
