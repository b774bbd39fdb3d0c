"""numerics: a compiled, batched RK4 of the contact model and what is built on it.

The verbs, their result objects and the scenes, by concept (each folder's own
``__init__`` says what it holds):

- ``simulation``: ``simulate`` (``Simulation``);
- ``steady``: ``steady_states``, ``sweep``, ``attractor_census``, ``largest_lyapunov``,
  ``atlas``;
- ``continuation``: ``continue_orbits``, ``continue_in_force``, ``switch_branch``,
  ``fold_curves``;
- ``backbone``: ``exact_backbone``; ``contact``: Fig. 4 and Fig. 5;
- ``comparison``: ``compare``, ``series_stability``;
- ``scenes``: ``run_scene``, a study written as a TOML file.

The compiled kernels that all of them run on are in ``kernels``; ``plots`` draws the
results and ``cli`` is the command line. The right-hand side is generated from
``perturb.ContactModel`` for the effects a scene asks for. Every result object keeps
the contract of ``perturb.common.Result`` (its model and settings, strict JSON, ``load``).
"""

from perturb.common import Status, lazy_names, load

# Every name is imported at first use (PEP 562), so that a command loads only what
# it runs: scipy.optimize (the backbone), sympy (what derives) and the scenes stay
# out of `python -m numerics sweep`.
_LAZY = {
    "__version__": ("perturb.common._version", "VERSION"),
    "Atlas": ".steady",
    "atlas": ".steady",
    "Attractor": ".steady",
    "attractor_census": ".steady",
    "attractors": ".steady",  # deprecated: attractor_census
    "Census": ".steady",
    "classify_motion": ".steady",
    "largest_lyapunov": ".steady",
    "LyapunovExponents": ".steady",
    "Orbits": ".steady",
    "steady_states": ".steady",
    "SteadyStates": ".steady",
    "Sweep": ".steady",
    "sweep": ".steady",
    "SweepRun": ".steady",
    "Bifurcation": ".continuation",
    "Continuation": ".continuation",
    "continue_in_force": ".continuation",
    "continue_orbits": ".continuation",
    "ContinuedBranch": ".continuation",
    "Cusp": ".continuation",
    "fold_curves": ".continuation",
    "FoldCurve": ".continuation",
    "FoldCurves": ".continuation",
    "ForceContinuation": ".continuation",
    "switch_branch": ".continuation",
    "WalkOptions": ".continuation",
    "SteadyOptions": ".steady",
    "Backbone": ".backbone",
    "exact_backbone": ".backbone",
    "HeightSweep": ".contact",
    "hysteresis_loop": ".contact",
    "HysteresisLoop": ".contact",
    "natural_frequency_vs_height": ".contact",
    "compare": ".comparison",
    "Comparison": ".comparison",
    "series_stability": ".comparison",
    "SeriesBranchStability": ".comparison",
    "SeriesStability": ".comparison",
    "simulate": ".simulation",
    "Simulation": ".simulation",
    "SceneRun": ".scenes",
    "read_scene": ".scenes",
    "run_scene": ".scenes",
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())


__all__ = [
    "Atlas",
    "Attractor",
    "Backbone",
    "Bifurcation",
    "Census",
    "Comparison",
    "Continuation",
    "ContinuedBranch",
    "Cusp",
    "FoldCurve",
    "FoldCurves",
    "ForceContinuation",
    "HeightSweep",
    "HysteresisLoop",
    "LyapunovExponents",
    "Orbits",
    "SceneRun",
    "SeriesBranchStability",
    "SeriesStability",
    "Simulation",
    "Status",
    "SteadyOptions",
    "SteadyStates",
    "Sweep",
    "SweepRun",
    "WalkOptions",
    "atlas",
    "attractor_census",
    "classify_motion",
    "compare",
    "continue_in_force",
    "continue_orbits",
    "exact_backbone",
    "fold_curves",
    "hysteresis_loop",
    "largest_lyapunov",
    "load",
    "natural_frequency_vs_height",
    "read_scene",
    "run_scene",
    "series_stability",
    "simulate",
    "steady_states",
    "sweep",
    "switch_branch",
]
