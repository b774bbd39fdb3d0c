"""Continuation of the whole primary branch at 0.15 Q, 250-1800 Hz, with stability.

Issue 13's goal: under 0.5 s once compiled. Baseline, measured in the same run: the
sweep up and down of the same band on a 5 Hz grid (311 points each way), which sees
only the stable parts. Medians of interleaved repeats, warm (kernels compiled).
The continuation package pycont-lite (issue 13 asks for it beside) is not a dependency
of the project: not run here (see docs/continuation.md).
"""

from __future__ import annotations

import numpy as np

from numerics import continue_orbits, sweep

from ._timing import header, interleaved_medians, row

PA_FRAC, BAND = 0.15, (250.0, 1800.0)
GRID = np.arange(BAND[0], BAND[1] + 0.5, 5.0)


def main() -> None:
    run = continue_orbits(PA_FRAC, *BAND)  # compile / load the kernels
    sweep(GRID, PA_FRAC)
    continued, swept = interleaved_medians(lambda: continue_orbits(PA_FRAC, *BAND),
                                           lambda: sweep(GRID, PA_FRAC), repeats=5)
    header(f"Continuation at {PA_FRAC} Q, {BAND[0]:g}-{BAND[1]:g} Hz (warm, medians of 5)")
    row("continue_orbits [s] vs sweep up+down, 5 Hz [s]", continued, swept, "s",
        higher_is_better=False)
    row("continue_orbits [s] vs the goal of 0.5 s", continued, 0.5, "s",
        higher_is_better=False)
    points = sum(b.frequency_hz.size for b in run.branches)
    row("points on the continued branches", points)
    for branch in run.branches:
        print(f"  {branch.summary()}")
    for mark in run.bifurcations:
        print(f"  {mark.kind} at {mark.frequency_hz:.4f} Hz, App {mark.app_m * 1e9:.2f} nm")


if __name__ == "__main__":
    main()
