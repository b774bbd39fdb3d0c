"""Exact backbone: time for 300 energy levels and the accuracy reached.

Baseline, in the same run: the textbook route, one level at a time: turning
points by brentq on E - V(y), the substitution y = mid + half sin(theta), and
scipy.integrate.quad over theta, with E - V formed in physical units.

Accuracy, against an independent route: the period of a free run of Eq. 2.4
(F_d = 0, typed by hand) integrated by scipy's DOP853 at rtol 1e-13, at a few
levels from 1e-4 y0 to 3 y0 (contact and bouncing). Besides, where the textbook
route loses its digits: its error against this backbone at 128 nodes, printed
beside our own change from 48 to 128 nodes (a self-convergence figure, not an
accuracy: no ratio is printed).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad, solve_ivp
from scipy.optimize import brentq

from numerics import exact_backbone
from perturb import PAPER

from ._timing import header, median_time, row

POINTS = 300


def textbook_frequency(u_max: float, y0: float) -> float:
    """f from T = 2 * integral dy / sqrt(2 (E - V(y)) / M), V = S c_n y^3/3 - M g y (y > 0).

    Turning points by brentq on E - V; y = mid + half sin(theta) takes the
    inverse square roots out of the integrand; quad integrates over theta.
    """
    p = PAPER

    def potential(y):
        spring = p.S * p.c_n * max(y, 0.0) ** (p.m2 + 1) / (p.m2 + 1)
        return spring - p.M * p.g * y

    energy = potential(y0 + u_max)
    lower = brentq(lambda y: potential(y) - energy, -1e3 * y0 - 10 * u_max, y0, xtol=1e-30)
    mid, half = (y0 + u_max + lower) / 2, (y0 + u_max - lower) / 2

    def dt_dtheta(theta):
        gap = energy - potential(mid + half * math.sin(theta))
        return half * math.cos(theta) / math.sqrt(2 * max(gap, 1e-300) / p.M)

    period, _ = quad(dt_dtheta, -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-12, limit=200)
    return 1 / (2 * period)


def dop853_frequency(u_max: float, y0: float, periods: int = 3) -> float:
    """f of a free run from rest at y0 + u_max: Eq. 2.4 with F_d = 0, by DOP853."""
    p = PAPER

    def rhs(t, state):
        y, v = state
        return v, (-p.S * p.c_n * max(y, 0.0) ** p.m2) / p.M + p.g

    def top(t, state):
        return state[1]

    top.direction = -1
    omega0 = math.sqrt(p.g * p.m2 / y0)
    run = solve_ivp(rhs, (0.0, (periods + 1) * 4 * math.pi / omega0 * (1 + u_max / y0)),
                    [y0 + u_max, 0.0], method="DOP853", rtol=1e-13,
                    atol=[1e-14 * y0, 1e-14 * y0 * omega0], events=top)
    tops = run.t_events[0]
    return (tops.size - 1) / (tops[-1] - tops[0])


def main() -> None:
    backbone = exact_backbone(points=POINTS)  # also derives and lambdifies once
    u, y0 = backbone.u_max_m, backbone.y0_m
    reference = exact_backbone(u, nodes=128).frequency_hz
    ours = median_time(lambda: exact_backbone(u), repeats=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)  # it struggles where it fails
        textbook = median_time(lambda: [textbook_frequency(x, y0) for x in u], repeats=1)
        naive = np.array([textbook_frequency(x, y0) for x in u])
    levels = y0 * np.array([1e-4, 1e-2, 0.3, 1.0, 1.5, 2.0, 3.0])
    independent = np.array([dop853_frequency(x, y0) for x in levels])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        textbook_at = np.array([textbook_frequency(x, y0) for x in levels])
    err_ivp = np.abs(exact_backbone(levels).frequency_hz / independent - 1).max()
    err_ivp_naive = np.abs(textbook_at / independent - 1).max()
    self_change = np.abs(backbone.frequency_hz / reference - 1)
    err_naive = np.abs(naive / reference - 1)
    small, large = u < 1e-3 * y0, u > 1e-1 * y0
    header(f"exact backbone: {POINTS} levels, u_max = 1e-6..3 y0 (contact and bouncing)")
    row("time for the whole curve [s]", ours, textbook, "s", higher_is_better=False)
    row("largest |f/f_DOP853 - 1|, 7 levels 1e-4..3 y0", err_ivp, err_ivp_naive,
        ratio=False)
    print("textbook route against this backbone at 128 nodes; value: ours 48 vs 128 nodes")
    row("  largest |df/f|, all levels", self_change.max(), err_naive.max(), ratio=False)
    row("  largest |df/f|, u_max < 1e-3 y0", self_change[small].max(), err_naive[small].max(),
        ratio=False)
    row("  largest |df/f|, u_max > 0.1 y0", self_change[large].max(), err_naive[large].max(),
        ratio=False)


if __name__ == "__main__":
    main()
