"""The steady-state observables of a set of points: one record type.

Steady states, sweep runs, the census's lanes and the comparison's curves all
hold these columns, one row per point (lane); each adds its own context (the
model and settings, the sweep's amplitude and direction, ...).
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from perturb.common import Result, Status, result

__all__ = ["Orbits", "fates"]

# Plain integers for the comparisons made once per point of a sweep (an IntEnum
# member lookup costs more than the comparison itself).
_SUCCESS, _FAILED = int(Status.SUCCESS), int(Status.FAILED)


@result
class Orbits(Result):
    """Per point: the steady state found, its observables, and how it was reached.

    Attributes
    ----------
    frequency_hz, p_a_n : ndarray, shape (points,)
        Excitation frequency f_e [Hz] and force amplitude P_a [N].
    status : ndarray of int
        ``common.Status``: 0 settled, 1 not settled, -1 failed, 2 under-resolved.
    message : list of str
        Why a point has its status ("" when settled).
    period : ndarray of int
        p, the period of the orbit in excitation periods (0 if not settled).
    ymin_m, ymax_m : ndarray
        Extremes of y over one period of the response (p excitation periods).
    maxima_m, minima_m : list of ndarray
        Every local maximum and minimum of y over that period (Fig. 3).
    y_start_m, v_start_m_s : ndarray
        The state at phase 0 on the orbit [m, m/s] (the last state if not settled).
    multipliers : ndarray, shape (points, 2), complex
        Floquet multipliers of the orbit (NaN where not computed).
    method : ndarray of str
        "newton", "march+newton", "march", or "none".
    steps_used : ndarray of int
        RK4 steps per period of the point's result (after refinement).
    periods_run : ndarray of int
        Excitation periods integrated for the point (its cost).
    error_estimate : ndarray
        Estimated relative error of App from the step: |App(N) - App(N/2)| / App(N),
        one period from the orbit's start at half the steps (conservative: RK4 is
        about second order through loss of contact, fourth in contact); inf where
        the step is too coarse to estimate it, NaN where nothing settled or no
        estimate was asked for.
    orbit_y_m : list of ndarray, optional
        y after every step of one orbit (kept when asked for: the census).
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    frequency_hz: np.ndarray
    p_a_n: np.ndarray
    status: np.ndarray
    message: list[str]
    period: np.ndarray
    ymin_m: np.ndarray
    ymax_m: np.ndarray
    maxima_m: list[np.ndarray]
    minima_m: list[np.ndarray]
    y_start_m: np.ndarray
    v_start_m_s: np.ndarray
    multipliers: np.ndarray
    method: np.ndarray
    steps_used: np.ndarray
    periods_run: np.ndarray
    error_estimate: np.ndarray
    orbit_y_m: list[np.ndarray] | None = None

    @classmethod
    def empty(cls, frequency_hz, p_a_n, steps: int) -> "Orbits":
        """Nothing found yet: every point not settled, at ``steps`` per period."""
        n = frequency_hz.shape[0]
        return cls(
            frequency_hz=frequency_hz, p_a_n=p_a_n,
            status=np.full(n, Status.NOT_SETTLED, dtype=np.int64), message=[""] * n,
            period=np.zeros(n, dtype=np.int64), ymin_m=np.full(n, np.nan),
            ymax_m=np.full(n, np.nan), maxima_m=[np.empty(0)] * n, minima_m=[np.empty(0)] * n,
            y_start_m=np.full(n, np.nan), v_start_m_s=np.full(n, np.nan),
            multipliers=np.full((n, 2), np.nan, dtype=complex),
            method=np.full(n, "none", dtype=object), steps_used=np.full(n, steps, dtype=np.int64),
            periods_run=np.zeros(n, dtype=np.int64), error_estimate=np.full(n, np.nan),
        )

    @property
    def app_m(self) -> np.ndarray:
        """A_pp = ymax - ymin [m] (Fig. 2)."""
        return self.ymax_m - self.ymin_m

    @property
    def settled(self) -> np.ndarray:
        return self.status == _SUCCESS

    @property
    def failed(self) -> np.ndarray:
        return self.status == _FAILED

    @property
    def orbit_found(self) -> np.ndarray:
        """Settled or under-resolved: an orbit was found (an under-resolved one's error
        estimate is above ``app_rtol``, but it is an orbit; a sweep continues from it)."""
        return (self.status == _SUCCESS) | (self.status == int(Status.UNDER_RESOLVED))

    @property
    def contact_lost(self) -> np.ndarray:
        """ymin < 0: the slider leaves the slideway (Fig. 3b-j)."""
        return self.ymin_m < 0

    def derived(self) -> dict:
        return {"app_m": self.app_m, "settled": self.settled, "contact_lost": self.contact_lost}

    def summary(self) -> str:
        counts = {str(m): int((self.method == m).sum()) for m in np.unique(self.method.astype(str))}
        return (f"{type(self).__name__}: {int(self.settled.sum())}/{self.status.size} settled, "
                f"periods {sorted(set(self.period.tolist()))}, {counts}")

    def fates(self) -> str:
        """How many points did not settle, were under-resolved or failed ("" if none)."""
        return fates(self.status)

    def columns(self) -> dict:
        """The record's fields, by name (to build a subclass from them)."""
        return {f.name: getattr(self, f.name) for f in fields(Orbits)}

    def take(self, index) -> "Orbits":
        """The points ``index`` (an integer array), as a new record."""
        index = np.asarray(index)
        return Orbits(**{name: _take(value, index) for name, value in self.columns().items()})

    def put(self, index, other: "Orbits") -> None:
        """Overwrite the points ``index`` with ``other``'s points, in order."""
        for name, value in self.columns().items():
            new = getattr(other, name)
            if isinstance(value, np.ndarray):
                value[index] = new
            elif new is not None:
                if value is None:  # the first part that keeps this column
                    value = [np.empty(0)] * self.status.size
                    setattr(self, name, value)
                for j, i in enumerate(np.asarray(index)):
                    value[i] = new[j]

    @staticmethod
    def stack(parts: list["Orbits"]) -> "Orbits":
        """The points of every part, one after the other."""
        columns = {}
        for name in parts[0].columns():
            values = [getattr(p, name) for p in parts]
            if values[0] is None:
                columns[name] = None
            elif isinstance(values[0], np.ndarray):
                columns[name] = np.concatenate(values)
            else:
                columns[name] = [item for value in values for item in value]
        return Orbits(**columns)


def _take(value, index):
    if value is None:
        return None
    if isinstance(value, np.ndarray):
        return value[index]
    return [value[i] for i in index]


def fates(status: np.ndarray) -> str:
    """How many of ``status`` did not settle, were under-resolved or failed ("" if none)."""
    names = {Status.NOT_SETTLED: "not settled", Status.UNDER_RESOLVED: "under-resolved",
             Status.FAILED: "failed"}
    counts = {name: int((status == s).sum()) for s, name in names.items()}
    return ", ".join(f"{count} {name}" for name, count in counts.items() if count)
