"""A new figure, and saving it: shared by the plotting functions."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

__all__ = ["new_figure", "finish"]


def new_figure(size=(6.0, 4.2)) -> tuple[Figure, object]:
    """A figure with one axes; pyplot is never touched, so no backend is switched."""
    figure = Figure(figsize=size, layout="constrained")
    return figure, figure.add_subplot()


def finish(figure: Figure, path: str | Path | None) -> Figure:
    """Save ``figure`` to ``path`` (format from its suffix) when given; return it."""
    if path is not None:
        figure.savefig(path, dpi=150)
    return figure
