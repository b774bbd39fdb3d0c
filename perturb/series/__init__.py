"""The perturbation series of Eq. 2.6 to any order (Eq. 2.7-2.10, A.1, A.2).

- ``lindstedt``: ``derive``, the order-by-order Lindstedt-type derivation, with
  ``harmonics`` (products of cosines) and ``series_symbols`` (the series' names);
- ``truncation``: which terms of the contact's expansion a series keeps;
- ``compiled`` and ``formulas``: the series as fast numeric formulas
  (``compile_series``), from sympy or, for any truncation, from ``numeric`` (the scheme
  on numbers) and ``kernel`` (the same as one numba kernel);
- ``free_backbone``: ``backbone_series``, the free backbone as an exact series;
- ``slow_orders``: the largest order each piece of work takes without asking twice.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "Series": ".lindstedt",
    "derive": ".lindstedt",
    "Truncation": ".truncation",
    "CompiledSeries": ".compiled",
    "compile_series": ".formulas",
    "BackboneSeries": ".free_backbone",
    "backbone_series": ".free_backbone",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "BackboneSeries",
    "CompiledSeries",
    "Series",
    "Truncation",
    "backbone_series",
    "compile_series",
    "derive",
]
