"""The lanes of one kernel call, prepared in one place.

``simulate`` and the steady-state solver both advance a batch of lanes with
the compiled RK4 kernels; each lane has its own f_e (hence its own step dt) and
P_a. ``Lanes`` holds what every kernel call needs (the kernels, dt, the drive
table, the divergence limit) and wraps the calls, so that the 17 positional
buffers of ``record_periods`` are written once.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import check_int

from .codegen import compiled_kernels

__all__ = ["Lanes", "Recording", "drive_table", "divergence_limit", "failure_message",
           "DIVERGENCE_FACTOR"]

#: A lane fails when |y| exceeds this many times max(y0, g / f_e^2): far beyond any
#: flight the drive can cause (g / f_e^2 is 8x the height of a period's free
#: flight), so only an unstable step or a model with no floor gets there.
DIVERGENCE_FACTOR = 1e3
#: The kernels' MAX_SWITCHES (numerics/kernels/kernel_template.py): a step with more switches
#: of the contact makes its lane fail.
MAX_SWITCHES = 16


def drive_table(steps_per_period: int) -> np.ndarray:
    """cos(2 pi j / 2N) for j = 0..2N: the drive at every RK4 stage of a period."""
    return _drive_table(check_int("steps_per_period", steps_per_period, minimum=1))


@lru_cache(maxsize=32)
def _drive_table(steps: int) -> np.ndarray:
    table = np.cos(np.pi * np.arange(2 * steps + 1) / steps)
    table.flags.writeable = False  # shared by every batch with this step
    return table


def divergence_limit(model: ContactModel, frequency_hz: np.ndarray) -> np.ndarray:
    """Per lane, the |y| [m] beyond which the lane is marked failed."""
    y0 = eq26_numbers(model.parameters).y0_m
    return DIVERGENCE_FACTOR * np.maximum(y0, model.parameters.g / frequency_hz**2)


def failure_message(frequency_hz: float, p_a_n: float, period: int, omega0_dt: float) -> str:
    """Why a lane failed, with a hint when the step is too large for the contact."""
    message = (f"f_e={frequency_hz:g} Hz, P_a={p_a_n:g} N: state became non-finite, "
               f"diverged (|y| > {DIVERGENCE_FACTOR:g} max(y0, g/f_e^2)), or met more than "
               f"{MAX_SWITCHES} contact switches within one step (ever shorter flights) in "
               f"period {period}")
    # RK4 is stable for omega * dt below 2 sqrt(2) on an undamped oscillator, and for
    # rate * dt below 2.78 on a decaying one.
    if omega0_dt >= 2.0:
        message += (f"; the step is too large for the contact: rate*dt = {omega0_dt:.3g}, "
                    "the rate being omega0 or, overdamped, the fastest decay (RK4 needs "
                    "< 2.8): raise steps_per_period")
    return message


@dataclass
class Recording:
    """What ``Lanes.record`` noted over whole periods, per lane."""

    ymin: np.ndarray
    ymax: np.ndarray
    value: np.ndarray  # (lanes, width): every local extremum of y [m]
    phase: np.ndarray  # its phase in periods since the recording began
    kind: np.ndarray  # +1 maximum, -1 minimum
    count: np.ndarray  # extrema found per lane (may exceed the width)
    history_y: np.ndarray  # (lanes, periods * steps) or (lanes, 0)
    history_v: np.ndarray

    def extrema(self, lane: int) -> np.ndarray:
        """Rows (phase, y, kind) of one lane's extrema."""
        n = min(int(self.count[lane]), self.value.shape[1])
        return np.column_stack([self.phase[lane, :n], self.value[lane, :n], self.kind[lane, :n]])


class Lanes:
    """A batch of lanes with the same model and steps per period.

    Parameters
    ----------
    model : ContactModel
    frequency_hz, p_a_n : ndarray, shape (lanes,)
    steps : int
        RK4 steps per excitation period.
    """

    def __init__(self, model: ContactModel, frequency_hz: np.ndarray, p_a_n: np.ndarray,
                 steps: int) -> None:
        self.model, self.steps = model, steps
        self.kernels = compiled_kernels(model)
        self.frequency_hz, self.p_a = frequency_hz, p_a_n
        self.dt = 1.0 / (steps * frequency_hz)
        self.drive = drive_table(steps)
        self.limit = divergence_limit(model, frequency_hz)

    def advance(self, y, v, periods: int, failed_period, lanes=slice(None)) -> None:
        """Advance ``lanes`` by whole periods in place; mark the lanes that fail."""
        if periods > 0:
            self.kernels.advance_periods(y, v, self.dt[lanes], self.p_a[lanes], self.drive,
                                         periods, failed_period, self.limit[lanes])

    def record(self, y, v, periods: int, failed_period, first_period: int = 0, *,
               extrema_width: int = 0, history: bool = False, lanes=slice(None)) -> Recording:
        """Advance ``lanes`` by whole periods in place, noting min/max, extrema and history."""
        n = y.shape[0]
        width = (n, periods * self.steps) if history else (n, 0)
        out = Recording(
            ymin=np.empty(n), ymax=np.empty(n), value=np.empty((n, extrema_width)),
            phase=np.empty((n, extrema_width)), kind=np.empty((n, extrema_width), dtype=np.int8),
            count=np.zeros(n, dtype=np.int64), history_y=np.empty(width),
            history_v=np.empty(width),
        )
        self.kernels.record_periods(
            y, v, self.dt[lanes], self.p_a[lanes], self.drive, periods, failed_period,
            first_period, out.ymin, out.ymax, out.value, out.phase, out.kind, out.count,
            out.history_y, out.history_v, self.limit[lanes],
        )
        return out

    def failure_messages(self, failed_period: np.ndarray) -> list[str]:
        """Per lane, why it failed ("" where it did not)."""
        if not (failed_period >= 0).any():
            return [""] * failed_period.size
        rate = eq26_numbers(self.model.parameters).fastest_rate_per_s
        return [
            failure_message(self.frequency_hz[i], self.p_a[i], int(p), rate * self.dt[i])
            if p >= 0 else ""
            for i, p in enumerate(failed_period)
        ]
