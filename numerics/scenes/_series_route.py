"""The perturbation series in the table of ``effects = "auto"``: would it have done?

For a sweep scene asking for App and extrema, the series of Eq. 2.6 (Eq. 2.7, 2.8)
is compared with the scene's own run at every point, after the run: it is a
candidate where every point has exactly one response of the series, valid at half
the tolerance (its own error estimate, and contact kept); several responses at a
point (a bent peak) make the answer depend on the sweep's path, which the series
does not follow. The series is not taken as the route: it gives no orbit from
which the full model could be checked at every point, and one valid response of
the series does not exclude orbits it cannot describe (a period-2 orbit of the
full model near 2 f_n0, where the series sees a quiet period-1 response).
"""

from __future__ import annotations

import time

import numpy as np

from perturb import eq26_numbers, frequency_response

from ._schema import Scene

__all__ = ["series_row", "SERIES_ORDER", "SERIES_OBSERVABLES"]

#: Order of the series compared (the response's default).
SERIES_ORDER = 6
#: What the series gives of a sweep: App and the extrema of u(t) (Eq. 2.1: y = y0 + u).
SERIES_OBSERVABLES = frozenset({"app", "extrema"})
LABEL = f"the perturbation series of Eq. 2.6, order {SERIES_ORDER}, against the scene's run"


def series_row(scene: Scene, curves: list[dict], margin: float) -> dict:
    """The table's row of the series: its change from the scene's ``curves`` at every
    point, and whether it reproduces them within the tolerance."""
    from ._auto import observable_change

    start = time.perf_counter()
    series, why_not = _series_curves(scene, margin * scene.tolerance)
    seconds = time.perf_counter() - start
    if series is None:
        return {"effect": LABEL, "change": {}, "seconds": None,
                "verdict": f"not a candidate ({why_not})"}
    change = observable_change(scene.observables, curves, series)
    within = max(change.values(), default=0.0) <= scene.tolerance
    return {"effect": LABEL, "change": change, "seconds": seconds,
            "verdict": "reproduces the run" if within else "does not reproduce the run"}


def _series_curves(scene: Scene, tolerance: float) -> tuple[list[dict] | None, str]:
    """The series' curves, one per sweep run in the order ``observe`` gives them, or
    (None, why) where it is no candidate."""
    if scene.study != "sweep" or not SERIES_OBSERVABLES.issuperset(scene.observables):
        return None, f"the series gives {', '.join(sorted(SERIES_OBSERVABLES))} of a sweep"
    grid = scene.frequency_hz
    responses = [frequency_response(grid, frac, SERIES_ORDER, parameters=scene.parameters,
                                    tolerance=tolerance) for frac in scene.pa_frac]
    for frac, response in zip(scene.pa_frac, responses):
        several = int(np.sum(response.roots_per_frequency() != 1))
        if several:
            return None, (f"at {frac:g} Q, {several} of {grid.size} frequencies have no "
                          f"response or several (a bent peak)")
        invalid = int(np.sum(~response.branches[0].valid))
        if invalid:
            return None, (f"at {frac:g} Q, {invalid} of {grid.size} responses are not valid "
                          f"at {tolerance:.2g}")
    return _curves(scene, responses), ""


def _curves(scene: Scene, responses) -> list[dict]:
    y0 = eq26_numbers(scene.parameters).y0_m
    direction = scene.options["direction"]
    directions = ("up", "down") if direction == "both" else (direction,)
    curves = []
    for response in responses:
        branch = response.branches[0]
        for d in directions:
            order = slice(None) if d == "up" else slice(None, None, -1)
            curve = {"frequency_hz": branch.frequency_hz[order], "app_m": branch.app_m[order]}
            curve.update(ymin_m=y0 + branch.u_min_m[order], ymax_m=y0 + branch.u_max_m[order])
            curves.append(curve)
    return curves
