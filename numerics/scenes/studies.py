"""Each kind of study a scene can name, run through the public API with the scene's model.

``run_study`` calls exactly what a user would call in Python (``sweep``,
``attractors``, ``simulate``, ...), with the model's effects and only the
recorders that the scene's observables need; it says which recorder it ran.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perturb import ContactModel

from .schema import Scene

__all__ = ["StudyRun", "run_study", "register_study", "SERIES_STUDIES"]

#: Studies of the perturbation series: they run Eq. 2.6, whatever the scene's effects.
SERIES_STUDIES = ("analytic_response", "derivation")
#: Observables that need the orbit's history (y after every step), not only its extrema.
_NEED_ORBIT = {"spectrum", "contact_fraction", "time_history", "phase_portrait", "hysteresis"}


@dataclass
class StudyRun:
    """What a study gave: its result objects, its printed text and its recorder."""

    outcomes: list
    recorder: str
    text: str = ""


def run_study(scene: Scene, model: ContactModel, frequency_hz=None, quiet: bool = True
              ) -> StudyRun:
    """Run ``scene``'s study with ``model`` (on ``frequency_hz`` instead of its own, if given)."""
    grid = scene.frequency_hz if frequency_hz is None else np.asarray(frequency_hz, float)
    return _RUNNERS[scene.study](scene, model, grid, quiet)


def _pairs(scene: Scene, grid: np.ndarray) -> list[tuple[float, float]]:
    """(f_e, P_a / Q) of every point: each amplitude at each frequency."""
    return [(float(f), float(frac)) for frac in scene.pa_frac for f in grid]


def _sweep(scene, model, grid, quiet) -> StudyRun:
    from ..steady.sweeps import sweep

    keep = bool(_NEED_ORBIT & set(scene.observables))
    result = sweep(grid, scene.pa_frac, direction=scene.options["direction"], model=model,
                   steps_per_period=scene.options["steps_per_period"],
                   app_rtol=scene.tolerance, keep_orbits=keep, quiet=quiet,
                   unchecked=scene.unchecked)
    recorder = "steady states: extrema of one response period"
    return StudyRun([result], recorder + (", and y after every step of it" if keep else ""))


def _attractors(scene, model, grid, quiet) -> StudyRun:
    from ..steady.census import attractor_census

    censuses = [attractor_census(f, frac, model=model,
                                 steps_per_period=scene.options["steps_per_period"],
                                 unchecked=scene.unchecked)
                for f, frac in _pairs(scene, grid)]
    return StudyRun(censuses, "steady states from a grid of initial states: extrema and y after "
                              "every step of each attractor's period")


def time_history_record(observables) -> tuple[str, ...]:
    """The recorders ``simulate`` needs for these observables, and no other."""
    record = ["final"]
    if "app" in observables:
        record.append("minmax")
    if "extrema" in observables:
        record.append("extrema")
    if _NEED_ORBIT & set(observables):
        record.append("history")
    return tuple(record)


def _time_history(scene, model, grid, quiet) -> StudyRun:
    from ..simulation.rk4 import simulate

    pairs = _pairs(scene, grid)
    record = time_history_record(scene.observables)
    opts = scene.options
    recorded = min(opts["record_periods"], opts["periods"])
    run = simulate([f for f, _ in pairs], [frac * model.parameters.Q_n for _, frac in pairs],
                   periods=opts["periods"], steps_per_period=opts["steps_per_period"],
                   model=model, record=record, record_periods=recorded)
    return StudyRun([run], f"simulate, recording {', '.join(record)} over the last "
                           f"{recorded} periods")


def _hysteresis(scene, model, grid, quiet) -> StudyRun:
    from ..contact.hysteresis import hysteresis_loop

    loops = [hysteresis_loop(f, frac, model=model, periods=scene.options["periods"],
                             steps_per_period=scene.options["steps_per_period"])
             for f, frac in _pairs(scene, grid)]
    return StudyRun(loops, "y, v and the contact's reaction after every step of the last period")


def _analytic(scene, model, grid, quiet) -> StudyRun:
    from perturb import frequency_response

    responses = [frequency_response(grid, frac, scene.options["order"],
                                    parameters=model.parameters, tolerance=scene.tolerance,
                                    truncation=scene.options["truncation"])
                 for frac in scene.pa_frac]
    return StudyRun(responses, f"the {scene.options['truncation']} series of order "
                               f"{scene.options['order']} (every root, its extrema and its "
                               "error estimate)")


def _backbone(scene, model, grid, quiet) -> StudyRun:
    from perturb import backbone_series

    from ..backbone.exact import exact_backbone

    exact = exact_backbone(model=model, points=scene.options["points"])
    order, truncation = scene.options["order"], scene.options["truncation"]
    series = [backbone_series(order, truncation, model.parameters)]
    if truncation == "consistent":  # Eq. 2.6's beside it: what the paper's truncation drops
        series.append(backbone_series(order, "paper", model.parameters))
    return StudyRun([exact, *series],
                    "the period quadrature of the free oscillation, and the series")


def _derivation(scene, model, grid, quiet) -> StudyRun:
    from perturb import derivation_text, derive

    series = derive(scene.options["order"], scene.options["truncation"], model.parameters)
    return StudyRun([], "the symbolic derivation (sympy)", text=derivation_text(series))


