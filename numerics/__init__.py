"""numerics: a compiled, batched RK4 of the contact model and what is built on it.

The right-hand side is generated from ``perturb.ContactModel`` for the effects a
scene asks for; see ``simulate``. Every result object keeps the contract of
``common.Result`` (its model and settings, strict JSON, ``load``).
"""

from common import Status, lazy_names, load

# Every name is imported at first use (PEP 562), so that a command loads only what
# it runs: scipy.optimize (the backbone), sympy (what derives) and the scenes stay
# out of `python -m numerics sweep`.
_LAZY = {
    "Attractor": "._attractors",
    "Census": "._attractors",
    "attractors": "._attractors",
    "Backbone": "._backbone",
    "exact_backbone": "._backbone",
    "acceleration_source": "._codegen",
    "compiled_kernels": "._codegen",
    "Bifurcation": "._continuation",
    "Continuation": "._continuation",
    "ContinuedBranch": "._continuation",
    "continue_orbits": "._continuation",
    "Comparison": "._compare",
    "compare": "._compare",
    "HysteresisLoop": "._hysteresis",
    "hysteresis_loop": "._hysteresis",
    "drive_table": "._lanes",
    "HeightSweep": "._natural_frequency",
    "natural_frequency_vs_height": "._natural_frequency",
    "Orbits": "._orbits",
    "reference_last_period": "._reference",
    "RECORDABLE": "._simulate",
    "simulate": "._simulate",
    "Simulation": "._simulation",
    "SeriesBranchStability": "._series_stability",
    "SeriesStability": "._series_stability",
    "series_stability": "._series_stability",
    "SteadyStates": "._steady",
    "steady_states": "._steady",
    "Sweep": "._sweep",
    "SweepRun": "._sweep",
    "sweep": "._sweep",
    "SceneRun": ".scenes",
    "read_scene": ".scenes",
    "run_scene": ".scenes",
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())


__all__ = [
    "Attractor",
    "Backbone",
    "Bifurcation",
    "Census",
    "Comparison",
    "Continuation",
    "ContinuedBranch",
    "HeightSweep",
    "HysteresisLoop",
    "Orbits",
    "RECORDABLE",
    "SceneRun",
    "SeriesBranchStability",
    "SeriesStability",
    "Simulation",
    "Status",
    "SteadyStates",
    "Sweep",
    "SweepRun",
    "acceleration_source",
    "attractors",
    "compare",
    "compiled_kernels",
    "continue_orbits",
    "drive_table",
    "exact_backbone",
    "hysteresis_loop",
    "load",
    "natural_frequency_vs_height",
    "read_scene",
    "reference_last_period",
    "run_scene",
    "series_stability",
    "simulate",
    "steady_states",
    "sweep",
]
