"""The analytic forced response of each order against RK4 steady states.

``perturb.frequency_response`` solves the series of Eq. 2.6 for every response
at each excitation frequency, with a validity flag (no contact loss, last
the next two orders change it by < 1 %). The RK4 steady states come from frequency sweeps up
and down (``numerics.sweep``), as in the paper, for two models: Eq. 2.6 itself
(quadratic spring, linear damping, no contact loss), which the series should
reproduce, and the full piecewise model of Eq. 2.1-2.4, from which it parts
where the slider loses contact or the damping's dependence on y matters.
"""

from __future__ import annotations

import numpy as np

from perturb import (
    EQ_2_6,
    FULL,
    PAPER,
    ContactModel,
    ContactParameters,
    Response,
    eq26_numbers,
    frequency_response,
)
from perturb.common import Result, check_choice, result

from ..steady.orbits import Orbits
from ..steady.shooting import steady_states
from ..steady.sweeps import sweep

__all__ = ["SteadyCurve", "PeakCheck", "ResponseComparison", "steady_curve", "compare_response",
           "MODELS", "SUPERHARMONICS", "UNMATCHED"]

#: The two RK4 models the series is held against.
MODELS = {"eq26": EQ_2_6, "full": FULL}
#: The resonances checked, f_e ~ f_n0 / k (Eq. 3.1): primary, 1/2 and 1/3.
SUPERHARMONICS = (1, 2, 3)
#: Window searched for each peak, in units of f_n0 / k. Peaks bend to lower
#: frequencies; the primary (k = 1) the most: once contact is lost its upper
#: branch reaches past f_n0 / 2 (the paper's 740 Hz at 0.15Q; RK4 follows it to 370 Hz).
PEAK_WINDOWS = {1: (0.15, 1.08), 2: (0.8, 1.08), 3: (0.8, 1.08)}
#: A state farther than this (relative App) from the valid root nearest to it has
#: no counterpart in the series: the series' fold falls at another frequency (its
#: upper branch ends before RK4's does), or it lacks the branch. Such states still
#: count in ``largest_error``; ``largest_matched_error`` leaves them out.
UNMATCHED = 0.1


@result
class SteadyCurve(Orbits):
    """RK4 steady states of one model at one P_a, from sweeps up and down.

    The ``Orbits`` columns hold the up sweep's points, then the down sweep's, on
    the same grid (increasing frequency in both halves).
    """

    NOT_PER_LANE = ("notes",)

    model_name: str
    pa_frac: float
    direction: np.ndarray
    notes: list[str]


@result
class PeakCheck(Result):
    """Place and height of one resonance peak f_e ~ f_n0 / k, from RK4 and from the series."""

    k: int
    rk4_hz: float
    rk4_app_m: float
    series_hz: float
    series_app_m: float

    @property
    def height_ratio(self) -> float:
        return self.series_app_m / self.rk4_app_m

    def derived(self) -> dict:
        return {"height_ratio": self.height_ratio}


