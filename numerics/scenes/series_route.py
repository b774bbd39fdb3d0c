"""The perturbation series as a route of ``effects = "auto"``: a sweep without simulation.

For a sweep scene asking for App and extrema, the consistent series of the
contact's own equation in contact (Eq. 2.5 carried on: every Taylor term of the
spring and the damper up to the order; Eq. 2.7, 2.8's scheme, order
``SERIES_ORDER``; its compiled kernels where built, else the scheme's numba
kernel, as ``engine="auto"`` takes them) is a candidate route where every point
of the scene has exactly one response of the series, valid at the selection's
margin of the tolerance (its error estimate, which includes the terms it leaves
out, and contact kept). It stands for the full model (``SERIES_EFFECTS``): where
it is valid, the slider stays in contact. Several responses at a point (a bent
peak, or a root the series cannot vouch for) make the answer depend on the
sweep's path, which the series does not follow.

A candidate is given as the scene's sweep would give it (``Sweep``, one run per
amplitude and direction), each point with the state at the drive's phase 0 of the
orbit the series describes (``perturb.series_orbits``), so that it is checked
against the full model as a reduced model is: the full model takes every step of
the sweep from that state at the point before. One
valid response of the series does not exclude orbits it cannot describe (a
period-2 orbit of the full model near 2 f_n0, where the series sees a quiet
period-1 response): the check finds them.
"""

from __future__ import annotations

import time

import numpy as np

from perturb import FULL, eq26_numbers, frequency_response
from perturb.common import Status

from ..steady.orbits import Orbits
from ..steady.shooting import DEFAULTS
from ..steady.sweeps import Sweep, SweepRun
from .schema import Scene
from .studies import StudyRun

__all__ = ["series_study", "SERIES_ORDER", "SERIES_OBSERVABLES", "SERIES_LABEL",
           "SERIES_EFFECTS", "SERIES_TRUNCATION"]

#: Order of the series taken as a route (the response's default).
SERIES_ORDER = 6
#: What the series gives of a sweep: App and the extrema of u(t) (Eq. 2.1: y = y0 + u).
SERIES_OBSERVABLES = frozenset({"app", "extrema"})
#: The series taken: every Taylor term of the contact's own laws up to the order.
SERIES_TRUNCATION = "consistent"
#: The model the series stands for: the contact's own laws, which it expands in contact.
SERIES_EFFECTS = FULL
SERIES_LABEL = (f"the perturbation series of the contact's own laws (consistent truncation), "
                f"order {SERIES_ORDER} (no simulation)")
RECORDER = (f"the consistent series of order {SERIES_ORDER}: one response per point, its "
            "extrema and its state at the drive's phase 0")


def series_study(scene: Scene, grid: np.ndarray, tolerance: float
                 ) -> tuple[StudyRun | None, str, float]:
    """The series as the scene's sweep on ``grid`` (a ``StudyRun`` holding one ``Sweep``),
    or None and why it is no candidate; and the seconds it took."""
    if scene.study != "sweep" or not SERIES_OBSERVABLES.issuperset(scene.observables):
        return None, f"the series gives {', '.join(sorted(SERIES_OBSERVABLES))} of a sweep", 0.0
    if scene.animation and scene.animation["kind"] != "sweep":
        return None, "the slider's animation replays a simulated orbit", 0.0
    start = time.perf_counter()
    responses = [frequency_response(grid, frac, SERIES_ORDER, parameters=scene.parameters,
                                    tolerance=tolerance, engine="auto",
                                    truncation=SERIES_TRUNCATION)
                 for frac in scene.pa_frac]
    for frac, response in zip(scene.pa_frac, responses):
        several = int(np.sum(response.roots_per_frequency() != 1))
        if several:
            return None, (f"at {frac:g} Q, {several} of {grid.size} frequencies have no "
                          f"response or several (a bent peak, or a root the series "
                          f"cannot vouch for)"), 0.0
        invalid = int(np.sum(~response.branches[0].valid))
        if invalid:
            return None, (f"at {frac:g} Q, {invalid} of {grid.size} responses are not valid "
                          f"at {tolerance:.2g}"), 0.0
    result = _as_sweep(scene, grid, responses, start)
    return StudyRun([result], RECORDER), "", result.elapsed_s


def _as_sweep(scene: Scene, grid: np.ndarray, responses, start: float) -> Sweep:
    """The responses as ``sweep`` gives its runs: each amplitude in each direction."""
    direction = scene.options["direction"]
    runs = []
    for frac, response in zip(scene.pa_frac, responses):
        points = _points(scene, response.branches[0], frac)
        for d in ("up", "down") if direction == "both" else (direction,):
            order = np.arange(grid.size) if d == "up" else np.arange(grid.size)[::-1]
            runs.append(SweepRun(pa_frac=float(frac), direction=d, **points.take(order).columns()))
    # The accuracy of the scene's sweep: the full model's checks run with it.
    settings = {"frequency_hz": grid.tolist(), "pa_frac": list(scene.pa_frac),
                "direction": direction, **DEFAULTS,
                "steps_per_period": scene.options["steps_per_period"],
                "app_rtol": scene.tolerance, "method": "newton", "keep_orbits": False,
                "order": SERIES_ORDER, "truncation": SERIES_TRUNCATION}
    return Sweep(model=responses[0].model, settings=settings, runs=runs,
                 elapsed_s=time.perf_counter() - start)


def _points(scene: Scene, branch, pa_frac: float) -> Orbits:
    """The branch's points as steady states: period 1, settled, with the series' own
    error estimate, and nothing simulated (no steps, no periods run)."""
    from perturb import series_orbits  # its harmonics are sympy's lambdified formulas

    n = branch.frequency_hz.size
    orbit = series_orbits(branch, SERIES_ORDER, scene.parameters, truncation=SERIES_TRUNCATION)
    y0 = eq26_numbers(scene.parameters).y0_m
    return Orbits(
        frequency_hz=branch.frequency_hz, p_a_n=np.full(n, pa_frac * scene.parameters.Q_n),
        status=np.full(n, Status.SUCCESS, dtype=np.int64), message=[""] * n,
        period=np.ones(n, dtype=np.int64), ymin_m=y0 + branch.u_min_m,
        ymax_m=y0 + branch.u_max_m, maxima_m=orbit.maxima_m, minima_m=orbit.minima_m,
        y_start_m=orbit.y_start_m, v_start_m_s=orbit.v_start_m_s,
        multipliers=np.full((n, 2), np.nan, dtype=complex),
        method=np.full(n, "series", dtype=object), steps_used=np.zeros(n, dtype=np.int64),
        periods_run=np.zeros(n, dtype=np.int64), error_estimate=branch.error_estimate)
