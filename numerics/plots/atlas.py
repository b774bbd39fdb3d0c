"""The multistability atlas as a map: coexisting attractors per cell of (f_e, P_a)."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.patches import Patch

from perturb.common import Status

from .figure import finish, on_axes

__all__ = ["plot_atlas"]

#: The colour of the cells whose task failed (no count there).
FAILED_COLOUR = "0.55"


def plot_atlas(atlas, path=None, *, folds=None, ax=None):
    """The number of coexisting attractors at each cell, one colour per count, over f_e
    and P_a / Q; cells whose task failed in grey. ``atlas``: a ``numerics.Atlas``;
    ``folds``: a ``numerics.FoldCurves`` drawn over the map."""
    figure, ax = on_axes(ax, (7.0, 4.4))
    counts = np.asarray(atlas.attractor_count)
    failed = np.asarray(atlas.status) == Status.FAILED
    most = max(int(counts.max(initial=0)), 1)
    colours = _count_colours(most)
    x, y = _edges(atlas.frequency_hz), _edges(atlas.pa_frac)
    ax.pcolormesh(x, y, np.ma.masked_where(failed, counts), cmap=ListedColormap(colours),
                  norm=BoundaryNorm(np.arange(-0.5, most + 1), most + 1))
    if failed.any():
        ax.pcolormesh(x, y, np.ma.masked_where(~failed, np.zeros(counts.shape)),
                      cmap=ListedColormap([FAILED_COLOUR]))
    shown = sorted(set(counts[~failed].tolist()))
    handles = [Patch(color=colours[k], label=_count_label(k)) for k in shown]
    if failed.any():
        handles.append(Patch(color=FAILED_COLOUR, label=f"task failed ({int(failed.sum())})"))
    if folds is not None:
        from .folds import plot_folds

        plot_folds(folds, ax=ax)
        handles += ax.get_legend_handles_labels()[0]  # the fold curves, in one legend
        ax.set_xlim(x[0], x[-1])  # the map's extent, not the fold curves' box
        ax.set_ylim(y[0], y[-1])
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              title="attractors", title_fontsize=8)
    ax.set_xlabel("f_e [Hz]")
    ax.set_ylabel("P_a / Q")
    states = atlas.settings.get("initial_states")
    ax.set_title(f"Coexisting attractors ({states} initial states per cell)"
                 + (", fold curves over it" if folds is not None else ""), fontsize=10)
    return finish(figure, path)


def _count_colours(most: int) -> list:
    """White for none found, then one colour per count (a discrete map, darker = more)."""
    from matplotlib import colormaps

    ramp = colormaps["viridis_r"](np.linspace(0.0, 1.0, most))
    return ["white", *ramp]


def _count_label(k: int) -> str:
    return "none settled" if k == 0 else str(k)


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around uniformly spaced centres (a single centre: +-2.5 %, or 0.5)."""
    centres = np.asarray(centres, dtype=float)
    if centres.size == 1:
        half = 0.025 * abs(centres[0]) or 0.5
        return np.array([centres[0] - half, centres[0] + half])
    half = np.diff(centres) / 2
    inner = centres[:-1] + half
    return np.concatenate([[centres[0] - half[0]], inner, [centres[-1] + half[-1]]])
