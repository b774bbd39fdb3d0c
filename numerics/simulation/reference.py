"""A reference integrator: scipy's DOP853 on the model's own expressions.

The right-hand side is lambdified from ``perturb.ContactModel`` (no formula is
typed again), and integration stops at every crossing of y = 0, where the contact
law has its kink (or, for l = 0, its jump), and restarts there. Each piece is
integrated with the law of the side it starts on, extended past y = 0 (the
kernels' own side laws, ``numerics.kernels.codegen.side_laws``), so that the step that
finds the crossing, and the dense output that locates it, never straddle the
switch. It is slow and exact enough to judge the fast routes (work-precision,
tests).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from perturb import ContactModel, symbols
from perturb.common import check_int, check_positive, check_real

__all__ = ["reference_last_period"]


@lru_cache(maxsize=16)
def _rhs(parameters, effects):
    """The acceleration by the law of each side of y = 0: (in contact, in flight)."""
    from ..kernels.codegen import side_laws

    model = ContactModel(parameters, effects)
    force = sp.Symbol("force")
    return tuple(sp.lambdify((symbols.y, symbols.v, force), law, modules="math")
                 for law in side_laws(model.numeric_acceleration(force)))


def _crossing(t, state, *args):
    return state[0]


_crossing.terminal = True


def reference_last_period(model: ContactModel, frequency_hz: float, p_a_n: float,
                          y_init_m: float, v_init_m_s: float, periods: int, *,
                          rtol: float = 1e-10, samples: int = 20001):
    """y over the last of ``periods`` periods from (y, v) at phase 0: (phase, y_m).

    Parameters
    ----------
    model : ContactModel
        The model (any effects).
    frequency_hz, p_a_n : float
        Excitation frequency f_e [Hz] (> 0) and force amplitude P_a [N] (>= 0).
    y_init_m, v_init_m_s : float
        The state at phase 0 [m, m/s].
    periods : int
        Periods to integrate (>= 1); the last one is returned.
    rtol : float
        DOP853's relative tolerance (atol is 1e-7 of it, in metres).
    samples : int
        Points of the last period that sample the dense output (extrema to
        ~(pi/samples)^2), >= 2.

    Returns
    -------
    phase, y_m : ndarray, shape (samples,)
        Phase in periods, 0..1, and y [m].

    Raises
    ------
    ValueError
        For bad input, naming the argument.
    RuntimeError
        If ``solve_ivp`` fails (its message, and where it stopped) or y is not
        finite, instead of returning a period it did not integrate.
    """
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    frequency_hz = check_positive("frequency_hz", frequency_hz)
    p_a_n = check_positive("p_a_n", p_a_n, allow_zero=True)
    y_init_m, v_init_m_s = check_real("y_init_m", y_init_m), check_real("v_init_m_s", v_init_m_s)
    periods = check_int("periods", periods)
    rtol = check_positive("rtol", rtol)
    samples = check_int("samples", samples, 2)
    laws = _rhs(model.parameters, model.effects)
    omega = 2 * np.pi * frequency_hz
    side = [0 if y_init_m > 0 else 1]  # the law of the piece: 0 in contact, 1 in flight

    def rhs(t, state):
        acceleration = laws[side[0]](state[0], state[1], p_a_n * math.cos(omega * t))
        if not math.isfinite(acceleration):  # DOP853 would shrink its step forever
            raise RuntimeError(f"the acceleration is not finite at t = {t:.6g} s, "
                               f"y = {float(state[0]):.6g} m, v = {float(state[1]):.6g} m/s")
        return (state[1], acceleration)

    end = periods / frequency_hz
    pieces, t, state = [], 0.0, (y_init_m, v_init_m_s)
    while t < end:
        solution = solve_ivp(rhs, (t, end), state, method="DOP853", rtol=rtol,
                             atol=rtol * 1e-7, dense_output=True,
                             events=_crossing if model.effects.contact_loss else None)
        if not solution.success:
            raise RuntimeError(
                f"solve_ivp (DOP853, rtol={rtol:g}) failed at t = {solution.t[-1]:.6g} s "
                f"of {end:.6g} s: {solution.message}"
            )
        pieces.append((t, solution.sol))
        if solution.status != 1:  # reached the end
            break
        t, state = solution.t[-1], solution.y[:, -1]
        side[0] = 1 - side[0]  # across: the other side's law
        # Step off the crossing so that the event does not fire again at once.
        t, state = _nudge(rhs, t, state, end)
    times = np.linspace(end - 1 / frequency_hz, end, samples)
    values = np.empty(samples)
    # Each piece serves from its start to the next one's, so that the nudge's gap
    # (at most 1e-12 s) is covered too: every sample gets a value.
    bounds = [start for start, _ in pieces[1:]] + [np.inf]
    for (start, sol), stop in zip(pieces, bounds):
        inside = (times >= start) & (times < stop)
        if inside.any():
            values[inside] = sol(times[inside])[0]
    if not np.all(np.isfinite(values)):
        raise RuntimeError(
            f"solve_ivp (DOP853, rtol={rtol:g}) gave non-finite y over the last period "
            f"(from y = {y_init_m:.6g} m, v = {v_init_m_s:.6g} m/s at {frequency_hz:g} Hz)"
        )
    return (times - times[0]) * frequency_hz, values


def _nudge(rhs, t, state, end):
    """A tiny explicit step past the crossing (1e-9 of the remaining time at most)."""
    dt = min(1e-12, (end - t) * 1e-9)
    dy, dv = rhs(t, state)
    return t + dt, (state[0] + dt * dy, state[1] + dt * dv)
