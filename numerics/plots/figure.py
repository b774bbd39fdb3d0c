"""A new figure, and saving it: shared by the plotting functions."""

from __future__ import annotations

import functools
import os
import weakref
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.mathtext import MathTextParser
from matplotlib.ticker import Locator

from perturb.common import replacing

__all__ = ["new_figure", "finish", "panel_title", "fixed_layout", "DPI", "EDGE_PAD_IN"]

#: Resolution of the saved figures [dots per inch].
DPI = 150
#: Room left of a y axis for its label and pads, beside its widest tick label [in]:
#: constrained layout left 0.328 to 0.340 in there on the report's figures (10 pt
#: labels), measured 2026-11-23.
Y_LABEL_ROOM_IN = 0.335
#: Constrained layout's padding around each axes and at the figure's edge [in] (3 pt).
EDGE_PAD_IN = 3 / 72
#: The mathtext parser of every renderer here (``_share_mathtext``).
_MATHTEXT = MathTextParser("path")


def new_figure(size=(6.0, 4.2), layout: str | None = "constrained") -> tuple[Figure, object]:
    """A figure with one axes; pyplot is never touched, so no backend is switched.

    ``layout=None`` leaves the axes to be placed by ``fixed_layout``.
    """
    figure = Figure(figsize=size, layout=layout)
    return figure, figure.add_subplot()


#: The callers' figures that plot functions drew on (``ax=``): ``finish`` saves them as
#: they are, with ``savefig``, and leaves their canvas, layout and other axes alone.
_CALLERS: weakref.WeakSet = weakref.WeakSet()


def on_axes(ax, size=(6.0, 4.2), layout: str | None = "constrained") -> tuple[Figure, object]:
    """The figure and axes a plot function draws on: ``ax`` (a panel of the caller's own
    figure, laid out by the caller) and its figure, or a new figure with one axes."""
    if ax is None:
        return new_figure(size, layout)
    _CALLERS.add(ax.figure)
    return ax.figure, ax


def on_panels(ax, count: int, what: str):
    """The caller's axes for a figure of ``count`` panels (``ax``: a sequence of at
    least that many axes of one figure, one per ``what``, in order), as (figure, the
    axes as a grid of one row), or None when ``ax`` is None (the plot makes its own)."""
    if ax is None:
        return None
    axes = np.asarray(ax, dtype=object).ravel()
    if axes.size < count:
        raise ValueError(f"`ax` must hold one axes per {what} ({count}), got {axes.size}.")
    _CALLERS.add(axes[0].figure)
    return axes[0].figure, axes[:count].reshape(1, count)


def panel_title(ax, text: str, **kwargs) -> None:
    """Title ``ax`` just above its top edge, where matplotlib would put it anyway.

    For panels with no ticks and no offset text on top (log y axes, or linear ones in
    nm). Left to itself, matplotlib looks for such decorations at every layout pass,
    updating every tick of the axes to find none; ``tests/benchmarks/bench_paper.py``
    times what that costs the Fig. 2 figure, and ``tests/test_plots.py`` holds the
    files equal.
    """
    ax.set_title(text, y=1.0, **kwargs)


def fixed_layout(figure: Figure, grid, *, right: float, top: float, bottom: float,
                 row_gap: float = 0.0) -> None:
    """Place a grid of axes of equal size, margins given in inches, without a layout engine.

    ``grid`` holds the axes by row and column. Each column starts
    ``Y_LABEL_ROOM_IN`` plus its widest y tick label right of the column before it
    (that one's right margin ``right`` and a pad between): the part of a margin that
    depends on the data. ``top`` (titles), ``bottom`` (x tick labels and label) and
    ``row_gap`` hold text of fixed height, measured for each figure on its constrained
    layout. Constrained layout measures every tick label of every axes in two passes
    to find the same places; ``tests/test_plots.py`` checks that no label leaves the
    figure or overlaps another axes, and ``bench_paper.py`` times the difference.
    """
    grid = np.asarray(grid, dtype=object).reshape(np.shape(grid)[0], -1)
    width, height = figure.get_size_inches()
    figure.set_layout_engine(None)
    lefts = [Y_LABEL_ROOM_IN + max(_widest_tick_label_in(ax.yaxis) for ax in column
                                   if ax.get_visible()) for column in grid.T]
    gaps = [right + EDGE_PAD_IN + left for left in lefts[1:]]
    axes_width = (width - lefts[0] - right - sum(gaps)) / grid.shape[1]
    axes_height = (height - top - bottom - row_gap * (grid.shape[0] - 1)) / grid.shape[0]
    x0 = np.cumsum([lefts[0], *(axes_width + gap for gap in gaps)])
    for row, axes in enumerate(grid):
        y0 = height - top - axes_height - row * (axes_height + row_gap)
        for ax, x in zip(axes, x0):
            ax.set_position([x / width, y0 / height, axes_width / width, axes_height / height])


def _widest_tick_label_in(axis) -> float:
    """Width of the widest tick label ``axis`` will draw [in], major or minor (a log
    axis over less than a decade labels minor ticks), from its locators and formatters
    alone: no tick objects."""
    from matplotlib import rcParams
    from matplotlib.font_manager import FontProperties

    low, high = sorted(axis.get_view_interval())
    slack = 1e-9 * (high - low)  # a tick this close to an end is drawn
    labels = []
    for ticker in (axis.major, axis.minor):
        values = [v for v in ticker.locator() if low - slack <= v <= high + slack]
        labels += ticker.formatter.format_ticks(values)
    # Measured at DPI, as the PNG draws them: matplotlib keeps what it parsed of the
    # mathtext labels (10^n) for the drawing.
    renderer, font = _measuring_renderer(), FontProperties(
        size=rcParams[f"{axis.axis_name}tick.labelsize"])
    widths = [renderer.get_text_width_height_descent(label, font,
                                                     ismath=label.count("$") >= 2)[0]
              for label in labels if label]
    return max(widths, default=0.0) / DPI  # pixels to inches


