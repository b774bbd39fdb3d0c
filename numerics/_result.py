"""The result object of a simulation."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Simulation"]


@dataclass
class Simulation:
    """What a batched RK4 run measured, per lane, with what made it.

    Attributes
    ----------
    f_e_hz, p_a_n : ndarray, shape (lanes,)
        Excitation frequency [Hz] and force amplitude [N] of each lane.
    model : str
        The model and its effects.
    steps_per_period, periods, record_periods : int
        Steps per excitation period, periods run in all, periods recorded.
    y_final, v_final : ndarray, shape (lanes,)
        State at the end [m, m/s] (with "final").
    ymin, ymax : ndarray, shape (lanes,) or None
        Extremes of y over the recorded periods (with "minmax" or "extrema").
    extrema : list of ndarray, shape (k, 3) or None
        Per lane, rows (phase in periods from the start of the recording,
        y [m], +1 maximum / -1 minimum) (with "extrema").
    history_phase : ndarray, shape (steps,) or None
        Phase in periods, since the start of the recording, of each stored step.
    history_y, history_v : ndarray, shape (lanes, steps) or None
        The time history (with "history").
    failed : ndarray of bool, shape (lanes,)
        Lanes whose state became non-finite; ``messages`` says when.
    """

    f_e_hz: np.ndarray
    p_a_n: np.ndarray
    model: str
    steps_per_period: int
    periods: int
    record_periods: int
    y_final: np.ndarray
    v_final: np.ndarray
    failed: np.ndarray
    messages: list[str] = field(default_factory=list)
    ymin: np.ndarray | None = None
    ymax: np.ndarray | None = None
    extrema: list[np.ndarray] | None = None
    history_phase: np.ndarray | None = None
    history_y: np.ndarray | None = None
    history_v: np.ndarray | None = None
    elapsed_s: float = 0.0

    @property
    def app(self) -> np.ndarray:
        """Peak-to-peak amplitude A_pp = ymax - ymin [m] (Section 3)."""
        if self.ymin is None:
            raise ValueError("`app` needs record='minmax' or 'extrema'.")
        return self.ymax - self.ymin

    @property
    def lanes(self) -> int:
        return self.f_e_hz.shape[0]

    def __str__(self) -> str:
        return (
            f"Simulation: {self.lanes} lanes x {self.periods} periods x "
            f"{self.steps_per_period} steps, {int(self.failed.sum())} failed, "
            f"{self.elapsed_s:.3g} s [{self.model}]"
        )
