"""The result of a scene: its study's results, the observables, and what ran."""

from __future__ import annotations

import numpy as np

from perturb.common import Result, from_dict, result

__all__ = ["SceneRun"]


@result
class SceneRun(Result):
    """One scene, run.

    Attributes
    ----------
    title, study : str
        The scene's title and the kind of its study.
    effects : dict
        The effects the model ran with (``perturb.Effects`` fields).
    recorder : str
        What the simulator recorded (only what the observables need).
    route : str
        "full model", "reduced model" (``effects = "auto"`` dropped some effects)
        or "series" (a study of the perturbation series).
    outcomes : list
        The result objects of the study, as the Python API returns them.
    observables : list of dict
        One dict per curve (a sweep run, an attractor, a lane): ``label`` and the
        observables asked for.
    selection : list of dict
        With ``effects = "auto"``: for each effect, how much switching it off
        changed each observable, and whether it was kept (empty otherwise).
    selection_note : str
        The route chosen and why, the spot check, and the times of the sample runs.
    text : str
        What the study printed (the derivation), or "".
    files : list of str
        The files written, relative to the output folder.
    model, settings, elapsed_s
        The model it ran, the scene as checked (defaults filled in), the time.
    """

    title: str
    study: str
    effects: dict
    recorder: str
    route: str
    outcomes: list
    observables: list
    selection: list
    selection_note: str
    text: str
    files: list
    model: dict
    settings: dict
    elapsed_s: float

    @classmethod
    def from_dict(cls, data: dict) -> "SceneRun":
        run = super().from_dict(data)
        run.outcomes = [from_dict(item) for item in run.outcomes]
        run.observables = [{k: _array(v) for k, v in curve.items()} for curve in run.observables]
        return run

    def summary(self) -> str:
        outcome = "; ".join(o.summary() for o in self.outcomes[:3])
        more = f" (+{len(self.outcomes) - 3} more)" if len(self.outcomes) > 3 else ""
        return (f"SceneRun: {self.title!r}, {self.study} study, {self.route}, "
                f"{self.elapsed_s:.3g} s" + (f": {outcome}{more}" if outcome else ""))

    def table(self) -> str:
        lines = [f"  effects: {_describe(self.effects)}", f"  recorder: {self.recorder}"]
        if self.selection:
            lines += ["", selection_table(self.selection), "", f"  {self.selection_note}"]
        for outcome in self.outcomes:
            table = outcome.table()
            if table:
                lines += ["", table]
        if self.files:
            lines += ["", f"  wrote: {', '.join(self.files)}"]
        return "\n".join(lines)


def _describe(effects: dict) -> str:
    from perturb import Effects

    return Effects(**effects).describe()


def selection_table(rows: list[dict]) -> str:
    """The effects table of ``effects = "auto"``: change of each observable from the full
    model when the effect is switched off on top of those dropped above it, and (``own``)
    the largest change from the model of the row above it: what the effect alone adds."""
    observables = sorted({k for row in rows for k in row["change"]})
    width = max(len("effect switched off"), *(len(row["effect"]) for row in rows))
    head = f"  {'effect switched off':<{width}}" + "".join(f"{o:>12}" for o in observables)
    lines = [head + f"{'own':>12}  verdict"]
    for row in rows:
        cells = "".join(f"{_cell(row['change'].get(o)):>12}" for o in observables)
        own = row.get("own_change") or {}
        cells += f"{_cell(max(own.values()) if own else None):>12}"
        lines.append(f"  {row['effect']:<{width}}{cells}  {row['verdict']}")
    return "\n".join(lines)


def _cell(value) -> str:
    if value is None:
        return "-"
    return "inf" if not np.isfinite(value) else f"{value:.2e}"


def _array(value):
    """JSON lists back to arrays (ragged lists of arrays stay lists)."""
    if isinstance(value, list) and value and all(isinstance(v, (int, float)) or v is None
                                                 for v in value):
        return np.array([np.nan if v is None else v for v in value])
    if isinstance(value, list) and value and all(isinstance(v, list) for v in value):
        return [_array(v) for v in value]
    return value
