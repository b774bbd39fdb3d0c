"""Analytic against numerical: the series of each order against the simulator.

- ``study``: ``compare``, backbones and forced responses order by order (``Comparison``);
- ``backbones``: the backbone series of every order against the exact backbone;
- ``responses``: the analytic forced response of each order against RK4 steady states;
- ``root_stability``: ``series_stability``, the Floquet multipliers of the orbits the
  series' roots describe;
- ``table``: the comparison as ``python -m numerics compare`` prints it.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "Comparison": ".study",
    "compare": ".study",
    "SeriesBranchStability": ".root_stability",
    "SeriesStability": ".root_stability",
    "series_stability": ".root_stability",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Comparison",
    "SeriesBranchStability",
    "SeriesStability",
    "compare",
    "series_stability",
]
