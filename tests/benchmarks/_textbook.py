"""Baselines written the textbook way, for the benchmarks only.

Eq. 2.4 is typed here by hand, on purpose: a baseline must not share the
toolkit's generated code. tests/test_rhs_reference.py holds a third copy as the
reference of the generated right-hand side.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from scipy.integrate import solve_ivp

from perturb import PAPER

__all__ = ["textbook_rk4", "brute_force_sweep", "dop853_point", "PARAMETERS"]

PARAMETERS = (PAPER.S, PAPER.c_n, PAPER.m2, PAPER.h_n, PAPER.l, PAPER.M, PAPER.g)


@numba.njit(cache=True)
def _accel(t, y, v, f_e, p_a, S, c_n, m2, h_n, l, M, g):  # noqa: E741
    """Eq. 2.4 with cos and pow at every call."""
    contact = -S * c_n * y**m2 - S * h_n * y**l * v if y > 0 else 0.0
    return (contact + M * g + p_a * math.cos(2 * math.pi * f_e * t)) / M


@numba.njit(cache=True)
def _rk4_lane(y, v, f_e, p_a, steps, periods, par):
    """One lane, `periods` periods of `steps` RK4 steps; min and max over the last one."""
    S, c_n, m2, h_n, l, M, g = par  # noqa: E741
    dt = 1.0 / (steps * f_e)
    t = 0.0
    low, high = y, y
    for i in range(steps * periods):
        a1 = _accel(t, y, v, f_e, p_a, S, c_n, m2, h_n, l, M, g)
        y2, v2 = y + dt / 2 * v, v + dt / 2 * a1
        a2 = _accel(t + dt / 2, y2, v2, f_e, p_a, S, c_n, m2, h_n, l, M, g)
        y3, v3 = y + dt / 2 * v2, v + dt / 2 * a2
        a3 = _accel(t + dt / 2, y3, v3, f_e, p_a, S, c_n, m2, h_n, l, M, g)
        y4, v4 = y + dt * v3, v + dt * a3
        a4 = _accel(t + dt, y4, v4, f_e, p_a, S, c_n, m2, h_n, l, M, g)
        y = y + dt / 6 * (v + 2 * v2 + 2 * v3 + v4)
        v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        t += dt
        if i == steps * (periods - 1):
            low, high = y, y
        low, high = min(low, y), max(high, y)
    return y, v, low, high


@numba.njit(cache=True)
def textbook_rk4(y, v, f_e, p_a, steps, periods, par):
    """Every lane in turn, from its own state (for throughput)."""
    for lane in range(y.shape[0]):
        y[lane], v[lane], _, _ = _rk4_lane(y[lane], v[lane], f_e[lane], p_a[lane], steps,
                                           periods, par)


@numba.njit(cache=True)
def brute_force_sweep(frequencies, p_a, y_start, steps, periods, par):
    """The paper's method with no early stop: every point runs `periods` periods from
    the previous point's final state. Returns App per point."""
    app = np.empty(frequencies.shape[0])
    y, v = y_start, 0.0
    for j in range(frequencies.shape[0]):
        y, v, low, high = _rk4_lane(y, v, frequencies[j], p_a, steps, periods, par)
        app[j] = high - low
    return app


def dop853_point(f_e: float, p_a: float, y_start: float, periods: int, rtol: float = 1e-9):
    """One point of the sweep with scipy's DOP853; App over the last period."""
    S, c_n, m2, h_n, l, M, g = PARAMETERS  # noqa: E741

    def rhs(t, state):
        y, v = state
        contact = -S * c_n * y**m2 - S * h_n * y**l * v if y > 0 else 0.0
        return (v, (contact + M * g + p_a * math.cos(2 * math.pi * f_e * t)) / M)

    period = 1.0 / f_e
    last = np.linspace((periods - 1) * period, periods * period, 401)
    solution = solve_ivp(rhs, (0.0, periods * period), (y_start, 0.0), method="DOP853",
                         rtol=rtol, atol=1e-12 * y_start, t_eval=last)
    return np.ptp(solution.y[0])
