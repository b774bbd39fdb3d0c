"""The exact backbone: the frequency of free, undamped oscillation against amplitude.

- ``exact``: ``exact_backbone``, the period integral evaluated by spectral quadrature;
- ``restoring``: the conservative force in units of the weight, about y0;
- ``chebyshev``: quadrature on Chebyshev-Lobatto points, batched over rows (numpy has
  Chebyshev series but no batched Lobatto quadrature).
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "Backbone": ".exact",
    "exact_backbone": ".exact",
    "Restoring": ".restoring",
    "restoring_force": ".restoring",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Backbone",
    "Restoring",
    "exact_backbone",
    "restoring_force",
]
