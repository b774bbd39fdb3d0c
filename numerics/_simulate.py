"""The entry function of the simulator: a batched, phase-locked RK4 run."""

from __future__ import annotations

import time
from functools import lru_cache

import numpy as np

from perturb import ContactModel, Eq26

from ._codegen import compiled_kernels
from ._result import Simulation
from ._validate import check_record, finite_array, lane_array, positive_int

__all__ = ["simulate", "drive_table", "static_deflection", "divergence_limit"]


def drive_table(steps_per_period: int) -> np.ndarray:
    """cos(2 pi j / 2N) for j = 0..2N: the drive at every RK4 stage of a period."""
    return np.cos(np.pi * np.arange(2 * steps_per_period + 1) / steps_per_period)


#: A lane fails when |y| exceeds this many times max(y0, g / f_e^2): far beyond any
#: flight the drive can cause (g / f_e^2 is 8x the height of a period's free
#: flight), so only an unstable step or a model with no floor gets there.
DIVERGENCE_FACTOR = 1e3


def divergence_limit(model: ContactModel, f_e: np.ndarray) -> np.ndarray:
    """Per lane, the |y| [m] beyond which the lane is marked failed."""
    y0 = static_deflection(model)
    return DIVERGENCE_FACTOR * np.maximum(y0, model.parameters.g / f_e**2)


def static_deflection(model: ContactModel) -> float:
    """y0 of the model [m], the default initial state."""
    return _static_deflection_m(model.parameters)


@lru_cache(maxsize=64)
def _static_deflection_m(parameters) -> float:
    model = ContactModel(parameters)
    return model.numeric(model.static_deflection)


def _lanes(f_e_hz, p_a_n, y_init, v_init, model):
    f_e = lane_array("f_e_hz", f_e_hz, positive=True)
    p_a = lane_array("p_a_n", p_a_n)
    y = finite_array("y_init", static_deflection(model) if y_init is None else y_init)
    v = finite_array("v_init", 0.0 if v_init is None else v_init)
    try:
        arrays = np.broadcast_arrays(f_e, p_a, y, v)
    except ValueError:
        raise ValueError(
            "`f_e_hz`, `p_a_n`, `y_init`, `v_init` must broadcast to one lane count, got "
            f"{f_e.shape}, {p_a.shape}, {y.shape}, {v.shape}."
        ) from None
    return [np.array(a, dtype=float) for a in arrays]


def simulate(
    f_e_hz,
    p_a_n,
    *,
    periods: int,
    steps_per_period: int = 128,
    model: ContactModel | None = None,
    y_init=None,
    v_init=None,
    record=("final", "minmax"),
    record_periods: int = 1,
    max_extrema: int = 64,
    throw: bool = False,
) -> Simulation:
    """Integrate Eq. 2.4 (or a reduced model) for many lanes at once with RK4.

    Each lane has its own excitation frequency, force amplitude and initial
    state, and takes ``steps_per_period`` fixed steps per excitation period.

    Parameters
    ----------
    f_e_hz, p_a_n : float or array_like, shape (lanes,)
        Excitation frequency [Hz] (> 0) and force amplitude P_a [N] (>= 0).
    periods : int
        Excitation periods to run, the recorded ones included.
    steps_per_period : int
        RK4 steps per period, at least 4.
    model : ContactModel, optional
        The model and its effects; the paper's full model by default.
    y_init, v_init : float or array_like, optional
        Initial state [m, m/s]; rest at the static deflection y0 by default.
    record : sequence of {"final", "minmax", "extrema", "history"}
        Observables to record over the last ``record_periods`` periods;
        nothing else is stored.
    record_periods : int
        How many final periods the observables cover.
    max_extrema : int
        Room for local extrema per lane (with "extrema").
    throw : bool
        Raise a RuntimeError if a lane fails, instead of marking it.

    Returns
    -------
    Simulation

    Examples
    --------
    >>> from perturb import PAPER
    >>> run = simulate([1000.0, 1400.0], 0.05 * PAPER.weight_n, periods=200)
    >>> [f"{a * 1e9:.2f} nm" for a in run.app]
    ['20.58 nm', '106.08 nm']
    """
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    steps = positive_int("steps_per_period", steps_per_period, minimum=4)
    periods = positive_int("periods", periods)
    record_periods = positive_int("record_periods", record_periods)
    if record_periods > periods:
        raise ValueError(f"`record_periods` must be <= periods={periods}, got {record_periods}.")
    names = check_record(record)
    max_extrema = positive_int("max_extrema", max_extrema)
    f_e, p_a, y, v = _lanes(f_e_hz, p_a_n, y_init, v_init, model)

    start = time.perf_counter()
    kernels = compiled_kernels(model)
    dt = 1.0 / (steps * f_e)
    drive = drive_table(steps)
    failed_period = np.full(f_e.shape[0], -1, dtype=np.int64)
    limit = divergence_limit(model, f_e)
    kernels.advance_periods(y, v, dt, p_a, drive, periods - record_periods, failed_period, limit)
    observed = _record(kernels, names, y, v, dt, p_a, drive, failed_period, periods,
                       record_periods, steps, max_extrema, limit)
    result = Simulation(
        f_e_hz=f_e, p_a_n=p_a, model=repr(model), steps_per_period=steps, periods=periods,
        record_periods=record_periods, y_final=y, v_final=v, failed=failed_period >= 0,
        messages=_failure_messages(failed_period, f_e, p_a, model, steps), **observed,
        elapsed_s=time.perf_counter() - start,
    )
    if throw and result.failed.any():
        raise RuntimeError("; ".join(result.messages))
    return result


