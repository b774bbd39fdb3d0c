"""Simulation: a batched, phase-locked RK4 run of the model, and its result.

- ``rk4``: ``simulate``, the entry function (``RECORDABLE``: what it can record);
- ``result``: ``Simulation``, the result object;
- ``reference``: ``reference_last_period``, scipy's DOP853 on the model's own
  expressions, the independent route every RK4 result is checked against;
- ``ranges``: where the simulator's answers are measured to hold.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "simulate": ".rk4",
    "RECORDABLE": ".rk4",
    "Simulation": ".result",
    "reference_last_period": ".reference",
    "TESTED": ".ranges",
    "check_tested": ".ranges",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "RECORDABLE",
    "Simulation",
    "TESTED",
    "check_tested",
    "reference_last_period",
    "simulate",
]
