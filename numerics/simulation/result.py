"""The result object of a simulation."""

from __future__ import annotations

import numpy as np

from perturb.common import Result, Status, result

__all__ = ["Simulation"]


@result
class Simulation(Result):
    """What a batched RK4 run measured, per lane, with what made it.

    Attributes
    ----------
    frequency_hz, p_a_n : ndarray, shape (lanes,)
        Excitation frequency [Hz] and force amplitude [N] of each lane.
    model : dict
        The model that ran: its parameters and effects (``ContactModel.as_dict()``).
    settings : dict
        steps_per_period, periods (run in all), record_periods, record, max_extrema.
    status : ndarray of int, shape (lanes,)
        ``common.Status``: 0 ran to the end, -1 failed (non-finite or diverged).
    message : list of str
        Per lane, why it failed, with a step-size hint where the step is too large.
    y_final_m, v_final_m_s : ndarray, shape (lanes,)
        State at the end [m, m/s].
    ymin_m, ymax_m : ndarray, shape (lanes,) or None
        Extremes of y over the recorded periods (with "minmax" or "extrema").
    extrema : list of ndarray, shape (k, 3) or None
        Per lane, rows (phase in periods from the start of the recording,
        y [m], +1 maximum / -1 minimum) (with "extrema").
    history_phase : ndarray, shape (steps,) or None
        Phase in periods, since the start of the recording, of each stored step.
    history_y_m, history_v_m_s : ndarray, shape (lanes, steps) or None
        The time history (with "history").
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane
    NOT_PER_LANE = ("history_phase",)  # the phases of the recorded steps

    frequency_hz: np.ndarray
    p_a_n: np.ndarray
    model: dict
    settings: dict
    status: np.ndarray
    message: list[str]
    y_final_m: np.ndarray
    v_final_m_s: np.ndarray
    ymin_m: np.ndarray | None = None
    ymax_m: np.ndarray | None = None
    extrema: list[np.ndarray] | None = None
    history_phase: np.ndarray | None = None
    history_y_m: np.ndarray | None = None
    history_v_m_s: np.ndarray | None = None
    elapsed_s: float = 0.0

    @property
    def app_m(self) -> np.ndarray:
        """Peak-to-peak amplitude A_pp = ymax - ymin [m] (Section 3)."""
        if self.ymin_m is None:
            raise ValueError("`app_m` needs record='minmax' or 'extrema'.")
        return self.ymax_m - self.ymin_m

    @property
    def failed(self) -> np.ndarray:
        return self.status == Status.FAILED

    @property
    def lanes(self) -> int:
        return self.frequency_hz.shape[0]

    def table(self, rows: int = 20) -> str:
        """One row per lane (the first ``rows``): f_e, P_a, status, App if recorded."""
        app = self.app_m if self.ymin_m is not None else np.full(self.lanes, np.nan)
        lines = [f"  {'f_e [Hz]':>10} {'P_a [N]':>10} {'status':<8} {'App [nm]':>11}  message"]
        lines += [f"  {self.frequency_hz[i]:>10.6g} {self.p_a_n[i]:>10.4g} "
                  f"{Status(self.status[i]).name:<8} {app[i] * 1e9:>11.4g}  {self.message[i]}"
                  for i in range(min(self.lanes, rows))]
        if self.lanes > rows:
            lines.append(f"  ... {self.lanes - rows} more lanes")
        return "\n".join(lines)

    def summary(self) -> str:
        s = self.settings
        return (
            f"Simulation: {self.lanes} lanes x {s['periods']} periods x "
            f"{s['steps_per_period']} steps, {int(self.failed.sum())} failed, "
            f"{self.elapsed_s:.3g} s"
        )