@result
class ResponseComparison(Result):
    """The order-N series against the RK4 steady states of one model at one P_a.

    Attributes
    ----------
    model_name, pa_frac, order
        Which RK4 model ("eq26" or "full"), force amplitude and series order.
    frequency_hz, rk4_app_m, contact_lost : ndarray, shape (states,)
        The settled RK4 states.
    series_app_m, relative_error : ndarray, shape (states,)
        The valid analytic response nearest to each state, and
        |App_series / App_RK4 - 1|; NaN where the series is not valid.
    unmatched : ndarray of bool, shape (states,)
        States where the series is valid but no response of it lies within
        ``UNMATCHED`` (a fold elsewhere, or a branch the series lacks).
    largest_error : float
        The largest error over every state where the series is valid, the
        unmatched ones included (NaN if there are none).
    largest_matched_error : float
        The same over the matched states only.
    peaks : list of PeakCheck
        The primary, 1/2 and 1/3 superharmonic peaks (Eq. 3.1).
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane
    NOT_PER_LANE = ("peaks",)

    model_name: str
    pa_frac: float
    order: int
    frequency_hz: np.ndarray
    rk4_app_m: np.ndarray
    contact_lost: np.ndarray
    series_app_m: np.ndarray
    relative_error: np.ndarray
    unmatched: np.ndarray
    largest_error: float
    largest_matched_error: float
    peaks: list[PeakCheck]

    @property
    def matched(self) -> np.ndarray:
        """States where the series is valid and has a response within UNMATCHED."""
        return np.isfinite(self.relative_error) & ~self.unmatched

    def derived(self) -> dict:
        return {"unmatched_hz": self.frequency_hz[self.unmatched]}

    def summary(self) -> str:
        return (f"ResponseComparison: order {self.order} against {self.model_name} at "
                f"P_a = {self.pa_frac:g} Q, largest error {self.largest_error:.2g}")


def _one_direction(grid, pa_frac, model, direction, steps) -> Orbits | str:
    """The points of one sweep, on the increasing grid; a message if the sweep breaks down."""
    try:
        run = sweep(grid, pa_frac, direction=direction, model=model, unchecked=True,
                    steps_per_period=steps).runs[0]
    except ValueError as error:  # a lane went non-finite (Eq. 2.6 escapes past its barrier)
        return f"{direction} sweep failed ({error}); steady states from rest instead"
    order = np.arange(grid.size)
    return run.take(order[::-1] if direction == "down" else order)


def steady_curve(grid, pa_frac: float, model_name: str, steps_per_period: int = 128,
                 parameters: ContactParameters = PAPER) -> SteadyCurve:
    """RK4 steady states of ``MODELS[model_name]`` with ``parameters`` along sweeps up and
    down of ``grid``."""
    check_choice("model_name", model_name, sorted(MODELS))
    model = ContactModel(parameters, MODELS[model_name])
    parts, notes = [], []
    for direction in ("up", "down"):
        found = _one_direction(grid, pa_frac, model, direction, steps_per_period)
        if isinstance(found, str):
            notes.append(found)
            found = steady_states(grid, pa_frac * model.parameters.Q_n, model=model,
                                  steps_per_period=steps_per_period)
        parts.append(found)
    return SteadyCurve(model_name=model_name, pa_frac=pa_frac,
                       direction=np.repeat(["up", "down"], grid.size), notes=notes,
                       **Orbits.stack(parts).columns())


def steady_curves(grid, pa_fracs, model_name: str, steps_per_period: int = 128,
                  parameters: ContactParameters = PAPER) -> list[SteadyCurve]:
    """``steady_curve`` at each of ``pa_fracs``, the sweeps of all amplitudes and both
    directions in one batched call (lanes are independent: the same states, some 3x
    faster than one call each); where that call breaks down, amplitude by amplitude."""
    check_choice("model_name", model_name, sorted(MODELS))
    model = ContactModel(parameters, MODELS[model_name])
    # The ranges are the caller's to check (``compare`` does): a ValueError here is a
    # lane that went non-finite.
    try:
        runs = sweep(grid, list(pa_fracs), direction="both", model=model,
                     steps_per_period=steps_per_period, unchecked=True)
    except ValueError:  # a lane went non-finite: find which amplitude, one by one
        return [steady_curve(grid, frac, model_name, steps_per_period, parameters)
                for frac in pa_fracs]
    order = np.arange(grid.size)
    curves = []
    for frac in pa_fracs:
        parts = [runs.run(frac, "up").take(order),
                 runs.run(frac, "down").take(order[::-1])]
        curves.append(SteadyCurve(model_name=model_name, pa_frac=frac,
                                  direction=np.repeat(["up", "down"], grid.size), notes=[],
                                  **Orbits.stack(parts).columns()))
    return curves


def _responses(response, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(frequencies, branches) matrices of the analytic App (NaN where no root) and validity."""
    app = np.full((grid.size, max(len(response.branches), 1)), np.nan)
    valid = np.zeros(app.shape, dtype=bool)
    for j, branch in enumerate(response.branches):
        rows = np.searchsorted(grid, branch.frequency_hz)
        app[rows, j], valid[rows, j] = branch.app_m, branch.valid
    return app, valid