@functools.cache
def _measuring_renderer():
    """An Agg renderer at ``DPI`` that measures text with the shared mathtext parser."""
    from matplotlib.backends.backend_agg import RendererAgg

    renderer = RendererAgg(1, 1, DPI)
    _share_mathtext(renderer)
    return renderer


def _own_parser_after_fork() -> None:
    """Give a forked child a parser (and a measuring renderer) of its own.

    The shared parser keeps FreeType fonts, and a font reads its file through a file
    descriptor that a forked child shares with its parent, offset and all: a child
    parsing with the parent's fonts moved the parent's reads ("FT_Load_Glyph ...
    invalid outline" in the parent, tests/test_paper_checks.py, once). matplotlib
    clears its own font cache in a forked child for the same reason."""
    global _MATHTEXT
    _MATHTEXT = MathTextParser("path")
    _measuring_renderer.cache_clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_own_parser_after_fork)


def _share_mathtext(renderer) -> None:
    """Give ``renderer`` the mathtext parser of every renderer here.

    matplotlib keeps what it parsed of a label ($10^{3}$) per parser, and gives each
    renderer a parser of its own: every figure, and every axis measured by
    ``fixed_layout``, parsed its labels again. ``tests/test_plots.py`` holds the files
    equal and counts the parses; ``bench_paper.py`` times it on Fig. 2.
    """
    renderer.mathtext_parser = _MATHTEXT


def finish(figure: Figure, path: str | Path | None) -> Figure:
    """Save ``figure`` to ``path`` (format from its suffix) when given; return it.

    The figure is laid out with fewer tick objects and tick updates (the spines that
    tick labels cover stay out of the layout; log axes keep only the minor ticks in
    view). A PNG is drawn once on an Agg canvas (the layout, then the pixels), its
    mathtext labels parsed once for all figures, and written from its buffer:
    ``savefig`` would first run a draw of its own, without pixels, to lay the figure
    out. The report's nine PNG files are byte for byte
    those ``savefig`` wrote without these changes (``tests/test_plots.py`` holds
    Fig. 2 and 3 to it); ``tests/benchmarks/bench_paper.py`` times each change.
    """
    if figure in _CALLERS:  # the caller's figure: saved as it is, if asked
        if path is not None:
            figure.savefig(path, dpi=DPI)
        return figure
    _spines_out_of_layout(figure)
    _minor_log_ticks_in_view(figure)
    if path is None:
        return figure
    if not isinstance(path, (str, os.PathLike)):  # a file object: matplotlib's to write
        figure.savefig(path, dpi=DPI)
        return figure
    suffix = Path(path).suffix.lower()
    with replacing(path) as target:  # whole or not at all, never through a symlink
        if suffix in (".png", ""):  # no suffix: PNG, matplotlib's default format
            _write_png(figure, target)
        else:  # the format told by the name asked for, not by the temporary one's
            figure.savefig(target, dpi=DPI, format=suffix[1:])
    return figure


def _spines_out_of_layout(figure: Figure) -> None:
    """Lay the figure out without the spines whose extent the tick labels cover.

    To measure a spine, constrained layout updates every tick of its axis, at each
    of its two passes. Only the left spine has tick marks there, and the y tick
    labels beyond them set the margin; the bottom spine stays in, for the tick marks
    of panels whose x tick labels are hidden.
    """
    for ax in figure.axes:
        for side in ("left", "right", "top"):
            ax.spines[side].set_in_layout(False)


class _InView(Locator):
    """The locations of ``locator`` inside the view of its axis.

    A log axis's minor locator also gives the ticks of the decades on either side of
    the view, which matplotlib makes into tick objects, updates at every layout
    pass and then leaves out of the drawing as outside.
    """

    def __init__(self, locator: Locator) -> None:
        self.locator = locator

    def set_axis(self, axis) -> None:
        super().set_axis(axis)
        self.locator.set_axis(axis)

    def __call__(self):
        locations = np.asarray(self.locator())
        low, high = sorted(self.axis.get_view_interval())
        slack = 1 + 1e-9  # a tick this close to an end is drawn, as matplotlib does
        return locations[(locations >= low / slack) & (locations <= high * slack)]

    def tick_values(self, vmin, vmax):
        return self.locator.tick_values(vmin, vmax)


def _minor_log_ticks_in_view(figure: Figure) -> None:
    """Give every log axis only the minor ticks it draws (the files are the same)."""
    for ax in figure.axes:
        for axis in (ax.xaxis, ax.yaxis):
            minor = axis.get_minor_locator()
            if axis.get_scale() == "log" and not isinstance(minor, _InView):
                axis.set_minor_locator(_InView(minor))


def _write_png(figure: Figure, path: str | Path) -> None:
    """Draw ``figure`` at ``DPI`` on an Agg canvas and write its pixels as a PNG file."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.image import imsave

    canvas = FigureCanvasAgg(figure)
    dpi = figure.dpi
    figure.set_dpi(DPI)
    try:
        _share_mathtext(canvas.get_renderer())  # kept by draw: the size is the same
        canvas.draw()  # the layout engine runs here, once
        imsave(path, canvas.buffer_rgba(), format="png", origin="upper", dpi=DPI)
    finally:
        figure.set_dpi(dpi)
