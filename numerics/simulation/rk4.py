"""The entry function of the simulator: a batched, phase-locked RK4 run."""

from __future__ import annotations

import time

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import Status, check_choice, check_int, finite_array, lane_array

from ..kernels.lanes import Lanes
from .result import Simulation

__all__ = ["simulate", "check_model", "initial_lanes", "RECORDABLE"]

#: The most memory the recorded observables of one run may take [bytes]: a history
#: takes 16 bytes per lane and step, the extrema 17 bytes per lane and slot.
MAX_RECORD_BYTES = 2**31

#: The observables a run can record, and what each one stores.
RECORDABLE = {
    "final": "state (y, v) at the end of the run",
    "minmax": "min and max of y over the recorded periods",
    "extrema": "every local extremum of y over the recorded periods",
    "history": "y and v after every step of the recorded periods",
}


def check_model(model) -> ContactModel:
    """The model (the paper's full model when None), or a ValueError."""
    model = ContactModel() if model is None else model
    if not isinstance(model, ContactModel):
        raise ValueError(f"`model` must be a perturb.ContactModel, got {model!r}.")
    return model


def initial_lanes(frequency_hz, p_a_n, y_init_m, v_init_m_s, model, **more):
    """The lanes' arrays broadcast to one count; rest at y0 by default.

    ``more`` are further per-lane arrays (already checked) to broadcast with them.
    """
    f_e = lane_array("frequency_hz", frequency_hz, positive=True)
    p_a = lane_array("p_a_n", p_a_n)
    y0 = eq26_numbers(model.parameters).y0_m
    y = finite_array("y_init_m", y0 if y_init_m is None else y_init_m)
    v = finite_array("v_init_m_s", 0.0 if v_init_m_s is None else v_init_m_s)
    named = {"frequency_hz": f_e, "p_a_n": p_a, "y_init_m": y, "v_init_m_s": v, **more}
    try:
        arrays = np.broadcast_arrays(*named.values())
    except ValueError:
        shapes = ", ".join(f"`{k}` {a.shape}" for k, a in named.items())
        raise ValueError(f"the lane arguments must broadcast to one lane count, got {shapes}.") \
            from None
    return [np.array(a) for a in arrays]


def simulate(
    frequency_hz,
    p_a_n,
    *,
    periods: int,
    steps_per_period: int = 128,
    model: ContactModel | None = None,
    y_init_m=None,
    v_init_m_s=None,
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
    frequency_hz, p_a_n : float or array_like, shape (lanes,)
        Excitation frequency f_e [Hz] (> 0) and force amplitude P_a [N] (>= 0).
    periods : int
        Excitation periods to run, the recorded ones included.
    steps_per_period : int
        RK4 steps per period, at least 4.
    model : ContactModel, optional
        The model and its effects; the paper's full model by default.
    y_init_m, v_init_m_s : float or array_like, optional
        Initial state [m, m/s]; rest at the static deflection y0 by default.
    record : sequence of {"final", "minmax", "extrema", "history"}
        Observables to record over the last ``record_periods`` periods;
        nothing else is stored.
    record_periods : int
        How many final periods the observables cover.
    max_extrema : int
        Room for local extrema per lane (with "extrema").
    throw : bool
        Raise a RuntimeError if a lane fails, instead of giving it the status
        ``Status.FAILED`` and a message.

    Returns
    -------
    Simulation

    Examples
    --------
    >>> from perturb import PAPER
    >>> run = simulate([1000.0, 1400.0], 0.05 * PAPER.Q_n, periods=200)
    >>> [f"{a * 1e9:.2f} nm" for a in run.app_m]
    ['20.58 nm', '106.08 nm']
    """
    model = check_model(model)
    steps = check_int("steps_per_period", steps_per_period, minimum=4)
    periods = check_int("periods", periods)
    record_periods = check_int("record_periods", record_periods)
    if record_periods > periods:
        raise ValueError(f"`record_periods` must be <= periods={periods}, got {record_periods}.")
    names = (record,) if isinstance(record, str) else tuple(record)
    for name in names:
        check_choice("record", name, sorted(RECORDABLE))
    max_extrema = check_int("max_extrema", max_extrema)
    f_e, p_a, y, v = initial_lanes(frequency_hz, p_a_n, y_init_m, v_init_m_s, model)
    _check_record_size(f_e.size, names, record_periods * steps, max_extrema)

    start = time.perf_counter()
    lanes = Lanes(model, f_e, p_a, steps)
    failed_period = np.full(f_e.shape[0], -1, dtype=np.int64)
    lanes.advance(y, v, periods - record_periods, failed_period)
    recording = lanes.record(y, v, record_periods, failed_period, periods - record_periods,
                             extrema_width=max_extrema if "extrema" in names else 0,
                             history="history" in names)
    result = Simulation(
        frequency_hz=f_e, p_a_n=p_a, model=model.as_dict(),
        settings={"steps_per_period": steps, "periods": periods,
                  "record_periods": record_periods, "record": list(names),
                  "max_extrema": max_extrema},
        status=np.where(failed_period >= 0, Status.FAILED, Status.SUCCESS),
        message=lanes.failure_messages(failed_period),
        y_final_m=y, v_final_m_s=v, **_observed(recording, names, record_periods, steps),
        elapsed_s=time.perf_counter() - start,
    )
    if throw and result.failed.any():
        raise RuntimeError("; ".join(f"lane {i}: {m}" for i, m in enumerate(result.message) if m))
    return result


def _check_record_size(lanes: int, names, steps: int, max_extrema: int) -> None:
    """Refuse, before allocating, a recording larger than MAX_RECORD_BYTES."""
    size = lanes * (16 * steps * ("history" in names) + 17 * max_extrema * ("extrema" in names))
    if size > MAX_RECORD_BYTES:
        raise ValueError(
            f"recording {list(names)} for {lanes} lanes over {steps} steps would take "
            f"{size / 2**30:.1f} GiB, more than the limit of {MAX_RECORD_BYTES / 2**30:g} GiB: "
            "lower `record_periods`, `max_extrema` or the lanes, or record less.")


def _observed(recording, names, record_periods: int, steps: int) -> dict:
    """The observables asked for, and nothing else."""
    observed: dict = {}
    if "minmax" in names or "extrema" in names:
        observed.update(ymin_m=recording.ymin, ymax_m=recording.ymax)
    if "extrema" in names:
        width = recording.value.shape[1]
        if (recording.count > width).any():
            raise RuntimeError(
                f"a lane had {int(recording.count.max())} local extrema, more than "
                f"`max_extrema`={width}; raise it."
            )
        observed["extrema"] = [recording.extrema(i) for i in range(recording.count.size)]
    if "history" in names:
        observed.update(
            history_phase=np.arange(1, record_periods * steps + 1) / steps,
            history_y_m=recording.history_y, history_v_m_s=recording.history_v,
        )
    return observed