def relative_difference(series: np.ndarray, rk4: np.ndarray) -> np.ndarray:
    """|series / rk4 - 1|; 0 where both are 0 (no force: rest), inf where only rk4 is."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(series / rk4 - 1)
    return np.where((rk4 == 0) & (series == 0), 0.0, ratio)


def _nearest(app: np.ndarray, valid: np.ndarray, rows: np.ndarray, target: np.ndarray):
    """Per state, the analytic root of its frequency nearest in App, and whether it is valid."""
    candidates = app[rows]
    distance = relative_difference(candidates, target[:, None])
    best = np.argmin(np.where(np.isnan(distance), np.inf, distance), axis=1)
    picked = candidates[np.arange(rows.size), best]
    return picked, valid[rows, best] & np.isfinite(picked)


def _envelope(frequency: np.ndarray, app: np.ndarray, highest: bool):
    """The highest (or lowest) App at each frequency, frequencies sorted."""
    keep = np.isfinite(app)
    grid = np.unique(frequency[keep])
    envelope = np.full(grid.size, -np.inf if highest else np.inf)
    rows = np.searchsorted(grid, frequency[keep])
    (np.maximum if highest else np.minimum).at(envelope, rows, app[keep])
    return grid, envelope


def _peak(frequency, app, centre, window) -> tuple[float, float]:
    """The highest local maximum of App(f) strictly inside ``window`` (units of ``centre``).

    A maximum at the window's edge is the flank of a neighbouring peak, not a peak.
    """
    inside = np.flatnonzero((frequency >= window[0] * centre) & (frequency <= window[1] * centre))
    if inside.size < 3:
        return np.nan, np.nan
    a = app[inside]
    local = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    if local.size == 0:
        return np.nan, np.nan
    best = inside[local[np.argmax(a[local])]]
    return float(frequency[best]), float(app[best])


def _peaks(states_f, states_app, series_f, series_app, f_n0) -> list[PeakCheck]:
    """Place and height of the primary (k = 1) and superharmonic (k >= 2) peaks.

    The primary is sought on the highest response at each frequency, the
    superharmonics on the lowest: where the bent primary coexists with them,
    they are the other solution.
    """
    checks = []
    for k in SUPERHARMONICS:
        rk4 = _envelope(states_f, states_app, highest=k == 1)
        series = _envelope(series_f, series_app, highest=k == 1)
        window = PEAK_WINDOWS[k]
        rk4_peak = _peak(*rk4, f_n0 / k, window)
        series_peak = _peak(*series, f_n0 / k, window)
        checks.append(PeakCheck(k=k, rk4_hz=rk4_peak[0], rk4_app_m=rk4_peak[1],
                                series_hz=series_peak[0], series_app_m=series_peak[1]))
    return checks


def compare_response(
    curve: SteadyCurve, order: int, grid: np.ndarray, app_limit_m: float = np.inf,
    parameters: ContactParameters = PAPER, response: Response | None = None,
) -> ResponseComparison:
    """The order-N analytic response against the settled states of ``curve`` (computed
    with ``parameters``).

    Each RK4 state is matched with the analytic root of its frequency nearest in
    App. The series counts as valid for the state when that root is flagged
    valid (no contact loss, next orders change it by < 1 %) and the state's App
    is within ``app_limit_m``, the range where the order's backbone holds.
    ``response`` is the series' ``frequency_response`` on ``grid`` at the curve's P_a,
    if already solved (one serves the curves of both models); solved here if None.
    """
    if response is None:
        response = frequency_response(grid, curve.pa_frac, order, parameters=parameters,
                                      truncation="paper")
    elif differences := _differences(response, order, curve.pa_frac, grid):
        raise ValueError(f"`response` is not the series asked for: {'; '.join(differences)}.")
    app_table, valid_table = _responses(response, grid)
    keep = curve.settled & np.isfinite(curve.app_m)
    frequency, app = curve.frequency_hz[keep], curve.app_m[keep]
    nearest, valid = _nearest(app_table, valid_table, np.searchsorted(grid, frequency), app)
    series = np.where(valid & (app <= app_limit_m), nearest, np.nan)
    error = relative_difference(series, app)
    unmatched = error > UNMATCHED
    matched = np.isfinite(error) & ~unmatched
    shown = np.where(valid_table, app_table, np.nan).ravel()
    peaks = _peaks(frequency, app, np.repeat(grid, app_table.shape[1]), shown,
                   eq26_numbers(parameters).f_n0_hz)
    return ResponseComparison(
        model_name=curve.model_name, pa_frac=curve.pa_frac, order=order, frequency_hz=frequency,
        rk4_app_m=app, contact_lost=curve.contact_lost[keep], series_app_m=series,
        relative_error=error,
        unmatched=unmatched, largest_error=_largest(error, np.isfinite(error)),
        largest_matched_error=_largest(error, matched), peaks=peaks,
    )


def _differences(response: Response, order: int, pa_frac: float, grid) -> list[str]:
    """What sets a given ``response`` apart from the series of ``order`` at ``pa_frac`` on
    ``grid`` (its order, its amplitude, its grid), each said; [] if nothing does."""
    differences = []
    if response.order != order:
        differences.append(f"its order is {response.order}, not {order}")
    if response.pa_frac != pa_frac:
        differences.append(f"its P_a is {response.pa_frac} Q, not the curve's {pa_frac} Q")
    theirs, ours = np.asarray(response.frequency_hz), np.asarray(grid)
    if theirs.shape != ours.shape:
        differences.append(f"its grid has {theirs.size} points ({_span(theirs)}), `grid` "
                           f"{ours.size} ({_span(ours)})")
    elif not np.array_equal(theirs, ours):
        at = np.flatnonzero(theirs != ours)
        first = (float(theirs[at[0]]), float(ours[at[0]]))  # every digit: may be a rounding
        differences.append(f"its grid differs from `grid` at {at.size} of {ours.size} "
                           f"points, first at {first[0]!r} Hz against {first[1]!r} Hz")
    return differences


def _span(grid: np.ndarray) -> str:
    return f"{grid.min():g}-{grid.max():g} Hz" if grid.size else "none"


def _largest(error: np.ndarray, where: np.ndarray) -> float:
    return float(error[where].max()) if where.any() else np.nan
