"""numerics: a compiled, batched RK4 of the contact model and what is built on it.

The right-hand side is generated from ``perturb.ContactModel`` for the effects a
scene asks for; see ``simulate``.
"""

from ._attractors import Attractor, Census, attractors
from ._backbone import Backbone, exact_backbone
from ._codegen import acceleration_source, compiled_kernels
from ._compare import Comparison, compare
from ._hysteresis import HysteresisLoop, hysteresis_loop
from ._natural_frequency import HeightSweep, natural_frequency_vs_height
from ._reference import reference_last_period
from ._result import Simulation
from ._simulate import drive_table, simulate, static_deflection
from ._steady import SteadyStates, steady_states
from ._sweep import Sweep, SweepRun, sweep
from ._validate import RECORDABLE

__all__ = [
    "Attractor",
    "Backbone",
    "Census",
    "Comparison",
    "HeightSweep",
    "HysteresisLoop",
    "RECORDABLE",
    "Simulation",
    "SteadyStates",
    "Sweep",
    "SweepRun",
    "acceleration_source",
    "attractors",
    "compare",
    "compiled_kernels",
    "drive_table",
    "exact_backbone",
    "hysteresis_loop",
    "natural_frequency_vs_height",
    "reference_last_period",
    "simulate",
    "static_deflection",
    "steady_states",
    "sweep",
]
