"""Exact backbone: time for 300 energy levels and the accuracy reached.

Baseline, in the same run: the textbook route, one level at a time: turning
points by brentq on E - V(y), the substitution y = mid + half sin(theta), and
scipy.integrate.quad over theta, with E - V formed in physical units. The accuracy of both
is measured against the backbone at 128 nodes (which the tests check against
solve_ivp to 1e-10).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad
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


def main() -> None:
    backbone = exact_backbone(points=POINTS)  # also derives and lambdifies once
    u, y0 = backbone.u_max_m, backbone.y0_m
    reference = exact_backbone(u, nodes=128).frequency_hz
    ours = median_time(lambda: exact_backbone(u), repeats=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)  # it struggles where it fails
        textbook = median_time(lambda: [textbook_frequency(x, y0) for x in u], repeats=1)
        naive = np.array([textbook_frequency(x, y0) for x in u])
    err_ours = np.abs(backbone.frequency_hz / reference - 1)
    err_naive = np.abs(naive / reference - 1)
    small, large = u < 1e-3 * y0, u > 1e-1 * y0
    header(f"exact backbone: {POINTS} levels, u_max = 1e-6..3 y0 (contact and bouncing)")
    row("time for the whole curve [s]", ours, textbook, "s", higher_is_better=False)
    row("largest relative error of f, all levels", err_ours.max(), err_naive.max(),
        higher_is_better=False)
    row("largest relative error of f, u_max < 1e-3 y0", err_ours[small].max(),
        err_naive[small].max(), higher_is_better=False)
    row("largest relative error of f, u_max > 0.1 y0", err_ours[large].max(),
        err_naive[large].max(), higher_is_better=False)


if __name__ == "__main__":
    main()
