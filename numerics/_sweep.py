"""Frequency sweeps up and down, for many force amplitudes at once (Fig. 2, 3).

Each point starts from the previous point's steady state, as in the paper's
method; every (amplitude, direction) pair is a lane, and all lanes advance
through their frequency lists together.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import numpy as np

from perturb import ContactModel

from ._info import model_info
from common import progress
from ._simulate import static_deflection
from ._steady import DEFAULTS, steady_states
from ._validate import lane_array, positive_int

__all__ = ["SweepRun", "Sweep", "sweep", "DIRECTIONS"]

DIRECTIONS = ("up", "down", "both")


@dataclass
class SweepRun:
    """One amplitude swept in one direction; lists are in the order swept."""

    pa_frac: float
    direction: str
    frequency_hz: list[float]
    app_m: list[float]
    ymin_m: list[float]
    ymax_m: list[float]
    maxima_m: list[list[float]]
    minima_m: list[list[float]]
    period: list[int]
    settled: list[bool]
    method: list[str] = field(default_factory=list)
    y_start_m: list[float] = field(default_factory=list)  # the orbit's state at phase 0
    v_start_m: list[float] = field(default_factory=list)
    steps_used: list[int] = field(default_factory=list)  # RK4 steps per period of each point

    @property
    def contact_lost(self) -> np.ndarray:
        return np.asarray(self.ymin_m) < 0

    def jumps(self, ratio: float = 1.3) -> list[int]:
        """Indices i where App jumps by more than ``ratio`` from point i-1 to i."""
        app = np.asarray(self.app_m)
        change = np.maximum(app[1:] / app[:-1], app[:-1] / app[1:])
        return (np.flatnonzero(change > ratio) + 1).tolist()


@dataclass
class Sweep:
    """All runs of a sweep, with the model and the settings that made them."""

    model: dict
    settings: dict
    runs: list[SweepRun]
    elapsed_s: float

    def as_dict(self) -> dict:
        return {"model": self.model, "settings": self.settings,
                "runs": [_run_dict(r) for r in self.runs], "elapsed_s": self.elapsed_s}

    def run(self, pa_frac: float, direction: str) -> SweepRun:
        for r in self.runs:
            if np.isclose(r.pa_frac, pa_frac) and r.direction == direction:
                return r
        raise KeyError(f"no run with pa_frac={pa_frac}, direction={direction!r}")

    def __str__(self) -> str:
        points = sum(len(r.frequency_hz) for r in self.runs)
        unsettled = sum(not s for r in self.runs for s in r.settled)
        return (f"Sweep: {len(self.runs)} runs, {points} points, {unsettled} not settled, "
                f"{self.elapsed_s:.3g} s")


def _run_dict(run: SweepRun) -> dict:
    """The documented JSON keys of a run (method and orbit states stay in Python)."""
    out = asdict(run)
    for key in ("method", "y_start_m", "v_start_m", "steps_used"):
        out.pop(key)
    return out


def sweep(
    frequencies_hz,
    pa_fracs,
    *,
    direction: str = "both",
    model: ContactModel | None = None,
    steps_per_period: int = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int = DEFAULTS["max_periods"],
    method: str = "newton",
    refinements: int = DEFAULTS["refinements"],
    quiet: bool = True,
) -> Sweep:
    """Sweep the excitation frequency up and/or down for each force amplitude.

    Parameters
    ----------
    frequencies_hz : array_like
        The frequency grid [Hz], increasing; "down" runs take it in reverse.
    pa_fracs : array_like
        Force amplitudes P_a as fractions of the weight Q.
    direction : {"up", "down", "both"}
    model : ContactModel, optional
    steps_per_period, tol, max_periods, method, refinements
        As in ``steady_states``.
    quiet : bool
        No progress bar on stderr.

    Examples
    --------
    >>> result = sweep([1300.0, 1350.0, 1400.0], [0.05], direction="up")
    >>> [round(a * 1e9, 1) for a in result.runs[0].app_m]
    [48.1, 65.0, 106.1]
    """
    if direction not in DIRECTIONS:
        raise ValueError(f"`direction` must be one of {DIRECTIONS}, got {direction!r}.")
    model = ContactModel() if model is None else model
    grid = lane_array("frequencies_hz", frequencies_hz, positive=True)
    if grid.size > 1 and np.any(np.diff(grid) <= 0):
        raise ValueError("`frequencies_hz` must be strictly increasing.")
    fracs = lane_array("pa_fracs", pa_fracs)
    positive_int("steps_per_period", steps_per_period, minimum=4)
    directions = ("up", "down") if direction == "both" else (direction,)
    lanes = [(frac, d) for frac in fracs for d in directions]
    order = {"up": grid, "down": grid[::-1]}
    freq = np.array([order[d] for _, d in lanes])  # (lanes, points)
    p_a = np.array([frac for frac, _ in lanes]) * model.parameters.weight_n

    start = time.perf_counter()
    columns = _sweep_lanes(freq, p_a, model, quiet, steps_per_period=steps_per_period, tol=tol,
                           max_periods=max_periods, method=method, refinements=refinements)
    runs = [
        SweepRun(pa_frac=float(frac), direction=d, frequency_hz=freq[i].tolist(),
                 **{key: [value[j][i] for j in range(grid.size)] for key, value in columns.items()})
        for i, (frac, d) in enumerate(lanes)
    ]
    settings = {"frequencies_hz": [float(grid[0]), float(grid[-1]), int(grid.size)],
                "pa_fracs": fracs.tolist(), "direction": direction,
                "steps_per_period": steps_per_period, "tol": tol, "max_periods": max_periods,
                "method": method, "refinements": refinements, "effects": model.effects.label(),
                "parameters": model.parameters.as_dict()}
    return Sweep(model=model_info(model),
                 settings=settings, runs=runs, elapsed_s=time.perf_counter() - start)


def _sweep_lanes(freq, p_a, model, quiet, **accuracy) -> dict:
    """Walk every lane through its frequencies; return per-point columns."""
    points = freq.shape[1]
    columns = {k: [] for k in ("app_m", "ymin_m", "ymax_m", "maxima_m", "minima_m", "period",
                               "settled", "method", "y_start_m", "v_start_m", "steps_used")}
    y = v = span = None
    period = 1
    rest = static_deflection(model)
    bar = progress(points, "sweep", quiet=quiet)
    for j in range(points):
        found = steady_states(freq[:, j], p_a, model=model, y_init=y, v_init=v,
                              period_guess=period, span_guess=span, **accuracy)
        # The next point starts from this point's orbit (or last state, if unsettled);
        # a lane whose state blew up (a reduced model with no floor) starts from rest.
        blown = ~(np.isfinite(found.y_start) & np.isfinite(found.v_start))
        y = np.where(blown, rest, found.y_start)
        v = np.where(blown, 0.0, found.v_start)
        span = np.where(found.settled & ~blown, found.app, 0.0)
        period = np.maximum(found.period, 1)
        columns["app_m"].append(found.app.tolist())
        columns["ymin_m"].append(found.ymin.tolist())
        columns["ymax_m"].append(found.ymax.tolist())
        columns["maxima_m"].append([m.tolist() for m in found.maxima])
        columns["minima_m"].append([m.tolist() for m in found.minima])
        columns["period"].append(found.period.tolist())
        columns["settled"].append(found.settled.tolist())
        columns["method"].append(found.method.tolist())
        columns["y_start_m"].append(found.y_start.tolist())
        columns["v_start_m"].append(found.v_start.tolist())
        columns["steps_used"].append(found.steps_used.tolist())
        bar.update()
    bar.close()
    return columns
