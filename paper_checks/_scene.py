"""The computations the paper's checks share, each done once and timed.

``PaperScene(quick)`` computes on first use: the sweeps of Fig. 2 and 3, the
attractor censuses at the paper's points of multi-stability, the exact backbone,
and the perturbation series. ``quick`` uses coarser grids (for the tests).
"""

from __future__ import annotations

import time
from functools import cached_property

import numpy as np

from numerics import attractors, compare, exact_backbone, steady_states, sweep
from perturb import (
    PAPER,
    PAPER_BAND_HZ,
    PAPER_COEXISTENCE,
    PAPER_PANEL_FRACTIONS,
    derive,
    eq26_numbers,
)

__all__ = ["PaperScene", "COEXISTENCE_POINTS"]

#: Section 3.3: (f_e [Hz], P_a / Q) where the paper reports coexisting solutions.
COEXISTENCE_POINTS = PAPER_COEXISTENCE
#: Section 3.1's "very small amplitude of the excitation force", as P_a / Q.
TINY_FORCE_FRAC = 1e-3
#: Force amplitudes at which the series is compared with RK4 (the series needs contact).
COMPARED_FRACTIONS = (0.05, 0.10, 0.15)


class PaperScene:
    """Shared, lazily computed results, with the time and settings of each."""

    def __init__(self, quick: bool = False) -> None:
        self.quick = quick
        self.timings: dict[str, dict] = {}

    def _timed(self, name: str, settings: str, compute):
        start = time.perf_counter()
        result = compute()
        self.timings[name] = {"seconds": time.perf_counter() - start, "settings": settings}
        return result

    @cached_property
    def info(self) -> dict:
        return eq26_numbers().as_dict()

    @cached_property
    def grid_hz(self) -> np.ndarray:
        # The paper's band on a 5 Hz grid (10 Hz when quick).
        step = 10.0 if self.quick else 5.0
        return np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + step / 2, step)

    @cached_property
    def sweep(self):
        """Fig. 2 and 3: ten amplitudes, swept up and down."""
        return self._timed(
            "sweep (Fig. 2, 3)",
            f"{len(PAPER_PANEL_FRACTIONS)} amplitudes x up/down x {self.grid_hz.size} points; "
            "128 steps/period, tol 1e-6 (App within 0.5 %)",
            lambda: sweep(self.grid_hz, PAPER_PANEL_FRACTIONS),
        )

    @cached_property
    def censuses(self) -> dict:
        return self._timed(
            "attractor censuses", "98 initial states each; 128 steps/period, tol 1e-6",
            lambda: {name: attractors(f, frac) for name, (f, frac) in COEXISTENCE_POINTS.items()},
        )

    @cached_property
    def tiny_force(self):
        """Steady states at P_a = 1e-3 Q over the band (Section 3.1: linear resonance)."""
        f = self.grid_hz[::4]
        return self._timed(
            "linear check (1e-3 Q)", f"{f.size} frequencies from rest",
            lambda: steady_states(f, TINY_FORCE_FRAC * PAPER.Q_n),
        )

    @cached_property
    def backbone(self):
        points = 60 if self.quick else 200
        return self._timed("exact backbone", f"{points} energy levels, period quadrature",
                           lambda: exact_backbone(points=points))

    @cached_property
    def comparison(self):
        """Series of orders 2..8 against the exact backbone and RK4 (Eq. 2.6 and full)."""
        orders = (2, 4, 6) if self.quick else (2, 4, 6, 8)
        return self._timed(
            "analytic against numerical", f"orders {orders}, P_a = 0.05, 0.10, 0.15 Q, "
            f"{self.grid_hz.size} frequencies, up and down, both models",
            lambda: compare(orders, COMPARED_FRACTIONS, frequency_hz=self.grid_hz),
        )

    @cached_property
    def series(self):
        return self._timed("perturbation series, order 4", "symbolic derivation (sympy)",
                           lambda: derive(4))
