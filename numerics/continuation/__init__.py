"""Continuation: periodic orbits followed through their folds, with their stability.

- ``period_map``: the scaled period map walked along (``PeriodMap``; ``ForceMap`` makes
  the force amplitude the continuation parameter) and its corrector;
- ``walk``: the walks' one engine (``ArclengthWalk``: the pseudo-arclength step, Brent's
  method for the events between two points, the edges) and ``continue_orbits``, the walk
  in f_e, with folds and period doublings located;
- ``force``: ``continue_in_force``, the walk in P_a at one f_e;
- ``branch_switch``: ``switch_branch``, the period-2p branch born at a period doubling;
- ``folds``: ``fold_curves``, folds continued in the (f_e, P_a) plane, with their cusps;
- ``options``: ``WalkOptions``, the tuning every walk takes (step control, corrector).
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "Bifurcation": ".walk",
    "Continuation": ".walk",
    "ContinuedBranch": ".walk",
    "continue_orbits": ".walk",
    "ForceContinuation": ".force",
    "continue_in_force": ".force",
    "switch_branch": ".branch_switch",
    "Cusp": ".folds",
    "FoldCurve": ".folds",
    "FoldCurves": ".folds",
    "fold_curves": ".folds",
    "PeriodMap": ".period_map",
    "ForceMap": ".period_map",
    "Point": ".period_map",
    "WalkOptions": ".options",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Bifurcation",
    "Continuation",
    "ContinuedBranch",
    "Cusp",
    "FoldCurve",
    "FoldCurves",
    "ForceContinuation",
    "ForceMap",
    "PeriodMap",
    "Point",
    "WalkOptions",
    "continue_in_force",
    "continue_orbits",
    "fold_curves",
    "switch_branch",
]
