"""Figures drawn from the result objects of ``numerics``, kept out of its core.

Each function takes a result (``Backbone``, ``HeightSweep``, ``HysteresisLoop``,
``Comparison``, ...), draws on a new matplotlib ``Figure`` (no pyplot, no global
state; PNG through Agg) and, given ``path``, saves it there.
"""

from ._backbone import plot_backbone
from ._census import plot_census
from ._compare import plot_comparison
from ._hysteresis import plot_hysteresis
from ._natural_frequency import plot_natural_frequency
from ._sweep import plot_app, plot_extrema

__all__ = [
    "plot_app",
    "plot_backbone",
    "plot_comparison",
    "plot_census",
    "plot_extrema",
    "plot_hysteresis",
    "plot_natural_frequency",
]
