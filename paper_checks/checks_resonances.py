"""Claims about the resonances themselves (Sections 3, 3.1, 3.2)."""

from __future__ import annotations

import numpy as np

from perturb import PAPER_F_N0_HZ, PAPER_PANEL_FRACTIONS, frequency_response

from .claims import Claim
from .scene import TINY_FORCE_FRAC, PaperScene

__all__ = ["natural_frequency", "linear_resonance", "peaks_bend", "superharmonic_peaks",
           "asymmetry"]

PANELS = "abcdefghij"


def natural_frequency(scene: PaperScene) -> Claim:
    f_n0 = scene.info["f_n0_hz"]
    deviation = f_n0 / PAPER_F_N0_HZ - 1
    return Claim(
        "f_n0", "the natural frequency of the considered system equals f_n0 = 1485 Hz "
        "(Section 3)", abs(deviation) < 1e-3,
        {"f_n0_hz": f_n0, "paper_hz": PAPER_F_N0_HZ, "relative_deviation": deviation},
    )


def linear_resonance(scene: PaperScene) -> Claim:
    """At a very small force the response is the linear transfer of Eq. 2.6."""
    found = scene.tiny_force
    # The linear response is the order-0 series of Eq. 2.6 (u0 = G H_1 cos, Eq. 2.8).
    (branch,) = frequency_response(found.frequency_hz, TINY_FORCE_FRAC, order=0,
                                     truncation="paper").branches
    linear = branch.app_m
    deviation = np.abs(found.app_m / linear - 1)
    peak = found.frequency_hz[np.argmax(found.app_m)]
    return Claim(
        "linear_resonance", "in the case of a very small amplitude of the excitation force the "
        "vibrations are linear and the resonance is linear (Section 3.1)",
        bool(deviation.max() < 0.01 and abs(peak / scene.info["f_n0_hz"] - 1) < 0.01),
        {"pa_frac": TINY_FORCE_FRAC, "max_relative_deviation_from_linear": float(deviation.max()),
         "peak_hz": float(peak), "points": int(found.app_m.size)},
    )


def _primary_peak(run) -> tuple[float, float]:
    """(f, App) of the largest App of an up sweep above f_n0/2: the primary peak."""
    f, app = np.asarray(run.frequency_hz), np.asarray(run.app_m)
    window = f > 0.75 * PAPER_F_N0_HZ
    i = np.argmax(np.where(window, app, -np.inf))
    return float(f[i]), float(app[i])


def peaks_bend(scene: PaperScene) -> Claim:
    """The primary peak moves to lower f_e as P_a grows (Section 3.1, Fig. 2, 3)."""
    peaks = [_primary_peak(scene.sweep.run(frac, "up")) for frac in PAPER_PANEL_FRACTIONS]
    freq = [p[0] for p in peaks]
    return Claim(
        "peaks_bend", "the resonance peaks bend to the lower frequencies as the excitation "
        "amplitude grows (Section 3.1)", bool(np.all(np.diff(freq) < 0)),
        {"pa_frac": list(PAPER_PANEL_FRACTIONS), "primary_peak_hz_up_sweep": freq,
         "f_n0_hz": scene.info["f_n0_hz"]},
    )


def _superharmonic_peak(run, m: int, f_n0: float):
    """Largest App of the up sweep in [0.85, 1.03] f_n0/m, and its prominence over
    the App at the window's ends (the background)."""
    f, app = np.asarray(run.frequency_hz), np.asarray(run.app_m)
    window = (f >= 0.85 * f_n0 / m) & (f <= 1.03 * f_n0 / m)
    i = np.flatnonzero(window)[np.argmax(app[window])]
    edges = app[np.flatnonzero(window)[[0, -1]]]
    interior = 0 < i - np.flatnonzero(window)[0] < window.sum() - 1
    return float(f[i]), float(app[i]), float(app[i] / edges.min()), bool(interior)


def superharmonic_peaks(scene: PaperScene) -> Claim:
    """Peaks near f_n0/m (m = 2, 3) that grow with P_a (Section 3.2)."""
    f_n0 = scene.info["f_n0_hz"]
    measured, ok = {}, True
    for m in (2, 3):
        peaks = [_superharmonic_peak(scene.sweep.run(frac, "up"), m, f_n0)
                 for frac in PAPER_PANEL_FRACTIONS]
        heights = [p[1] for p in peaks]
        # A peak stands out (prominence > 1.05, inside the window) from some amplitude on.
        seen = [frac for frac, p in zip(PAPER_PANEL_FRACTIONS, peaks) if p[3] and p[2] > 1.05]
        measured[f"1/{m}"] = {"f_n0_over_m_hz": f_n0 / m, "peak_hz": [p[0] for p in peaks],
                              "peak_app_m": heights, "prominence": [p[2] for p in peaks],
                              "first_seen_at_pa_frac": seen[0] if seen else None}
        ok &= bool(seen) and bool(np.all(np.diff(heights) > 0))
        ok &= all(abs(p[0] / (f_n0 / m) - 1) < 0.1 for p in peaks if p[3])
    return Claim(
        "superharmonic_peaks", "superharmonic resonances appear at f_e ~ f_n0/m and become "
        "stronger with the increase of the excitation amplitude (Section 3.2)", ok, measured,
    )


def asymmetry(scene: PaperScene) -> Claim:
    """Vibrations are asymmetric about y0 (Section 3.1, A2 of Eq. 2.9)."""
    y0 = scene.info["y0_m"]
    ratios = {}
    for frac in (PAPER_PANEL_FRACTIONS[0], PAPER_PANEL_FRACTIONS[2]):
        run = scene.sweep.run(frac, "up")
        f, _ = _primary_peak(run)
        i = run.frequency_hz.tolist().index(f)
        up, down = run.ymax_m[i] - y0, y0 - run.ymin_m[i]
        ratios[f"{frac:.2f}Q at {f:g} Hz"] = {"ymax_minus_y0_m": up, "y0_minus_ymin_m": down,
                                               "ratio": up / down}
    passed = all(abs(r["ratio"] - 1) > 0.05 for r in ratios.values())
    return Claim(
        "asymmetry", "the contact vibrations become asymmetrical to the equilibrium position "
        "(Section 3.1)", passed, ratios,
        detail="ratio = (ymax - y0) / (y0 - ymin) at the primary peak; it differs from 1 by "
        "more than 5 % to pass. Below 1, the slider moves further away from the slideway "
        "than into it: the spring stiffens as it is compressed (Fig. 1f)",
    )
