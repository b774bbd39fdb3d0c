"""Periodic orbits continued in the force amplitude P_a at one f_e.

A sweep of f_e at fixed P_a shows where a peak bends (Fig. 2); at a fixed f_e near
a bent peak the response to a growing force folds too: App jumps up as P_a rises
past one fold and down as it falls past the other. The same pseudo-arclength walk
as ``continue_orbits`` (``walk``) follows the orbit, stable or not, with
P_a in the place of f_e: the unknowns are z = (y / y0, v / (omega0 y0), P_a / Q)
(``period_map.ForceMap``), dR/dP_a the map's exact derivative, and folds and
period doublings are located the same way, in P_a.
"""

from __future__ import annotations

import time

from perturb import ContactModel, eq26_numbers
from perturb.common import Result, check_choice, check_positive, result

from ..simulation.rk4 import check_model
from ..steady.sweeps import ENGINES
from .options import WalkOptions
from .period_map import ForceMap
from .walk import (
    DEFAULTS,
    Bifurcation,
    ContinuedBranch,
    branch_steps,
    check_band,
    check_options,
    check_walk,
    count_kinds,
    walk_finest,
    walk_settings,
)

__all__ = ["ForceContinuation", "continue_in_force"]


@result
class ForceContinuation(Result):
    """Branches of periodic orbits continued in P_a at one f_e, and their bifurcations.

    Attributes
    ----------
    frequency_hz : float
        f_e [Hz].
    branches : list of ContinuedBranch
        Each point's P_a / Q in ``pa_frac`` (``frequency_hz`` is constant).
    bifurcations : list of Bifurcation
        Folds and period doublings, located in P_a (``pa_frac``).
    model, settings : dict
        The model; pa_min, pa_max, steps_per_period (the N used), ds_max, max_angle, engine,
        max_points.
    elapsed_s : float
    """

    frequency_hz: float
    branches: list[ContinuedBranch]
    bifurcations: list[Bifurcation]
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return (f"ForceContinuation: f_e = {self.frequency_hz:g} Hz, {len(self.branches)} "
                f"branch(es), {sum(b.frequency_hz.size for b in self.branches)} points, "
                f"{count_kinds(self.bifurcations)}, {self.elapsed_s:.3g} s")

    def table(self) -> str:
        lines = [f"  {b.summary()}" for b in self.branches]
        lines += [f"  {b.kind:<16} P_a = {b.pa_frac:.6f} Q, {b.precision()}  App "
                  f"{b.app_m * 1e9:>9.4f} nm" for b in self.bifurcations]
        return "\n".join(lines)


def continue_in_force(
    frequency_hz: float,
    pa_min: float,
    pa_max: float,
    *,
    model: ContactModel | None = None,
    period: int = 1,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    ds_max: float = DEFAULTS["ds_max"],
    max_angle: float = DEFAULTS["max_angle"],
    max_points: int = DEFAULTS["max_points"],
    quiet: bool = True,
    engine: str = "auto",
    options: WalkOptions | None = None,
) -> ForceContinuation:
    """Continue the p-periodic orbit reached at ``pa_min`` from rest up to ``pa_max``, at
    one f_e: the force-response curve, through its folds.

    Parameters
    ----------
    frequency_hz : float
        f_e [Hz], within 1e-4 to 100 f_n0 (as ``continue_orbits``' band).
    pa_min, pa_max : float
        The range of P_a / Q (pa_min >= 0). The branch starts at the stable orbit that
        time marching from rest reaches at ``pa_min`` and, if it ends inside the range,
        a second walk starts from the one reached at ``pa_max``, down in P_a.
    model, period, steps_per_period, ds_max, max_angle, max_points, quiet, engine, options
        As in ``continue_orbits`` ("auto" steps: ``steady_states``' choice at f_e, but at
        least 512, walked again at twice N while a walk stops at a corner).

    Returns
    -------
    ForceContinuation

    Examples
    --------
    At 1400 Hz, inside the bistable band of the primary peak at 0.05 Q, App jumps up
    and down with the force, between two folds:

    >>> run = continue_in_force(1400.0, 0.02, 0.08)
    >>> [(b.kind, round(b.pa_frac, 4)) for b in run.bifurcations]
    [('fold', 0.0695), ('fold', 0.0456)]
    """
    model = check_model(model)
    f_e = check_positive("frequency_hz", frequency_hz)
    pa_min = check_positive("pa_min", pa_min, allow_zero=True)
    pa_max = check_positive("pa_max", pa_max)
    if not pa_min < pa_max:
        raise ValueError(f"`pa_max` must be above `pa_min`, got {pa_min!r} and {pa_max!r}.")
    ds_max, max_angle, max_points = check_walk(period, ds_max, max_angle, max_points)
    check_choice("engine", engine, ENGINES)
    options = check_options(options)
    check_band("frequency_hz", f_e, model.parameters)
    steps = branch_steps(steps_per_period, f_e, eq26_numbers(model.parameters))
    start = time.perf_counter()
    q = model.parameters.Q_n
    shoot, branches, bifurcations = walk_finest(
        lambda n: ForceMap(model, f_e, n, period, engine, options), steps,
        steps_per_period == "auto", model,
        pa_min * q, pa_max * q, ds_max, max_angle, max_points, quiet)
    settings = {"pa_min": pa_min, "pa_max": pa_max,
                **walk_settings(shoot, ds_max, max_angle, max_points)}
    return ForceContinuation(frequency_hz=f_e, branches=branches, bifurcations=bifurcations,
                             model=model.as_dict(), settings=settings,
                             elapsed_s=time.perf_counter() - start)
