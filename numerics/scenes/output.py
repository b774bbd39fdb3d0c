"""What a scene writes: its figures, its animation, its printed text and its JSON.

Every file goes into the output folder, under the plain file name the scene gives
(the scene cannot name a path elsewhere). matplotlib is imported here only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from perturb.common import write_atomically

from .observables import HARMONICS_OF_F_E, replay
from .schema import Scene

__all__ = ["write_outputs"]


def write_outputs(scene: Scene, run, out: Path) -> list[str]:
    """Write what ``scene`` asks for into ``out``; the names written, in order."""
    out.mkdir(parents=True, exist_ok=True)
    files = []
    for kind, name in scene.figures.items():
        files += _FIGURES[kind](scene, run, out, name)
    if scene.animation:
        files.append(_animate(scene, run, out))
    if scene.text:
        write_atomically(out / scene.text, run.text)
        files.append(scene.text)
    return files


def _title(scene: Scene) -> str:
    """The scene's title for matplotlib: mathtext where it parses as such ("$f_e$"), and
    otherwise every "$" written as itself ("x $\\frac$ y" would not draw)."""
    from matplotlib.mathtext import MathTextParser

    title = scene.title
    if title.count("$") % 2:  # not mathtext for matplotlib: drawn as it is
        return title
    try:
        MathTextParser("path").parse(title)
    except ValueError:
        return title.replace("$", r"\$")
    return title


def _numbered(out: Path, name: str, count: int) -> list[Path]:
    """``name`` for one figure; name-1, name-2, ... for several."""
    if count == 1:
        return [out / name]
    stem, suffix = Path(name).stem, Path(name).suffix
    return [out / f"{stem}-{i}{suffix}" for i in range(1, count + 1)]


def _each(draw, items, out: Path, name: str) -> list[str]:
    paths = _numbered(out, name, len(items))
    for item, path in zip(items, paths):
        draw(item, path)
    return [p.name for p in paths]


def _app(scene, run, out, name):
    if scene.study == "sweep":
        from ..plots import plot_app

        return _each(plot_app, run.outcomes, out, name)
    from ..plots.curves import plot_curves

    plot_curves(run.observables, out / name, title=_title(scene))
    return [name]


def _extrema(scene, run, out, name):
    from ..plots import plot_extrema

    return _each(plot_extrema, run.outcomes, out, name)


def _spectrum(scene, run, out, name):
    from ..plots import plot_spectrum

    if scene.study == "sweep":  # harmonics of f_e against f_e, at the period-1 points
        # The curve of the largest response: there the harmonics are strongest.
        k = int(np.argmax([np.nanmax(r.app_m, initial=0.0) for r in run.outcomes[0].runs]))
        curve, periods = run.observables[k], run.outcomes[0].runs[k].period
        width = HARMONICS_OF_F_E + 1
        rows = np.array([np.asarray(s) if p == 1 and np.size(s) == width
                         else np.full(width, np.nan)
                         for s, p in zip(curve["spectrum_m"], periods)])
        plot_spectrum(rows, out / name, frequency_hz=np.asarray(curve["frequency_hz"]),
                      title=f"harmonics of y at P_a = {curve['label']} (period-1 points)")
        return [name]
    curve = run.observables[0]
    spectra = curve["spectrum_m"]
    # An attractor's spectrum spans its period p, a time history's its recorded periods.
    periods = int(curve.get("period", scene.options.get("record_periods", 1)))
    plot_spectrum(np.asarray(spectra), out / name, title=f"harmonics of y: {curve['label']}",
                  periods=periods)
    return [name]


def _contact_fraction(scene, run, out, name):
    from ..plots import plot_contact_fraction

    curves = run.observables
    grid = np.sort(np.asarray(curves[0]["frequency_hz"]))
    # Each curve in the order of the grid (a down sweep runs it backwards).
    fractions = [np.asarray(c["contact_fraction"])[np.argsort(c["frequency_hz"])]
                 for c in curves]
    plot_contact_fraction(grid, np.array(fractions), out / name,
                          labels=[c["label"] for c in curves], title=_title(scene))
    return [name]


def _phase_portrait(scene, run, out, name):
    from ..plots import plot_phase_portrait

    curves = [c for c in run.observables if "y_m" in c]
    plot_phase_portrait([c["y_m"] for c in curves], [c["v_m_s"] for c in curves], out / name,
                        y0_m=run.model.get("y0_m"),
                        title=_title(scene))
    return [name]


def _time_history(scene, run, out, name):
    from ..plots import plot_time_history

    curve = run.observables[0]
    plot_time_history(curve["time_s"], curve["y_m"], out / name, title=curve["label"])
    return [name]


def _census(scene, run, out, name):
    from ..plots import plot_census

    return _each(plot_census, run.outcomes, out, name)


def _hysteresis(scene, run, out, name):
    from ..plots import plot_hysteresis

    return _each(plot_hysteresis, run.outcomes, out, name)


def _backbone(scene, run, out, name):
    from ..plots import plot_backbone, plot_backbone_truncations

    if len(run.outcomes) == 3:  # the consistent series and Eq. 2.6's beside the exact one
        return _each(plot_backbone_truncations, [[tuple(run.outcomes)]], out, name)
    return _each(plot_backbone, run.outcomes[:1], out, name)


def _natural_frequency(scene, run, out, name):
    from ..plots import plot_natural_frequency

    return _each(plot_natural_frequency, run.outcomes, out, name)


def _comparison(scene, run, out, name):
    from ..plots import plot_comparison

    return _each(plot_comparison, run.outcomes, out, name)


def _continuation(scene, run, out, name):
    from ..plots import plot_continuation

    return _each(plot_continuation, run.outcomes, out, name)


def _folds(scene, run, out, name):
    from ..plots import plot_folds

    return _each(plot_folds, run.outcomes, out, name)


def _atlas(scene, run, out, name):
    from ..plots import plot_atlas

    found, *folds = run.outcomes  # the fold curves follow with ``overlay_folds``
    plot_atlas(found, out / name, folds=folds[0] if folds else None)
    return [name]


_FIGURES = {
    "app": _app,
    "extrema": _extrema,
    "spectrum": _spectrum,
    "contact_fraction": _contact_fraction,
    "phase_portrait": _phase_portrait,
    "time_history": _time_history,
    "census": _census,
    "hysteresis": _hysteresis,
    "backbone": _backbone,
    "natural_frequency": _natural_frequency,
    "comparison": _comparison,
    "continuation": _continuation,
    "folds": _folds,
    "atlas": _atlas,
}


def _animate(scene: Scene, run, out: Path) -> str:
    from ..plots import animate_slider, animate_sweep

    animation = scene.animation
    name = f"{Path(scene.source).stem}-{animation['kind']}.gif"
    runs = run.outcomes[0].runs
    if animation["kind"] == "sweep":
        # Points that did not settle have no App to draw: the curve passes over them.
        kept = [np.isfinite(r.app_m) & r.settled for r in runs]
        frequency = [r.frequency_hz[k] for r, k in zip(runs, kept)]
        frames = min(animation["frames"], sum(f.size for f in frequency))
        animate_sweep(out / name, frequency_hz=frequency,
                      app_m=[r.app_m[k] for r, k in zip(runs, kept)],
                      labels=[f"{r.pa_frac:g} Q {r.direction}" for r in runs],
                      frames=frames, fps=animation["fps"], title=_title(scene))
        return name
    first = runs[0]
    i = _animated_point(first, animation.get("frequency_hz"))
    history = _orbit_history(scene, run, first, i)
    animate_slider(out / name, time_s=history["time_s"], y_m=history["y_m"],
                   y0_m=history["y0_m"], curve_hz=first.frequency_hz, curve_app_m=first.app_m,
                   point_hz=float(first.frequency_hz[i]), point_app_m=float(first.app_m[i]),
                   frames=animation["frames"], fps=animation["fps"], title=_title(scene))
    return name


def _animated_point(sweep_run, frequency_hz) -> int:
    """The point at ``frequency_hz``, or where contact is nearest to lost (least y_min)."""
    if frequency_hz is not None:
        return int(np.argmin(np.abs(sweep_run.frequency_hz - frequency_hz)))
    ymin = np.where(sweep_run.settled, sweep_run.ymin_m, np.inf)
    return int(np.argmin(ymin))


#: Periods of the orbit the slider animation shows.
_ANIMATED_PERIODS = 3


def _orbit_history(scene, run, sweep_run, i: int) -> dict:
    """y after every step of a few periods of the orbit at point ``i``, simulated again."""
    from perturb import Effects

    from .studies import model_of

    periods = _ANIMATED_PERIODS * int(max(sweep_run.period[i], 1))
    orbit = replay(model_of(scene, Effects(**run.effects)), sweep_run, i, periods)
    # After every step, as the simulator records it (the start state left out).
    return {"time_s": orbit["time_s"][1:], "y_m": orbit["y_m"][1:], "y0_m": run.model["y0_m"]}
