"""The contact itself, against the paper's measurements (Fig. 4 and Fig. 5).

- ``natural_frequency``: Fig. 4, the natural frequency of a steel body against its height;
- ``hysteresis``: Fig. 5, the loop of y against the contact pressure.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "HeightSweep": ".natural_frequency",
    "natural_frequency_vs_height": ".natural_frequency",
    "HysteresisLoop": ".hysteresis",
    "hysteresis_loop": ".hysteresis",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "HeightSweep",
    "HysteresisLoop",
    "hysteresis_loop",
    "natural_frequency_vs_height",
]
