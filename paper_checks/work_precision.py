"""What accuracy costs: RK4 steps, series order and DOP853 tolerance against error and time.

Every point is measured in one run of the command (under ``make paper``, each method in
a worker process of its own). Errors are the largest relative App error
over a few (P_a, f_e) points:

- RK4 (full model, steady states by shooting from the reference orbit) against
  the same orbit at 3,200 steps per period and tol 1e-9;
- the perturbation series of order N (Eq. 2.6) against RK4 of the Eq. 2.6 model at
  1,600 steps per period, on the numpy route (``engine="numpy"``): every order the
  same route whatever the cache holds (the compiled route, where an order's kernels
  are built, is 10-20 times faster: ``make bench``);
- scipy's DOP853 (full model lambdified from perturb, restarted at every crossing
  of y = 0; 30 periods from the reference orbit, App of the last period from its
  dense output) against the same reference as RK4, down to rtol 1e-9: below it the
  error is the reference's own (at rtol 1e-11 it measured 4.4e-9 against 5.1e-9 at
  1e-9, 2026-11-23, measured once by hand), and that point alone took 0.42 s of the
  study's 3.7 s in that run.

Each order of the series is derived and compiled (``compile_series``) before any is
timed, in increasing order, each order's time measured alone: the numpy route of
order N also evaluates orders N+1 and N+2 (its error estimate), so the first timed
call of one order would otherwise build the next two inside its timing. An order
whose formulas an earlier run left on disk is imported from there, not derived:
``derive_cached`` says which, beside ``derive_seconds``.

The methods are measured one after the other, or any of them alone
(``work_precision(methods=...)``, the study's option ``method``): ``make paper`` measures
each in a job of its own and merges them (``WorkPrecision.merged``), so that its
workers share the study's work (about 1.1 s).

It is also a kind of scene study, ``work_precision`` (``scenes/work-precision.toml``),
registered here on import. Its ``SceneRun.outcomes`` is empty and its ``text`` is the
measurement as strict JSON (``WorkPrecision.from_text`` reads it back): the points
are no result of the toolkit (no model of their own: each method runs its own), so
they are not dressed up as one.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from numerics import steady_states
from numerics.scenes import Option, Study, StudyRun, register_study
from perturb import EQ_2_6, FULL, PAPER, ContactModel, compile_series, frequency_response
from perturb.common import jsonable
from perturb.series.compiled import formulas_cached, lambdified_series
from perturb.series.truncation import TRUNCATIONS, truncation_for

__all__ = ["WorkPrecision", "work_precision", "scene_methods", "RK4_POINTS", "SERIES_POINTS"]

#: (P_a / Q, f_e [Hz]): the primary peak, the 1/2 superharmonic, a bouncing state.
RK4_POINTS = ((0.05, 1420.0), (0.15, 740.0), (0.5, 1200.0))
#: Where the series is valid (no loss of contact): off-peak, near the peak, 1/2 peak.
SERIES_POINTS = ((0.05, 740.0), (0.05, 1000.0), (0.05, 1300.0))
RK4_STEPS = (25, 50, 100, 200, 400, 800, 1600)
SERIES_ORDERS = tuple(range(9))
#: The orders above N that the numpy route of order N evaluates for its error estimate
#: (``perturb.frequency_response``: orders N+1 and N+2).
ERROR_ORDERS = 2
DOP853_RTOL = (1e-3, 1e-5, 1e-7, 1e-9)
DOP853_PERIODS = 30
#: The methods measured, in the order of the report (``Method.name``).
METHODS = ("RK4", "series", "DOP853")


@dataclass
class Method:
    """One method's work-precision points."""

    name: str
    setting: str
    settings: list = field(default_factory=list)
    errors: list = field(default_factory=list)
    seconds: list = field(default_factory=list)
    extra: dict = field(default_factory=dict)


