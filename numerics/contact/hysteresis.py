"""Fig. 5: the hysteresis loop of the contact, y against the contact pressure.

Over one steady period of the forced full model (Eq. 2.4), the reaction
R = F_s + F_d of Eq. 2.1 is traced against y. The spring part is conservative,
so the area of the loop, the closed integral of R dy, is the energy the damping
force F_d dissipates in a period, which the drive P supplies.
"""

from __future__ import annotations

import time

import numpy as np
import sympy as sp

from perturb import ContactModel
from perturb import symbols as sym
from perturb.common import Result, check_int, check_positive, result

from ..simulation.rk4 import simulate

__all__ = ["HysteresisLoop", "hysteresis_loop", "contact_pressure"]


@result
class HysteresisLoop(Result):
    """One steady period of the forced response, with the contact's reaction.

    Attributes
    ----------
    frequency_hz, p_a_n, pa_frac : float
        Excitation frequency [Hz], force amplitude P_a [N] and P_a / Q.
    phase : ndarray, shape (steps,)
        Phase in periods, (1..steps) / steps.
    y_m, v_m_s : ndarray, shape (steps,)
        Displacement [m] and velocity [m/s] over the period.
    reaction_n, damping_n : ndarray, shape (steps,)
        The reaction R = F_s + F_d and its damping part F_d [N] (Eq. 2.1);
        negative while the contact pushes the slider up.
    pressure_pa : ndarray, shape (steps,)
        Normal contact pressure p = -R / S [Pa], positive in compression.
    loop_area_j : float
        Area of the loop in the (y, R) plane, |closed integral of R dy| [J].
    dissipated_j : float
        Energy dissipated by F_d over the period, -integral of F_d ydot dt [J].
    drive_work_j : float
        Work of the drive P over the period, integral of P ydot dt [J].
    closure : float
        Mismatch of the state after this period and the one before, relative
        to the peak-to-peak range: how steady the loop is.
    model : dict
        The model (``ContactModel.as_dict()``).
    settings : dict
        ``periods`` and ``steps_per_period`` (also the points on the loop).
    elapsed_s : float
        Wall time [s].
    """

    frequency_hz: float
    p_a_n: float
    pa_frac: float
    phase: np.ndarray
    y_m: np.ndarray
    v_m_s: np.ndarray
    reaction_n: np.ndarray
    damping_n: np.ndarray
    pressure_pa: np.ndarray
    loop_area_j: float
    dissipated_j: float
    drive_work_j: float
    closure: float
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return (
            f"HysteresisLoop: f_e = {self.frequency_hz:g} Hz, P_a = {self.pa_frac:g} Q, "
            f"y {self.y_m.min() * 1e9:.1f}..{self.y_m.max() * 1e9:.1f} nm, p "
            f"{self.pressure_pa.min():.4g}..{self.pressure_pa.max():.4g} Pa, loop area "
            f"{self.loop_area_j:.4g} J, dissipated {self.dissipated_j:.4g} J, "
            f"closure {self.closure:.1e}, {self.elapsed_s:.3g} s"
        )


def _forces(model: ContactModel):
    """R(y, v) and F_s(y) of the model (Eq. 2.1), vectorised, branches as in Piecewise."""
    reaction = model.contact_force().subs(model.values)
    spring = model.contact_force().subs(sym.h_n, 0).subs(model.values)

    def vectorised(expr):
        return np.vectorize(sp.lambdify((sym.y, sym.v), expr, modules="math"), otypes=[float])

    return vectorised(reaction), vectorised(spring)


def contact_pressure(model: ContactModel, y_m, v_m_s) -> np.ndarray:
    """The normal contact pressure p = -R / S [Pa] at the states (y, v) (Eq. 2.1)."""
    reaction, _ = _forces(model)
    return -reaction(np.asarray(y_m), np.asarray(v_m_s)) / model.parameters.S


def _shoelace(x: np.ndarray, y: np.ndarray) -> float:
    """|Area| of the closed polygon through the points, in order."""
    return abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))) / 2


def _closure(y: np.ndarray, v: np.ndarray, steps: int) -> float:
    """Largest relative change of the state over the last period (0 with no motion)."""
    def change(x):
        step, span = abs(x[-1] - x[steps - 1]), np.ptp(x[steps:])
        return 0.0 if step == 0 else step / span

    return float(max(change(y), change(v)))


def hysteresis_loop(
    frequency_hz: float,
    pa_frac: float,
    *,
    model: ContactModel | None = None,
    periods: int = 400,
    steps_per_period: int = 512,
) -> HysteresisLoop:
    """The loop of y against the contact pressure over one steady period (Fig. 5).

    Parameters
    ----------
    frequency_hz : float
        Excitation frequency f_e [Hz] (> 0).
    pa_frac : float
        Force amplitude P_a as a fraction of the weight Q (>= 0).
    model : ContactModel, optional
        The model; the paper's full model by default.
    periods : int
        Periods run from rest at y0 before the loop is taken, the loop included (>= 2).
    steps_per_period : int
        RK4 steps per period, also the points on the loop (>= 4).

    Returns
    -------
    HysteresisLoop

    Raises
    ------
    RuntimeError
        If the run fails (its state becomes non-finite), with simulate's message.

    Examples
    --------
    >>> loop = hysteresis_loop(1600.0, 0.40)  # the caption of Fig. 5
    >>> f"{loop.pressure_pa.min():.0f}..{loop.pressure_pa.max():.0f} Pa"
    '79..5954 Pa'
    >>> f"{loop.loop_area_j / loop.dissipated_j - 1:.1e}"
    '-2.5e-05'
    """
    start = time.perf_counter()
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    frequency_hz = check_positive("frequency_hz", frequency_hz)
    pa_frac = check_positive("pa_frac", pa_frac, allow_zero=True)
    periods = check_int("periods", periods, 2)
    steps = check_int("steps_per_period", steps_per_period, 4)
    p_a = pa_frac * model.parameters.Q_n
    run = simulate(frequency_hz, p_a, periods=periods, steps_per_period=steps, model=model,
                   record=("history",), record_periods=2, throw=True)
    y, v = run.history_y_m[0, steps:], run.history_v_m_s[0, steps:]
    reaction, spring = _forces(model)
    r = reaction(y, v)
    damping = r - spring(y, v)
    phase = run.history_phase[:steps]
    dt = 1 / (steps * frequency_hz)
    return HysteresisLoop(
        frequency_hz=frequency_hz, p_a_n=p_a, pa_frac=pa_frac, phase=phase, y_m=y, v_m_s=v,
        reaction_n=r, damping_n=damping, pressure_pa=-r / model.parameters.S,
        loop_area_j=_shoelace(y, r),
        # Periodic samples: the rectangle rule is the trapezoidal rule here.
        dissipated_j=-float(np.sum(damping * v)) * dt,
        drive_work_j=float(np.sum(p_a * np.cos(2 * np.pi * phase) * v)) * dt,
        closure=_closure(run.history_y_m[0], run.history_v_m_s[0], steps),
        model=model.as_dict(), settings={"periods": periods, "steps_per_period": steps},
        elapsed_s=time.perf_counter() - start,
    )
