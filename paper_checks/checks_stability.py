"""Claims about jumps, bi- and multi-stability, and loss of contact (Sections 3.1, 3.3)."""

from __future__ import annotations

import numpy as np

from perturb import PAPER_PANEL_FRACTIONS

from .claims import Claim
from .scene import PaperScene

__all__ = ["bistability", "contact_loss", "coexistence_740", "coexistence_490"]

PANELS = "abcdefghij"


def bistability(scene: PaperScene) -> Claim:
    """Up and down sweeps differ inside a band at 0.05Q (Fig. 2a, 3a)."""
    frac = PAPER_PANEL_FRACTIONS[0]
    up, down = scene.sweep.run(frac, "up"), scene.sweep.run(frac, "down")
    f = np.asarray(up.frequency_hz)
    app_up = np.asarray(up.app_m)
    app_down = np.asarray(down.app_m)[::-1]  # down runs are stored in the order swept
    differ = np.maximum(app_up / app_down, app_down / app_up) > 1.05
    band = [float(f[differ].min()), float(f[differ].max())] if differ.any() else None
    return Claim(
        "bistability_005", "the peak bends to lower frequencies, thus a bi-stability area "
        "appears for P_a = 0.05Q (Section 3.3, Fig. 2a, 3a)", bool(differ.any()),
        {"bistable_band_hz": band, "jump_up_hz": [float(up.frequency_hz[i]) for i in up.jumps()],
         "jump_down_hz": [float(down.frequency_hz[i]) for i in down.jumps()]},
    )


def contact_loss(scene: PaperScene) -> Claim:
    """ymin < 0 somewhere in panels b..j, nowhere in panel a (Fig. 3)."""
    lost = {}
    for panel, frac in zip(PANELS, PAPER_PANEL_FRACTIONS):
        runs = [scene.sweep.run(frac, d) for d in ("up", "down")]
        where = sorted({f for r in runs for f, m in zip(r.frequency_hz, r.ymin_m) if m < 0})
        lost[panel] = {"pa_frac": frac, "points_with_contact_loss": len(where),
                       "band_hz": [where[0], where[-1]] if where else None}
    passed = lost["a"]["points_with_contact_loss"] == 0 and all(
        lost[p]["points_with_contact_loss"] > 0 for p in PANELS[1:])
    return Claim(
        "contact_loss", "the slider can lose contact with the slideway (Figs. 3b-3j); minima "
        "below zero reveal it", passed, lost, beyond=_bouncing_to_band_end(scene),
    )


def _bouncing_to_band_end(scene: PaperScene) -> str:
    """The amplitudes whose down sweep bounces all the way to the band's lowest f_e."""
    lowest = min(scene.grid_hz)
    fracs = [frac for frac in PAPER_PANEL_FRACTIONS
             if scene.sweep.run(frac, "down").ymin_m[-1] < 0]
    if not fracs:
        return ""
    apps = [scene.sweep.run(frac, "down").app_m[-1] for frac in fracs]
    return (f"from P_a = {fracs[0]:.2f}Q up, the down sweeps stay on the bouncing primary "
            f"branch down to {lowest:g} Hz, far below the primary peak (App there "
            f"{min(apps) * 1e6:.1f}-{max(apps) * 1e6:.1f} um); an independent integrator "
            "confirms it is an attractor (tests/test_sweep.py)")


def _census_claim(scene: PaperScene, key: str, claim_id: str, statement: str,
                  expected: set[str]) -> Claim:
    census = scene.censuses[key]
    labels = [a.label for a in census.attractors]
    extra = [a for a in census.attractors if a.label not in expected]
    measured = {
        "attractors": [{"label": a.label, "period": a.period, "app_m": a.app_m,
                        "ymin_m": a.ymin_m, "basin_fraction": a.basin_fraction,
                        "contact_lost": a.contact_lost} for a in census.attractors],
        "initial_states": census.settings["initial_states"],
        "not_settled_fraction": census.not_settled_fraction,
    }
    beyond = "; ".join(
        f"also a {a.label} orbit, App {a.app_m * 1e9:.0f} nm, basin {a.basin_fraction:.0%}"
        + (", with loss of contact" if a.contact_lost else "") for a in extra)
    return Claim(claim_id, statement, expected <= set(labels), measured, beyond=beyond)


def coexistence_740(scene: PaperScene) -> Claim:
    return _census_claim(
        scene, "740 Hz, 0.15Q", "coexistence_740",
        "for P_a = 0.15Q the primary resonance and the 1/2 superharmonic resonance can be "
        "excited at the same frequency f_e = 740 Hz (Section 3.3)",
        {"primary", "1/2 superharmonic"},
    )


def coexistence_490(scene: PaperScene) -> Claim:
    return _census_claim(
        scene, "490 Hz, 0.50Q", "coexistence_490",
        "three solutions are possible: the primary resonance, the 1/2 and 1/3 superharmonic "
        "resonances for P_a = 0.50Q and f_e = 490 Hz (Section 3.3)",
        {"primary", "1/2 superharmonic", "1/3 superharmonic"},
    )
