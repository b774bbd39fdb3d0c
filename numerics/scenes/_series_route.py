"""The perturbation series as a route of ``effects = "auto"`` for a sweep scene.

Where every point of the scene has exactly one response of the series (Eq. 2.7, 2.8),
valid at the scene's tolerance (the series' own error estimate, with the margin of
the reduced models, and contact kept), the series gives the sweep's App and extrema
without simulating: the up and the down sweep are the same curve there, since one
response leaves no branch to choose. Several responses at a point (a bent peak) make
the answer depend on the sweep's path, which the series does not follow: there it
is no candidate.
"""

from __future__ import annotations

import numpy as np

from common import Status
from perturb import eq26_numbers, frequency_response

from ._schema import Scene

__all__ = ["series_curves", "SERIES_ORDER", "SERIES_OBSERVABLES"]

#: Order of the series the route uses (the response's default).
SERIES_ORDER = 6
#: What the series gives of a sweep: App and the extrema of u(t) (Eq. 2.1: y = y0 + u).
SERIES_OBSERVABLES = frozenset({"app", "extrema"})


def series_curves(scene: Scene, tolerance: float) -> tuple[list[dict] | None, list, str]:
    """The series' curves of a sweep scene, one per run as ``observe`` gives them, its
    responses (one per amplitude), and why not (``None``, [], reason) where it is no
    candidate: observables it does not give, or a point without exactly one response
    valid at ``tolerance``."""
    if scene.study != "sweep" or not SERIES_OBSERVABLES.issuperset(scene.observables):
        return None, [], f"the series gives {', '.join(sorted(SERIES_OBSERVABLES))} of a sweep"
    if scene.animation or set(scene.figures) - {"app"}:
        return None, [], "the scene's figures or animation are drawn from the sweep's orbits"
    grid = scene.frequency_hz
    responses = [frequency_response(grid, frac, SERIES_ORDER, parameters=scene.parameters,
                                    tolerance=tolerance) for frac in scene.pa_frac]
    for frac, response in zip(scene.pa_frac, responses):
        several = int(np.sum(response.roots_per_frequency() != 1))
        if several:
            return None, responses, (f"at {frac:g} Q, {several} of {grid.size} frequencies have "
                                     f"no response or several (a bent peak)")
        invalid = int(np.sum(~response.branches[0].valid))
        if invalid:
            return None, responses, (f"at {frac:g} Q, {invalid} of {grid.size} responses are "
                                     f"not valid at {tolerance:.2g}")
    return _curves(scene, responses), responses, ""


def _curves(scene: Scene, responses) -> list[dict]:
    y0 = eq26_numbers(scene.parameters).y0_m
    direction = scene.options["direction"]
    directions = ("up", "down") if direction == "both" else (direction,)
    curves = []
    for frac, response in zip(scene.pa_frac, responses):
        branch = response.branches[0]
        for d in directions:
            order = slice(None) if d == "up" else slice(None, None, -1)
            curve = {"label": f"{frac:g} Q {d}", "pa_frac": frac, "direction": d,
                     "frequency_hz": branch.frequency_hz[order],
                     "status": np.full(branch.frequency_hz.size, int(Status.SUCCESS))}
            if "app" in scene.observables:
                curve["app_m"] = branch.app_m[order]
            if "extrema" in scene.observables:
                curve.update(ymin_m=y0 + branch.u_min_m[order], ymax_m=y0 + branch.u_max_m[order])
            curves.append(curve)
    return curves
