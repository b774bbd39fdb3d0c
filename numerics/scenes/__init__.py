"""Scenes: one study, figure or lesson written as data, and run with only what it needs.

A scene is a TOML file (``read_scene``; nothing in it is evaluated) that names the
model, its effects (or ``"auto"``), the excitation, the study, the observables,
the tolerance and the outputs; ``run_scene`` runs it (``python -m numerics scene``).
See ``docs/scenes.md`` for the keys.
"""

from .auto import Selection, observable_change, select_effects
from .observables import contact_fraction, harmonic_amplitudes
from .result import SceneRun
from .run import run_scene
from .schema import (
    NAMED_EFFECTS,
    OBSERVABLES,
    STUDIES,
    Option,
    Scene,
    SceneError,
    Study,
    parse_scene,
    read_scene,
)
from .studies import StudyRun, register_study

__all__ = [
    "NAMED_EFFECTS",
    "OBSERVABLES",
    "Option",
    "STUDIES",
    "Scene",
    "SceneError",
    "SceneRun",
    "Selection",
    "Study",
    "StudyRun",
    "contact_fraction",
    "harmonic_amplitudes",
    "observable_change",
    "parse_scene",
    "read_scene",
    "register_study",
    "run_scene",
    "select_effects",
]
