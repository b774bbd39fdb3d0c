"""Figures drawn from the result objects of ``numerics``, kept out of its core.

Each function takes a result (``Backbone``, ``HeightSweep``, ``HysteresisLoop``,
``Comparison``, ...), draws on a new matplotlib ``Figure`` (no pyplot, no global
state; PNG through Agg) and, given ``path``, saves it there.

The figures and animations of scenes take plain numpy arrays (SI units) instead:
``plot_spectrum``, ``plot_phase_portrait``, ``plot_time_history`` and
``plot_contact_fraction`` return a ``Figure``; ``animate_slider`` and
``animate_sweep`` write a GIF and return its path.
"""

from perturb.common import lazy_names

# Each figure's module is imported at first use (PEP 562): the comparison's and the
# backbone's figures import the exact backbone (scipy.optimize, sympy), which a scene
# drawing a resonance curve does not need.
_LAZY = {
    "animate_slider": "._animation",
    "animate_sweep": "._animation",
    "plot_atlas": "._atlas",
    "plot_backbone": "._backbone",
    "plot_backbone_truncations": "._backbone",
    "plot_census": "._census",
    "plot_continuation": "._continuation",
    "plot_continued_app": "._continuation",
    "plot_force_continuation": "._continuation",
    "plot_comparison": "._compare",
    "plot_folds": "._folds",
    "plot_hysteresis": "._hysteresis",
    "plot_natural_frequency": "._natural_frequency",
    "plot_contact_fraction": "._observables",
    "plot_phase_portrait": "._observables",
    "plot_spectrum": "._observables",
    "plot_series_stability": "._series_stability",
    "plot_time_history": "._observables",
    "plot_app": "._sweep",
    "plot_extrema": "._sweep",
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())


__all__ = [
    "animate_slider",
    "animate_sweep",
    "plot_app",
    "plot_atlas",
    "plot_backbone",
    "plot_backbone_truncations",
    "plot_census",
    "plot_comparison",
    "plot_continuation",
    "plot_continued_app",
    "plot_contact_fraction",
    "plot_extrema",
    "plot_folds",
    "plot_force_continuation",
    "plot_hysteresis",
    "plot_natural_frequency",
    "plot_phase_portrait",
    "plot_series_stability",
    "plot_spectrum",
    "plot_time_history",
]
