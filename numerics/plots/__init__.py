"""Figures drawn from the result objects of ``numerics``, kept out of its core.

Each function takes a result (``Backbone``, ``HeightSweep``, ``HysteresisLoop``,
``Comparison``, ...), draws on a new matplotlib ``Figure`` (no pyplot, no global
state; PNG through Agg) and, given ``path``, saves it there. Every ``plot_`` function
also takes ``ax=``: it then draws on the caller's axes (one, or one per panel: per
force amplitude, increasing) and leaves the figure's layout to the caller.

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
    "animate_slider": ".animation",
    "animate_sweep": ".animation",
    "plot_atlas": ".atlas",
    "plot_backbone": ".backbone",
    "plot_backbone_truncations": ".backbone",
    "plot_census": ".census",
    "plot_continuation": ".continuation",
    "plot_continued_app": ".continuation",
    "plot_force_continuation": ".continuation",
    "plot_comparison": ".compare",
    "plot_folds": ".folds",
    "plot_hysteresis": ".hysteresis",
    "plot_natural_frequency": ".natural_frequency",
    "plot_contact_fraction": ".observables",
    "plot_phase_portrait": ".observables",
    "plot_spectrum": ".observables",
    "plot_series_stability": ".series_stability",
    "plot_time_history": ".observables",
    "plot_app": ".sweep",
    "plot_extrema": ".sweep",
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
