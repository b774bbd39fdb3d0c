"""Running a scene: its model with the effects it names (or chooses), its study, its outputs."""

from __future__ import annotations

import time
from pathlib import Path

from perturb import FULL
from perturb.common import note

from .auto import select_effects
from .observables import observe
from .result import SceneRun
from .schema import Scene, read_scene
from .studies import SERIES_STUDIES, model_of, run_study

__all__ = ["run_scene"]


def run_scene(scene: Scene | str | Path, *, out: str | Path | None = None, json: str | Path |
              None = None, quiet: bool = True) -> SceneRun:
    """Run a scene (a ``Scene`` or the path of its TOML file) and write what it asks for.

    Parameters
    ----------
    scene : Scene or path
    out : path, optional
        Folder for the scene's figures, animation, text and JSON (none written without it).
    json : path, optional
        Also write the result there (as ``--json`` does).
    quiet : bool
        No progress on stderr.

    Returns
    -------
    SceneRun
        The study's results, as the Python API gives them, with the observables, the
        effects and recorder it ran and, with ``effects = "auto"``, the table of effects.

    Examples
    --------
    >>> from numerics.scenes import parse_scene
    >>> scene = parse_scene('''
    ... observables = ["app", "contact_fraction"]
    ... [excitation]
    ... pa_frac = 0.05
    ... frequency_hz = [1300.0, 1400.0]
    ... [study]
    ... kind = "sweep"
    ... direction = "up"
    ... ''')
    >>> run = run_scene(scene)
    >>> curve = run.observables[0]
    >>> [round(float(a) * 1e9, 1) for a in curve["app_m"]], curve["contact_fraction"].tolist()
    ([48.1, 106.1], [0.0, 0.0])
    >>> run.route, run.recorder
    ('full model', 'steady states: extrema of one response period, and y after every step of it')
    """
    scene = scene if isinstance(scene, Scene) else read_scene(scene)
    start = time.perf_counter()
    rows, selection_note, study = [], "", None
    if scene.auto:
        note(f"{scene.title}: measuring what each effect contributes ...", quiet=quiet)
        selection = select_effects(scene, quiet=quiet)
        effects, route, study = selection.effects, selection.route, selection.study
        rows, selection_note = selection.rows, selection.note
    else:
        effects = scene.effects
        route = "full model" if effects == FULL else "reduced model"
    model = model_of(scene, effects)
    if scene.study in SERIES_STUDIES:
        route = "series"
    elif scene.study == "natural_frequency":
        route = "closed form"
    if study is None:  # not run yet (auto has run a sweep's chosen model to check it)
        note(f"{scene.title}: {scene.study} study, {model.effects.describe()} ...", quiet=quiet)
        study = run_study(scene, model, quiet=quiet)
    curves = observe(scene, study.outcomes, model)
    run = SceneRun(title=scene.title, study=scene.study,
                   effects=model.effects.__dict__.copy(), recorder=study.recorder, route=route,
                   outcomes=study.outcomes, observables=curves,
                   selection=rows, selection_note=selection_note, text=study.text, files=[],
                   model=model.as_dict(), settings=scene.as_dict(),
                   elapsed_s=time.perf_counter() - start)
    if out is not None:
        from .output import write_outputs

        out = Path(out)
        run.files = write_outputs(scene, run, out)
        if scene.json:
            run.to_json(out / scene.json)
            run.files.append(scene.json)
    if json is not None:
        run.to_json(json)
    return run