def _natural_frequency(scene, model, grid, quiet) -> StudyRun:
    from ..contact.natural_frequency import natural_frequency_vs_height

    heights = natural_frequency_vs_height(parameters=model.parameters,
                                          points=scene.options["points"])
    return StudyRun([heights], "f_n0 of Eq. 2.6 for each height (closed form)")


def _comparison(scene, model, grid, quiet) -> StudyRun:
    from ..comparison.study import compare

    result = compare(scene.options["orders"], scene.pa_frac, frequency_hz=grid,
                     steps_per_period=scene.options["steps_per_period"],
                     model=ContactModel(model.parameters), quiet=quiet,
                     truncation=scene.options["truncation"])
    return StudyRun([result], "series, exact backbone, and RK4 steady states of Eq. 2.6 and "
                              "of the full model")


#: What the continuation studies compute, in the words of ``StudyRun.recorder``.
_SHOOTING = ("fixed points of the RK4 period map and their monodromy matrices (the tangent "
             "RK4 beside the state); App from one recorded period of each point")


def _walk(options: dict) -> dict:
    """The step control of a pseudo-arclength walk, as the API names it."""
    return {name: options[name] for name in ("steps_per_period", "ds_max", "max_angle",
                                             "max_points")}


def _continuation(scene, model, grid, quiet) -> StudyRun:
    """One ``Continuation`` per amplitude over the band ``grid`` (its two ends), or one
    ``ForceContinuation`` per frequency over the range of ``pa_frac``."""
    from ..continuation.force import continue_in_force
    from ..continuation.walk import continue_orbits

    opts, walk = scene.options, _walk(scene.options)
    if opts["continued_in"] == "pa_frac":
        low, high = scene.pa_frac
        runs = [continue_in_force(float(f), low, high, model=model, period=opts["period"],
                                  quiet=quiet, **walk) for f in grid]
        return StudyRun(runs, f"continuation in P_a: {_SHOOTING}")
    runs = [continue_orbits(frac, float(grid[0]), float(grid[-1]), model=model,
                            period=opts["period"], quiet=quiet, **walk)
            for frac in scene.pa_frac]
    if opts["switch_branches"]:
        from ..continuation.branch_switch import with_doubled_branches

        runs = [with_doubled_branches(run, quiet=quiet) for run in runs]
    return StudyRun(runs, f"continuation in f_e: {_SHOOTING}")


def _folds(scene, model, grid, quiet) -> StudyRun:
    from ..continuation.folds import fold_curves

    (fmin, fmax), (pa_min, pa_max) = grid, scene.pa_frac
    folds = fold_curves(float(fmin), float(fmax), pa_min, pa_max, model=model,
                        seed_pa_fracs=scene.options["seed_pa_fracs"], quiet=quiet,
                        **_walk(scene.options))
    return StudyRun([folds], "folds of period-1 orbits continued in (f_e, P_a): "
                             "the period map's fixed points where a multiplier is +1")


def _atlas(scene, model, grid, quiet) -> StudyRun:
    """The ``Atlas`` of the grid (``grid`` x ``pa_frac``); with ``overlay_folds``, the
    ``FoldCurves`` of the same box after it."""
    from ..steady.multistability import atlas

    opts = scene.options
    found = atlas(float(grid[0]), float(grid[-1]), scene.pa_frac[0], scene.pa_frac[-1],
                  grid=(grid.size, len(scene.pa_frac)), workers=opts["workers"],
                  initial_states={name: opts[name] for name in ("y_over_y0", "v_over_omega0_y0")},
                  model=model, steps_per_period=opts["steps_per_period"], tol=opts["tol"],
                  quiet=quiet, unchecked=scene.unchecked)
    recorder = ("the attractor census of every cell: steady states from each initial state, "
                "their extrema and y after every step of each attractor's period")
    if not opts["overlay_folds"]:
        return StudyRun([found], recorder)
    from ..continuation.folds import fold_curves

    folds = fold_curves(float(grid[0]), float(grid[-1]), scene.pa_frac[0], scene.pa_frac[-1],
                        model=model, quiet=quiet)
    return StudyRun([found, folds], recorder + "; and the fold curves of the same box")


_RUNNERS = {
    "sweep": _sweep,
    "attractors": _attractors,
    "time_history": _time_history,
    "hysteresis": _hysteresis,
    "analytic_response": _analytic,
    "backbone": _backbone,
    "derivation": _derivation,
    "natural_frequency": _natural_frequency,
    "comparison": _comparison,
    "continuation": _continuation,
    "folds": _folds,
    "atlas": _atlas,
}


def register_study(kind: str, study, runner) -> None:
    """Add a kind of study (a ``Study`` of its options and outputs, and its runner
    ``runner(scene, model, frequency_hz, quiet) -> StudyRun``); a package that owns a
    study, as paper_checks owns the work-precision study, registers it when the module
    that defines it is imported."""
    from .schema import STUDIES

    if kind in STUDIES and _RUNNERS.get(kind) is not runner:
        raise ValueError(f"a study {kind!r} is already registered.")
    STUDIES[kind] = study
    _RUNNERS[kind] = runner


def model_of(scene: Scene, effects=None) -> ContactModel:
    """The scene's model with ``effects`` (its own by default: the schema fixes Eq. 2.6's
    for the series studies)."""
    return ContactModel(scene.parameters, effects or scene.effects)
