"""numerics: a compiled, batched RK4 of the contact model and what is built on it.

The right-hand side is generated from ``perturb.ContactModel`` for the effects a
scene asks for; see ``simulate``. Every result object keeps the contract of
``common.Result`` (its model and settings, strict JSON, ``load``).
"""

from common import Status, load

from ._attractors import Attractor, Census, attractors
from ._backbone import Backbone, exact_backbone
from ._codegen import acceleration_source, compiled_kernels
from ._compare import Comparison, compare
from ._hysteresis import HysteresisLoop, hysteresis_loop
from ._lanes import drive_table
from ._natural_frequency import HeightSweep, natural_frequency_vs_height
from ._orbits import Orbits
from ._reference import reference_last_period
from ._simulate import RECORDABLE, simulate
from ._simulation import Simulation
from ._steady import SteadyStates, steady_states
from ._sweep import Sweep, SweepRun, sweep
from .scenes import SceneRun, read_scene, run_scene

__all__ = [
    "Attractor",
    "Backbone",
    "Census",
    "Comparison",
    "HeightSweep",
    "HysteresisLoop",
    "Orbits",
    "RECORDABLE",
    "SceneRun",
    "Simulation",
    "Status",
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
    "load",
    "natural_frequency_vs_height",
    "read_scene",
    "reference_last_period",
    "run_scene",
    "simulate",
    "steady_states",
    "sweep",
]
