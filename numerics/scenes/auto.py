"""``effects = "auto"``: the fewest effects that keep a scene's observables within its tolerance.

The full model is run on a sample of the scene's points; then the effects are
switched off one after the other, each on top of those already dropped (the
spring simplified step by step: linear, then Taylor polynomials of rising
degree), and the change of every observable is measured against the full model
on the same sample. An effect is dropped when the change stays below half the
tolerance (a margin for the points between the samples).

The model without the dropped effects then runs the scene, and is checked
against the full model at every point. For a sweep, the full model takes every
step of the sweep, continuing from the chosen model's orbit at the point before
(from rest at a run's first point; the steps run as lanes of one sweep, those
from rest and those from an orbit in two batches): a step that lands elsewhere
than the chosen orbit (a coexisting orbit the chosen model lacks, or none
settled) is where the paths part. Where every step lands within the tolerance,
the full model's sweep, started from its own orbits within the tolerance of the
chosen ones, takes the same path, but for a seed that falls on the other side of
a basin's boundary near a fold: the windows below follow the full model's own
orbits there. The full model also runs through a window of the scene's grid around each
sensitive point (the peaks of each curve, the superharmonic ones included, both
sides of every jump, where contact is nearest to being lost, and where the
chosen model differed most on the sample), continuing from the chosen model's
orbit just before the window, as the scene's own sweep would. Censuses and time
histories, whose points do not depend on each other, are compared with the full
model run at every point. If the chosen model is off by more than the tolerance
anywhere, or a point did not settle in it, the scene runs the full model and
says where.

For a sweep asking for App and extrema only, the consistent perturbation series
of the contact's own laws is tried first as the route (``series_route.py``):
where it is a candidate and within the margin of the full model on the sample,
it is checked as the chosen model would be, step by step and through the
windows, and where it passes nothing is simulated for the scene.

The change of an observable is the largest, over the points, of its difference
from the full model divided by the curve's scale: the largest App of the curve
(for App, the extrema and the orbit), the largest harmonic (for the spectrum);
the fraction of a period out of contact is compared as it is.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from perturb import FULL, Effects, eq26_numbers

from ..steady.options import ACCURACY_FIELDS, SteadyOptions
from ..steady.orbits import Orbits
from .observables import observe, orbit_observables
from .schema import Scene
from .series_route import SERIES_EFFECTS, SERIES_LABEL, series_study
from .studies import StudyRun, model_of, run_study

__all__ = ["Selection", "select_effects", "observable_change", "SAMPLE_POINTS", "MARGIN"]

#: Frequencies of the scene's grid on which each effect is measured (evenly picked).
SAMPLE_POINTS = 24
#: An effect is dropped when switching it off changes every observable by less than
#: this fraction of the tolerance: the changes of the dropped effects add up.
MARGIN = 0.5
#: Peaks of each curve that a sweep's windows visit (the highest, by App), and points where
#: the chosen model differed most on the sample.
SPOT_PEAKS = 4
#: A sweep's window around a sensitive point: this many points of the grid before it (a
#: fold of the full model a little earlier is crossed inside the window) and after it.
WINDOW_BEFORE, WINDOW_AFTER = 4, 2

#: Each effect and the simpler laws tried in its place, simplest first. The laws come
#: first: contact loss can be switched off only once the laws are polynomials.
SIMPLIFICATIONS: tuple[tuple[str, tuple[tuple[str, dict], ...]], ...] = (
    ("power-law spring", (("linearised at y0", {"spring": "linear"}),
                          ("Taylor, degree 2", {"spring": "taylor", "taylor_degree": 2}),
                          ("Taylor, degree 3", {"spring": "taylor", "taylor_degree": 3}),
                          ("Taylor, degree 4", {"spring": "taylor", "taylor_degree": 4}))),
    ("power-law damping", (("linearised at y0", {"damping": "linear"}),)),
    ("contact loss", (("switched off", {"contact_loss": False}),)),
    ("gravity preload", (("switched off", {"gravity": False}),)),
)


@dataclass
class Selection:
    """The effects chosen, the table that shows why, and the route."""

    effects: Effects
    rows: list[dict]
    note: str
    route: str
    study: StudyRun | None = None  # the scene's run with ``effects``, when already run


def sample_grid(grid: np.ndarray, points: int = SAMPLE_POINTS) -> np.ndarray:
    """``points`` frequencies of ``grid``, evenly spread, its ends included."""
    if grid.size <= points:
        return grid
    return grid[np.unique(np.round(np.linspace(0, grid.size - 1, points)).astype(int))]


def _evaluate(scene: Scene, effects: Effects, grid: np.ndarray) -> tuple[list[dict], float]:
    """The curves of the scene's study on ``grid`` with ``effects``, and the seconds it took
    (the model's kernels loaded, or compiled, before the clock starts)."""
    from ..kernels.codegen import compiled_kernels

    model = model_of(scene, effects)
    compiled_kernels(model)
    eq26_numbers(model.parameters)
    start = time.perf_counter()
    curves = observe(scene, run_study(scene, model, grid).outcomes, model)
    return curves, time.perf_counter() - start


def _scale(curve: dict) -> float:
    """The curve's length scale: its largest App (or the span of its orbit); where the
    slider rests (both 0), its largest |y|, about y0: a length of the model, never 1 m."""
    candidates = (("app_m", np.abs), ("y_m", np.ptp), ("ymax_m", np.abs), ("y_m", np.abs))
    for key, measure in candidates:
        if key in curve and np.size(curve[key]):
            with np.errstate(invalid="ignore"):
                scale = np.nanmax(measure(np.asarray(curve[key], dtype=float)))
            if np.isfinite(scale) and scale > 0:
                return float(scale)
    return 1.0


def _difference(a, b, scale: float) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return np.inf
    with np.errstate(invalid="ignore"):
        change = np.abs(a - b) / scale
    # A point that failed or did not settle (NaN) in either model cannot vouch for the
    # other: its change is infinite, and the effect is kept.
    return float(np.max(np.where(np.isnan(change), np.inf, change), initial=0.0))


def _spectrum_change(a: list, b: list) -> float:
    worst = 0.0
    for x, y in zip(a, b):
        n = min(len(x), len(y))
        scale = max(np.max(x[1:n], initial=0.0), 1e-300)
        worst = max(worst, _difference(x[1:n], y[1:n], scale))
    return worst


def observable_change(observables, full: list[dict], other: list[dict]) -> dict[str, float]:
    """Largest change of each observable from ``full`` to ``other`` (see the module's doc)."""
    if len(full) != len(other):  # e.g. a census that finds other attractors
        return {name: np.inf for name in observables}
    change = {}
    for name in observables:
        worst = 0.0
        for a, b in zip(full, other):
            worst = max(worst, _curve_change(name, a, b))
        change[name] = worst
    return change


def _curve_change(name: str, a: dict, b: dict, scale: float | None = None) -> float:
    """Change of observable ``name`` from curve ``a`` to ``b``, relative to ``scale``
    (by default ``a``'s own: pass the whole curve's when ``a`` is a piece of it)."""
    scale = _scale(a) if scale is None else scale
    if name == "app":
        return _difference(a["app_m"], b["app_m"], scale)
    if name == "extrema":
        return max(_difference(a["ymin_m"], b["ymin_m"], scale),
                   _difference(a["ymax_m"], b["ymax_m"], scale))
    if name == "contact_fraction":
        return _difference(a["contact_fraction"], b["contact_fraction"], 1.0)
    if name == "spectrum":
        spectra = (a["spectrum_m"], b["spectrum_m"])
        if isinstance(spectra[0], np.ndarray) and spectra[0].ndim == 1:
            spectra = ([spectra[0]], [spectra[1]])
        return _spectrum_change(*spectra)
    if name in ("time_history", "phase_portrait", "hysteresis"):
        return _difference(a["y_m"], b["y_m"], float(np.ptp(a["y_m"])) or 1.0)
    return 0.0


def select_effects(scene: Scene, quiet: bool = True) -> Selection:
    """Measure what each effect contributes on a sample of the scene, choose, run and check.

    The effects are switched off one after the other, each on top of those already
    dropped, and each change is measured against the full model: the last row that
    says "dropped" is the model chosen, measured as a whole. The chosen model then
    runs the scene (``Selection.study``) and is checked against the full model at
    every point; without a reduced model that passes, the selection is the full
    model, and the scene is left to run it.
    """
    sample = sample_grid(scene.frequency_hz)
    full, full_s = _evaluate(scene, FULL, sample)
    rows, chosen, chosen_s, chosen_curves = [], FULL, full_s, full
    for effect, laws in SIMPLIFICATIONS:
        for law, change in laws:
            label = f"{effect}: {law}"
            candidate = replace(chosen, **change)
            try:
                curves, seconds = _evaluate(scene, candidate, sample)
            except ValueError as error:  # e.g. no contact loss with a non-polynomial law
                reason = str(error).split(": use")[0]
                rows.append({"effect": label, "change": {}, "seconds": None,
                             "verdict": f"kept (cannot be switched off: {reason})"})
                break
            measured = observable_change(scene.observables, full, curves)
            small = max(measured.values(), default=0.0) <= MARGIN * scene.tolerance
            rows.append({"effect": label, "change": measured, "seconds": seconds,
                         "own_change": observable_change(scene.observables, chosen_curves,
                                                         curves),
                         "verdict": "dropped" if small else "kept"})
            if small:
                chosen, chosen_s, chosen_curves = candidate, seconds, curves
                break
    where = f"on {sample.size} of the scene's {scene.frequency_hz.size} frequencies"
    series = _series_route(scene, sample, full, full_s, where, rows)
    if series is not None:
        return series
    if chosen == FULL:
        return Selection(FULL, rows, f"every effect matters {where}: the full model ran "
                                     f"(full model {full_s:.3g} s there)", "full model")
    times = (f"time {where}: full model {full_s:.3g} s, chosen model {chosen_s:.3g} s "
             f"({full_s / max(chosen_s, 1e-9):.2g}x)")
    if scene.study == "sweep":
        sensitive = _sensitive(sample, full) | _worst(sample, full, chosen_curves)
        return _sweep_check(scene, chosen, rows, sensitive, times, quiet)
    return _pointwise_check(scene, chosen, rows, times, quiet)


def _verdict(scene, chosen, rows, check: str, largest: float, times: str,
             study: StudyRun) -> Selection:
    check += f": largest change {largest:.2e}, tolerance {scene.tolerance:g}"
    if not largest <= scene.tolerance:
        return Selection(FULL, rows, f"{check}: above the tolerance, so the full model ran; "
                                     f"{times}", "full model")
    return Selection(chosen, rows, f"ran {chosen.describe()}; {check}; {times}",
                     "reduced model", study)


def _pointwise_check(scene, chosen, rows, times, quiet) -> Selection:
    """Both models at every point of a scene whose points do not depend on each other
    (censuses, time histories): the check costs the full model's run."""
    model = model_of(scene, chosen)
    study = run_study(scene, model, quiet=quiet)
    curves = observe(scene, study.outcomes, model)
    full, _ = _evaluate(scene, FULL, scene.frequency_hz)
    worst = observable_change(scene.observables, full, curves)
    check = f"the full model at all {scene.frequency_hz.size} frequencies of the scene"
    return _verdict(scene, chosen, rows, check, max(worst.values(), default=0.0), times, study)


def _series_route(scene, sample, full, full_s, where, rows) -> Selection | None:
    """The series as the route, if it is a candidate (``series_route.py``), within the
    margin of the full model on the sample, and within the tolerance of the full model
    at every point and through the sweep's windows; its row is added to ``rows``."""
    margin = MARGIN * scene.tolerance
    on_grid, why_not, _ = series_study(scene, scene.frequency_hz, margin)
    row = {"effect": SERIES_LABEL, "change": {}, "seconds": None,
           "verdict": f"not a candidate ({why_not})"}
    rows.append(row)
    if on_grid is None:
        return None
    on_sample, _, seconds = series_study(scene, sample, margin)
    if on_sample is None:  # valid on the grid, so on the sample; said, should it differ
        row["verdict"] = "not a candidate (not valid on the sample)"
        return None
    curves = observe(scene, on_sample.outcomes, None)
    row.update(change=observable_change(scene.observables, full, curves), seconds=seconds)
    if not max(row["change"].values(), default=0.0) <= margin:
        row["verdict"] = "not taken (off the full model on the sample)"
        return None
    sensitive = _sensitive(sample, full) | _worst(sample, full, curves)
    largest, check = _against_full(scene, on_grid, sensitive)
    check += f": largest change {largest:.2e}, tolerance {scene.tolerance:g}"
    if not largest <= scene.tolerance:
        row["verdict"] = f"not taken ({check})"
        return None
    row["verdict"] = "taken: the route"
    times = (f"time {where}: full model {full_s:.3g} s, series {seconds:.3g} s "
             f"({full_s / max(seconds, 1e-9):.2g}x)")
    return Selection(SERIES_EFFECTS, rows, f"ran {SERIES_LABEL}; {check}; {times}", "series",
                     on_grid)


def _sweep_check(scene, chosen, rows, sensitive, times, quiet) -> Selection:
    """Run the scene's sweep with the chosen model, and check it (``_against_full``)."""
    study = run_study(scene, model_of(scene, chosen), quiet=quiet)
    largest, check = _against_full(scene, study, sensitive)
    return _verdict(scene, chosen, rows, check, largest, times, study)


def _against_full(scene, study: StudyRun, sensitive: set[float]) -> tuple[float, str]:
    """The full model through every step of the sweep ``study``, and through a window
    around every sensitive point (``_full_through``): the largest change, and the check
    in words.

    A step is the sweep's own: the full model at a point, continued from the chosen
    orbit before it (from rest at a run's first point). A step that lands elsewhere (a
    coexisting orbit the chosen model lacks, or none settled) is where the paths part.
    The steps run as lanes of one sweep (``_full_through``), the windows as another."""
    runs, curves = study.outcomes[0].runs, observe(scene, study.outcomes, None)
    points = Orbits.stack(runs)
    if not points.orbit_found.all():  # a point the chosen model did not settle cannot vouch
        return np.inf, (f"the chosen model did not settle at "
                        f"{points.frequency_hz[np.argmin(points.orbit_found)]:g} Hz")
    steps = [(r, i) for r, run in enumerate(runs) for i in range(run.status.size)]
    windows = [(r, first) for r, run in enumerate(runs)
               for first in _window_starts(run, sensitive)]
    largest, worst_at = 0.0, None
    for group, length in ((steps, 1), (windows, _window_length(runs[0]))):
        for (r, first), found in zip(group, _full_through(scene, study, group, length)):
            for k in range(found.status.size):  # point by point, to say where
                change = _window_change(scene, curves[r], found.take([k]), first + k)
                if not change <= largest:
                    largest, worst_at = change, float(runs[r].frequency_hz[first + k])
    check = (f"the full model through every step of the sweep from the chosen orbit before "
             f"it, and through {len(windows)} window{'s' * (len(windows) != 1)} of "
             f"{_window_length(runs[0])} points "
             f"around the peaks, jumps and sensitive points"
             + (f" (largest change at {worst_at:g} Hz)" if worst_at is not None else ""))
    return largest, check


def _accuracy(study: StudyRun) -> dict:
    """The sweep's accuracy settings, for the full model's checks."""
    settings = study.outcomes[0].settings
    options = SteadyOptions(**{name: settings[name] for name in ACCURACY_FIELDS},
                            **settings.get("steady_options", {}))
    return {"options": options, "keep_orbits": settings["keep_orbits"]}


def _window_length(run) -> int:
    return min(WINDOW_BEFORE + WINDOW_AFTER + 1, run.status.size)


def _window_starts(run, sensitive: set[float]) -> list[int]:
    """First indices (in the order swept) of the windows around the run's sensitive points:
    its peaks, both sides of its jumps, its least y_min and the sample's picks."""
    jumps = run.jumps()
    index = set(_peaks(np.asarray(run.app_m, dtype=float)).tolist()) | set(jumps)
    index |= {j - 1 for j in jumps}
    if np.isfinite(run.ymin_m).any():
        index.add(int(np.nanargmin(run.ymin_m)))
    index.update(int(np.argmin(np.abs(run.frequency_hz - f))) for f in sensitive)
    length = _window_length(run)
    return sorted({int(np.clip(i - WINDOW_BEFORE, 0, run.status.size - length))
                   for i in index})


def _full_through(scene, study: StudyRun, windows, length: int) -> list:
    """The full model's points in every window of ``length`` points (one ``Orbits``
    each), all windows run as lanes of one sweep. A window continues from the scene's
    last good orbit before it, as the scene's sweep did; with none (the start of a
    run), from rest."""
    from ..steady.sweeps import sweep_points

    model, runs = model_of(scene, FULL), study.outcomes[0].runs
    freq = np.array([runs[r].frequency_hz[first:first + length] for r, first in windows])
    p_a = np.array([runs[r].pa_frac for r, _ in windows]) * model.parameters.Q_n
    accuracy = _accuracy(study)
    seeds = [_last_good(runs[r], first) for r, first in windows]
    out = [None] * len(windows)
    for from_rest in (True, False):
        group = [w for w, seed in enumerate(seeds) if (seed is None) == from_rest]
        if not group:
            continue
        start = None if from_rest else Orbits.stack(
            [runs[windows[w][0]].take([seeds[w]]) for w in group])
        points = sweep_points(freq[group], p_a[group], model, True, start=start, **accuracy)
        for k, w in enumerate(group):  # points are stacked frequency by frequency
            out[w] = points.take(np.arange(k, points.status.size, len(group)))
    return out


def _last_good(run, first: int) -> int | None:
    """Index of the run's last orbit before ``first`` that seeded the next point."""
    good = np.flatnonzero(run.orbit_found[:first])
    return int(good[-1]) if good.size else None


def _window_change(scene, curve: dict, points, first: int) -> float:
    """Largest change of the scene's observables from the full model's window to the
    scene's run on the same points, relative to the scene's whole curve."""
    piece = slice(first, first + points.status.size)
    full = {"app_m": points.app_m, "ymin_m": points.ymin_m, "ymax_m": points.ymax_m}
    if points.orbit_y_m is not None:
        full.update(orbit_observables(scene.observables, points.orbit_y_m, points.period))
    chosen = {key: curve[key][piece] for key in full if key in curve}
    scale = _scale(curve)
    return max((_curve_change(name, full, chosen, scale) for name in scene.observables),
               default=0.0)


def _peaks(app: np.ndarray) -> np.ndarray:
    """Indices of the curve's local maxima of App (its ends included), highest first."""
    padded = np.r_[-np.inf, np.nan_to_num(app, nan=-np.inf), -np.inf]
    peak = (padded[1:-1] >= padded[:-2]) & (padded[1:-1] >= padded[2:]) & np.isfinite(app)
    index = np.flatnonzero(peak)
    return index[np.argsort(-app[index])][:SPOT_PEAKS]


def _curve_frequencies(curve: dict, sample: np.ndarray) -> np.ndarray:
    return np.atleast_1d(np.asarray(curve.get("frequency_hz", sample), dtype=float))


def _sensitive(sample: np.ndarray, full: list[dict]) -> set[float]:
    """Each curve's peaks (the primary and the superharmonic ones) and its least y_min."""
    picks = set()
    for curve in full:
        freq = _curve_frequencies(curve, sample)
        app = np.atleast_1d(np.asarray(curve.get("app_m", []), dtype=float))
        if app.size == freq.size:
            picks.update(float(freq[i]) for i in _peaks(app))
        ymin = np.atleast_1d(np.asarray(curve.get("ymin_m", []), dtype=float))
        if ymin.size == freq.size and np.isfinite(ymin).any():
            picks.add(float(freq[np.nanargmin(ymin)]))
    return picks


def _worst(sample: np.ndarray, full: list[dict], chosen: list[dict]) -> set[float]:
    """Where the chosen model differed most from the full one on the sample."""
    picks = set()
    for a, b in zip(full, chosen):
        freq = _curve_frequencies(a, sample)
        for key in ("app_m", "ymin_m"):
            x = np.atleast_1d(np.asarray(a.get(key, []), dtype=float))
            y = np.atleast_1d(np.asarray(b.get(key, []), dtype=float))
            if x.size == y.size == freq.size and x.size:
                gap = np.nan_to_num(np.abs(x - y), nan=np.inf)
                picks.update(float(f) for f in freq[np.argsort(-gap)[:SPOT_PEAKS]])
    return picks
