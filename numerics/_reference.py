"""A reference integrator: scipy's DOP853 on the model's own expressions.

The right-hand side is lambdified from ``perturb.ContactModel`` (no formula is
typed again), and integration stops at every crossing of y = 0, where the contact
law has its kink, and restarts there, so that the adaptive steps never straddle
it. It is slow and exact enough to judge the fast routes (work-precision, tests).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from perturb import ContactModel, symbols

__all__ = ["reference_last_period"]


@lru_cache(maxsize=16)
def _rhs(parameters, effects):
    model = ContactModel(parameters, effects)
    force = sp.Symbol("force")
    accel = sp.lambdify((symbols.y, symbols.v, force), model.numeric_acceleration(force),
                        modules="math")
    return accel


def _crossing(t, state, *args):
    return state[0]


_crossing.terminal = True


def reference_last_period(model: ContactModel, f_e: float, p_a: float, y: float, v: float,
                          periods: int, *, rtol: float = 1e-10, samples: int = 20001):
    """y over the last of ``periods`` periods from (y, v) at phase 0: (phase, y).

    ``samples`` points per period sample the dense output (extrema to ~(pi/samples)^2).
    """
    accel = _rhs(model.parameters, model.effects)
    omega = 2 * np.pi * f_e

    def rhs(t, state):
        return (state[1], accel(state[0], state[1], p_a * np.cos(omega * t)))

    end = periods / f_e
    pieces, t, state = [], 0.0, (y, v)
    while t < end:
        solution = solve_ivp(rhs, (t, end), state, method="DOP853", rtol=rtol,
                             atol=rtol * 1e-7, dense_output=True,
                             events=_crossing if model.effects.contact_loss else None)
        pieces.append((t, solution.t[-1], solution.sol))
        if solution.status != 1:  # reached the end
            break
        t, state = solution.t[-1], solution.y[:, -1]
        # Step off the crossing so that the event does not fire again at once.
        t, state = _nudge(rhs, t, state, end)
    times = np.linspace(end - 1 / f_e, end, samples)
    values = np.empty(samples)
    for start, stop, sol in pieces:
        inside = (times >= start) & (times <= stop)
        if inside.any():
            values[inside] = sol(times[inside])[0]
    return (times - times[0]) * f_e, values


def _nudge(rhs, t, state, end):
    """A tiny explicit step past the crossing (1e-9 of the remaining time at most)."""
    dt = min(1e-12, (end - t) * 1e-9)
    dy, dv = rhs(t, state)
    return t + dt, (state[0] + dt * dy, state[1] + dt * dv)
