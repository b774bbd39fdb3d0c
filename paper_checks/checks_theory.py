"""Claims about the perturbation solution and the natural frequency (Section 2, 3.1, A)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from perturb import backbone_series, series_symbols

from .claims import Claim
from .scene import PaperScene

__all__ = ["series_structure", "frequency_falls"]

#: Harmonics of u_n that Eq. 2.8-2.10, A.1 and A.2 print (0: the mean).
PAPER_HARMONICS = {0: (1,), 1: (0, 2), 2: (1, 3), 3: (0, 2, 4), 4: (1, 3, 5)}


def series_structure(scene: PaperScene) -> Claim:
    """b1 = b3 = 0, the harmonics of u_0..u_4, and b2 = 2 h A2 + h A1 cos(phi1)."""
    series = scene.series
    harmonics = {n: tuple(series.harmonics(n)) for n in range(5)}
    zero_b = {n: not series.has_b(n) for n in (1, 3)}
    b2 = series.b_closed_form(2)
    sym = series_symbols
    h = sym.h
    # Eq. 2.10: b2 = 2 h A2 + h A1 cos(phi1); in the engine's names A2 = A_1_0 (the mean
    # of u1), A1 = A_1_2, and phi1 = phi_1_2 - 2 phi_0_1 (phase of u1's second harmonic
    # relative to twice u0's).
    paper_b2 = 2 * h * sym.amplitude(1, 0) + h * sym.amplitude(1, 2) * sp.cos(
        sym.phase(1, 2) - 2 * sym.phase(0, 1))
    b2_matches = sp.simplify(sp.expand_trig(b2 - paper_b2)) == 0
    passed = harmonics == PAPER_HARMONICS and all(zero_b.values()) and b2_matches
    return Claim(
        "series_structure", "the perturbation solution's structure, order by order: b1 = b3 = 0; "
        "u1 has the mean and 2nd harmonic, u2 the 1st and 3rd, u3 the mean, 2nd and 4th, u4 the "
        "1st, 3rd and 5th; b2 = 2hA2 + hA1 cos(phi1) (Eq. 2.8-2.10, A.1, A.2)", passed,
        {"harmonics": {str(n): list(k) for n, k in harmonics.items()},
         "b1_b3_zero": all(zero_b.values()), "b2": str(b2), "b2_equals_eq_2_10": b2_matches},
    )


def frequency_falls(scene: PaperScene) -> Claim:
    """The backbone falls with amplitude: exactly (quadrature) and by the series (-5/12)."""
    backbone = scene.backbone
    order = np.argsort(backbone.app_m)
    f = backbone.frequency_hz[order]
    falls = bool(np.all(np.diff(f) <= 1e-9 * f[0]))
    coefficient = backbone_series(2, "paper").coefficients[2]
    return Claim(
        "frequency_falls", "the natural frequency of the non-linear system becomes smaller with "
        "the increase of the vibration amplitude (Section 3.1, Eq. 2.10)",
        falls and coefficient < 0,
        {"f_at_smallest_app_hz": float(f[0]), "f_at_contact_loss_hz": float(
            np.interp(backbone.contact_loss_app_m, backbone.app_m[order], f)),
         "f_at_largest_app_hz": float(f[-1]), "largest_app_m": float(backbone.app_m.max()),
         "series_alpha2_coefficient": str(coefficient)},
    )