@dataclass
class WorkPrecision:
    methods: list[Method]
    elapsed_s: float

    def as_dict(self) -> dict:
        return {m.name: {"setting": m.setting, "settings": m.settings, "errors": m.errors,
                         "seconds": m.seconds, **m.extra} for m in self.methods}

    def to_text(self) -> str:
        """Every field, as strict JSON (NaN as null)."""
        return json.dumps(jsonable(asdict(self)), allow_nan=False, indent=1)

    @classmethod
    def from_text(cls, text: str) -> "WorkPrecision":
        data = json.loads(text)

        def numbers(values):
            return [math.nan if v is None else v for v in values]

        methods = [Method(**{**m, "errors": numbers(m["errors"]),
                             "seconds": numbers(m["seconds"])}) for m in data["methods"]]
        return cls(methods, data["elapsed_s"])

    @classmethod
    def merged(cls, parts: list["WorkPrecision"]) -> "WorkPrecision":
        """One measurement from ``parts`` measured apart: their methods in the order of
        ``METHODS``, and the sum of their times."""
        methods = [m for part in parts for m in part.methods]
        names = [m.name for m in methods]
        if len(set(names)) != len(names) or not set(names) <= set(METHODS):
            raise ValueError(f"parts must measure distinct methods of {METHODS}, got {names}")
        return cls(sorted(methods, key=lambda m: METHODS.index(m.name)),
                   sum(part.elapsed_s for part in parts))


def _best_of(function, repeats: int = 3) -> tuple[object, float]:
    best, result = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return result, best


def _rk4_points() -> tuple[np.ndarray, np.ndarray]:
    """The frequencies [Hz] and force amplitudes [N] of ``RK4_POINTS``."""
    return (np.array([p[1] for p in RK4_POINTS]),
            np.array([p[0] for p in RK4_POINTS]) * PAPER.Q_n)


def _reference():
    """The reference orbits of RK4 and DOP853: RK4 at 3,200 steps per period, tol 1e-9."""
    return steady_states(*_rk4_points(), steps_per_period=3200, tol=1e-9)


def _rk4(quick: bool, ref) -> Method:
    f, p_a = _rk4_points()
    method = Method("RK4", "steps per period")
    for n in RK4_STEPS[:-2] if quick else RK4_STEPS:
        # The scheme at exactly n steps: no refinement, no step-error estimate.
        found, seconds = _best_of(lambda n=n: steady_states(
            f, p_a, y_init_m=ref.y_start_m, v_init_m_s=ref.v_start_m_s, app_guess_m=ref.app_m,
            period_guess=ref.period, steps_per_period=n, refinements=0, app_rtol=None))
        method.settings.append(n)
        method.errors.append(float(np.max(np.abs(found.app_m / ref.app_m - 1))))
        method.seconds.append(seconds)
    return method


def _series(quick: bool, truncation: str = "paper") -> Method:
    """The series by its order against RK4 of its own model: Eq. 2.6's series (the numpy
    route) against Eq. 2.6, or the consistent series (the scheme's kernel) against the
    full model."""
    f = np.array([p[1] for p in SERIES_POINTS])
    frac = SERIES_POINTS[0][0]
    paper = truncation == "paper"
    ref = steady_states(f, frac * PAPER.Q_n, model=ContactModel(effects=EQ_2_6 if paper
                                                                else FULL),
                        steps_per_period=1600, tol=1e-9)
    orders = SERIES_ORDERS[:5] if quick else SERIES_ORDERS
    derive_seconds, cached = _compile_orders(orders[-1] + ERROR_ORDERS, truncation)
    setting = "order N (numpy route)" if paper else "order N, consistent (the scheme's kernel)"
    method = Method("series", setting,
                    extra={"derive_seconds": derive_seconds[:len(orders)],
                           "derive_cached": cached[:len(orders)]})
    engine = "numpy" if paper else "compiled"
    for order in orders:
        response, seconds = _best_of(lambda o=order: frequency_response(f, frac, o,
                                                                        engine=engine,
                                                                        truncation=truncation))
        method.settings.append(order)
        method.errors.append(_series_error(response, ref.app_m))
        method.seconds.append(seconds)
    return method


