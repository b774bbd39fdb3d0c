"""The analytic frequency response of the series, and the orbits its roots describe.

- ``frequency``: ``frequency_response``, the roots of the series at each frequency,
  by the compiled route or in numpy (``numpy_route``);
- ``codegen`` and ``template``: the order-N kernels, generated and cached per order;
- ``orbit``: ``series_orbits``, a root's orbit as the simulator sees an orbit.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "Branch": ".frequency",
    "Response": ".frequency",
    "frequency_response": ".frequency",
    "SeriesOrbits": ".orbit",
    "series_orbits": ".orbit",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Branch",
    "Response",
    "SeriesOrbits",
    "frequency_response",
    "series_orbits",
]