def _record(kernels, names, y, v, dt, p_a, drive, failed_period, periods, record_periods,
            steps, max_extrema, limit) -> dict:
    lanes = y.shape[0]
    want_extrema = "extrema" in names
    want_history = "history" in names
    width = max_extrema if want_extrema else 0
    ymin, ymax = np.empty(lanes), np.empty(lanes)
    ext_value = np.empty((lanes, width))
    ext_phase = np.empty((lanes, width))
    ext_kind = np.empty((lanes, width), dtype=np.int8)
    ext_count = np.zeros(lanes, dtype=np.int64)
    history = (lanes, record_periods * steps) if want_history else (lanes, 0)
    history_y, history_v = np.empty(history), np.empty(history)
    kernels.record_periods(
        y, v, dt, p_a, drive, record_periods, failed_period, periods - record_periods,
        ymin, ymax, ext_value, ext_phase, ext_kind, ext_count, history_y, history_v, limit,
    )
    observed: dict = {}
    if "minmax" in names or want_extrema:
        observed.update(ymin=ymin, ymax=ymax)
    if want_extrema:
        if (ext_count > width).any():
            raise RuntimeError(
                f"a lane had {int(ext_count.max())} local extrema, more than "
                f"`max_extrema`={width}; raise it."
            )
        observed["extrema"] = [
            np.column_stack([ext_phase[i, :n], ext_value[i, :n], ext_kind[i, :n]])
            for i, n in enumerate(ext_count)
        ]
    if want_history:
        observed.update(
            history_phase=np.arange(1, record_periods * steps + 1) / steps,
            history_y=history_y, history_v=history_v,
        )
    return observed


def _failure_messages(failed_period, f_e, p_a, model, steps) -> list[str]:
    if not (failed_period >= 0).any():
        return []  # no need for omega0 (its first derivation costs a sympy run)
    # RK4 is stable for omega * dt below 2 sqrt(2) on an undamped oscillator.
    omega0 = Eq26(model).numeric()["omega0_rad_s"]
    return [
        f"lane {i} (f_e={f_e[i]:g} Hz, P_a={p_a[i]:g} N): state became non-finite or "
        f"diverged (|y| > {DIVERGENCE_FACTOR:g} max(y0, g/f_e^2)) in period {int(p)}"
        + _step_hint(omega0 / (steps * f_e[i]))
        for i, p in enumerate(failed_period)
        if p >= 0
    ]


def _step_hint(omega_dt: float) -> str:
    if omega_dt < 2.0:
        return ""
    return (f"; the step is too large for the contact: omega0*dt = {omega_dt:.3g} "
            "(RK4 needs < 2.8): raise steps_per_period")
