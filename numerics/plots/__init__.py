"""Figures drawn from the result objects of ``numerics``, kept out of its core.

Each function takes a result (``Backbone``, ``HeightSweep``, ``HysteresisLoop``,
``Comparison``, ...), draws on a new matplotlib ``Figure`` (no pyplot, no global
state; PNG through Agg) and, given ``path``, saves it there.

The figures and animations of scenes take plain numpy arrays (SI units) instead:
``plot_spectrum``, ``plot_phase_portrait``, ``plot_time_history`` and
``plot_contact_fraction`` return a ``Figure``; ``animate_slider`` and
``animate_sweep`` write a GIF and return its path.
"""

from ._animation import animate_slider, animate_sweep
from ._backbone import plot_backbone
from ._census import plot_census
from ._compare import plot_comparison
from ._hysteresis import plot_hysteresis
from ._natural_frequency import plot_natural_frequency
from ._observables import (
    plot_contact_fraction,
    plot_phase_portrait,
    plot_spectrum,
    plot_time_history,
)
from ._sweep import plot_app, plot_extrema

__all__ = [
    "animate_slider",
    "animate_sweep",
    "plot_app",
    "plot_backbone",
    "plot_census",
    "plot_comparison",
    "plot_contact_fraction",
    "plot_extrema",
    "plot_hysteresis",
    "plot_natural_frequency",
    "plot_phase_portrait",
    "plot_spectrum",
    "plot_time_history",
]
