"""Fold curves in (f_e, P_a) against one-parameter continuation at the same P_a's.

The box: the primary resonance, 1300-1500 Hz, 0.03-0.05 Q (seeded at 0.05 Q; the curve
runs from one fold at 0.05 Q through the cusp to the other). Baseline, measured in the
same run: ``continue_orbits`` over the same band at five P_a's (0.03, 0.035, ... 0.05),
which locates the folds at those levels only. Medians of interleaved repeats, warm.
"""

from __future__ import annotations

import numpy as np

from numerics import continue_orbits, fold_curves

from ._timing import header, interleaved_medians, row

BOX = (1300.0, 1500.0, 0.03, 0.05)
LEVELS = np.linspace(BOX[2], BOX[3], 5)


def _curves():
    return fold_curves(*BOX, seed_pa_fracs=[BOX[3]])


def _levels():
    return [continue_orbits(pa, BOX[0], BOX[1]) for pa in LEVELS]


def main() -> None:
    run, runs = _curves(), _levels()  # compile / load the kernels
    curves, levels = interleaved_medians(_curves, _levels, repeats=5)
    header(f"Fold curves, {BOX[0]:g}-{BOX[1]:g} Hz, {BOX[2]:g}-{BOX[3]:g} Q (warm, medians of 5)")
    row(f"fold_curves [s] vs continue_orbits at {LEVELS.size} P_a [s]", curves, levels, "s",
        higher_is_better=False)
    row("points on the fold curves", sum(c.frequency_hz.size for c in run.fold_curves))
    row(f"folds found by continue_orbits at the {LEVELS.size} P_a", sum(len(r.folds())
                                                                      for r in runs))
    worst = max(min(abs(a.frequency_hz - b.frequency_hz) for a in run.folds_at(r.pa_frac))
                for r in runs for b in r.folds())
    row("largest |f| gap, curve vs continue_orbits [Hz]", worst)
    for cusp in run.cusps:
        print(f"  {cusp.summary()}")


if __name__ == "__main__":
    main()
