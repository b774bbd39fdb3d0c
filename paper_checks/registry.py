"""Every check of the paper's claims, in the order of the report."""

from __future__ import annotations

from .checks_resonances import (
    asymmetry,
    linear_resonance,
    natural_frequency,
    peaks_bend,
    superharmonic_peaks,
)
from .checks_stability import bistability, coexistence_490, coexistence_740, contact_loss
from .checks_theory import frequency_falls, series_structure
from .claims import Claim
from .scene import PaperScene

__all__ = ["CHECKS", "run_claims"]

CHECKS = [
    natural_frequency, linear_resonance, peaks_bend, superharmonic_peaks, bistability,
    contact_loss, coexistence_740, coexistence_490, asymmetry, series_structure,
    frequency_falls,
]


def run_claims(scene: PaperScene | None = None) -> list[Claim]:
    """Check every claim of the paper (computing what they share once)."""
    scene = PaperScene() if scene is None else scene
    return [check(scene) for check in CHECKS]