def _compile_orders(highest: int, truncation: str = "paper"
                    ) -> tuple[list[float], list[bool]]:
    """Derive and compile orders 0..``highest`` in turn, or import them from the disk:
    the seconds of each, and whether it was on the disk (the consistent series derives
    nothing: its kernel is compiled once, in numba's cache). The process's own cache of
    ``compile_series`` is emptied first (another scene may have filled it in this
    worker), so that each is a first call."""
    compile_series.cache_clear()
    lambdified_series.cache_clear()  # where compile_series keeps Eq. 2.6's formulas
    seconds, cached = [], []
    for order in range(highest + 1):
        cached.append(formulas_cached(order) if truncation == "paper" else True)
        start = time.perf_counter()
        compile_series(order, truncation)
        seconds.append(time.perf_counter() - start)
    return seconds, cached


def _series_error(response, reference: np.ndarray) -> float:
    """Largest relative App error; at each frequency the root nearest the RK4 orbit."""
    worst = 0.0
    for i, f in enumerate(response.frequency_hz):
        apps = [b.app_m[list(b.frequency_hz).index(f)] for b in response.branches
                if f in b.frequency_hz]
        nearest = min(apps, key=lambda a: abs(a / reference[i] - 1))
        worst = max(worst, abs(nearest / reference[i] - 1))
    return float(worst)


def _dop853(ref, quick: bool, rtols: tuple[float, ...]) -> Method:
    # Imported here: scipy.integrate is for this study alone, whose worker process
    # imports it, not `make paper`'s main process before it starts the workers.
    from numerics.simulation import reference_last_period

    method = Method("DOP853", f"rtol ({DOP853_PERIODS} periods from the orbit)")
    for rtol in rtols[:3] if quick else rtols:
        start = time.perf_counter()
        apps = [np.ptp(reference_last_period(ContactModel(), f, frac * PAPER.Q_n, y, v,
                                             DOP853_PERIODS, rtol=rtol)[1])
                for (frac, f), y, v in zip(RK4_POINTS, ref.y_start_m, ref.v_start_m_s)]
        method.settings.append(rtol)
        method.seconds.append(time.perf_counter() - start)
        method.errors.append(float(np.max(np.abs(np.array(apps) / ref.app_m - 1))))
    return method


def work_precision(quick: bool = False, methods=METHODS,
                   truncation: str = "consistent",
                   dop853_rtols: tuple[float, ...] = DOP853_RTOL) -> WorkPrecision:
    """Measure the error and time of each of ``methods`` (names of ``METHODS``, by
    default all), in this run and in the order of ``METHODS``; the series of
    ``truncation`` ("consistent": against RK4 of the full model; "paper": Eq. 2.6's
    series against RK4 of Eq. 2.6); DOP853 at each of ``dop853_rtols`` (the first
    three when ``quick``)."""
    unknown = set(methods) - set(METHODS)
    if unknown or not methods:
        raise ValueError(f"`methods` must name some of {METHODS}, got {methods!r}.")
    truncation = truncation_for(truncation).name  # a bad name: a ValueError
    start = time.perf_counter()
    ref = _reference() if {"RK4", "DOP853"} & set(methods) else None
    measure = {"RK4": lambda: _rk4(quick, ref),
               "series": lambda: _series(quick, truncation),
               "DOP853": lambda: _dop853(ref, quick, dop853_rtols)}
    measured = [measure[name]() for name in METHODS if name in methods]
    return WorkPrecision(measured, time.perf_counter() - start)


def scene_methods(scene) -> tuple[str, ...]:
    """The methods a ``work_precision`` scene measures (its option ``method``: "all", or
    one of ``METHODS``)."""
    method = scene.options["method"]
    return METHODS if method == "all" else (method,)


def _run_scene_study(scene, model, frequency_hz, quiet) -> StudyRun:
    """The ``work_precision`` scene study (each method runs its own model and points)."""
    work = work_precision(quick=scene.options["quick"], methods=scene_methods(scene),
                          truncation=scene.options["truncation"])
    return StudyRun([], "RK4 steady states by steps per period, the series by order, DOP853 "
                        "by rtol; the measurement is the text, as JSON", text=work.to_text())


register_study(
    "work_precision",
    Study({"quick": Option("bool", False),
           "method": Option("choice", "all", choices=("all", *METHODS)),
           "truncation": Option("choice", "consistent", choices=TRUNCATIONS)},
          observables=(), default_observables=(),
          figures=("work_precision",)),
    _run_scene_study,
)
