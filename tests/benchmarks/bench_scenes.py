"""Scenes: what the scene layer costs, and what `effects = "auto"` gives (issue 11).

Baselines, measured in the same run:
- the paper's Fig. 2 + 3 scene (paper_checks/scenes/fig2-fig3.toml, run without
  figures) against the call it makes, ``sweep(grid, PAPER_PANEL_FRACTIONS)``,
  interleaved; goal: the scene layer adds under 5 %, and the App arrays are
  bit-identical;
- the commands a user runs, each a new process, kernels cached:
  ``python -m numerics scene FILE --quiet`` (a copy of the scene without its
  [output] table, so no figures) against ``python -m numerics sweep --quiet`` on
  the same grid and amplitudes;
- a scene with ``effects = "auto"`` against the same scene with the full model:
  both times (the whole ``run_scene``, the sample runs of the selection included)
  and the largest change of App and of y_min over the curve's largest App (the
  metric of numerics/scenes/auto.py), beside the tolerance; once where contact
  loss can go, once where the slider bounces and it must stay, and once below the
  peaks at 0.02 Q, where the perturbation series is the route.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from numerics import sweep
from numerics.scenes import parse_scene, run_scene
from paper_checks.scene import SCENES, paper_scene
from perturb import FULL, PAPER_PANEL_FRACTIONS, Effects

from ._timing import header, row

GOAL = 1.05  # the scene's time over the direct call's
PAIRS = 11  # interleaved pairs of the scene and the direct call

AUTO = """\
title = "{pa_frac} Q, {start:g}-{stop:g} Hz, auto"
effects = "auto"
observables = ["app", "extrema"]
tolerance = 5e-3
[excitation]
pa_frac = {pa_frac}
frequency_hz = {{start = {start}, stop = {stop}, count = {count}}}
[study]
kind = "sweep"
direction = "up"
"""
#: (P_a / Q, start, stop, count): the paper's contact away from its peak, where contact
#: loss does not matter; and over the bent peak at 0.5 Q, where the slider bounces.
AUTO_SCENES = ((0.05, 300.0, 1000.0, 71), (0.5, 1000.0, 1400.0, 41), (0.02, 200.0, 650.0, 46))


def _ratio_row(name: str, times: tuple[float, float, float]) -> None:
    """A row of ``_pair_ratios``: both medians, and the median ratio to three digits."""
    value, baseline, ratio = times
    print(f"{name:<52} {value:>11.4g} s  {baseline:>11.4g} s  {ratio:>8.3f}x")


def _pair_ratios(first, second, repeats: int) -> tuple[float, float, float]:
    """Medians of two functions run in turn, and the median of first / second pair by
    pair (a burst of load on the shared machine spoils one pair, not the ratio)."""
    times = []
    for _ in range(repeats):
        pair = []
        for function in (first, second):
            start = time.perf_counter()
            function()
            pair.append(time.perf_counter() - start)
        times.append(pair)
    a, b = zip(*times)
    return (statistics.median(a), statistics.median(b),
            statistics.median(x / y for x, y in times))


def scene_layer() -> None:
    scene = paper_scene("fig2-fig3.toml")
    grid = scene.frequency_hz
    in_scene = lambda: run_scene(scene).outcomes[0]  # noqa: E731
    direct = lambda: sweep(grid, PAPER_PANEL_FRACTIONS)  # noqa: E731
    same = all(np.array_equal(a.app_m, b.app_m, equal_nan=True)
               for a, b in zip(in_scene().runs, direct().runs, strict=True))
    layer = _pair_ratios(in_scene, direct, PAIRS)

    text = (SCENES / "fig2-fig3.toml").read_text(encoding="utf-8")
    without_output, found, _ = text.partition("\n[output]")
    assert found, "fig2-fig3.toml has no [output] table at its end"
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fig2-fig3.toml"
        path.write_text(without_output + "\n", encoding="utf-8")
        command = [sys.executable, "-m", "numerics"]
        scene_cmd = command + ["scene", str(path), "--quiet", "--out", tmp]
        band = ["--fmin", repr(float(grid[0])), "--fmax", repr(float(grid[-1])),
                "--points", str(grid.size), "--pa-frac", *map(repr, scene.pa_frac)]
        sweep_cmd = command + ["sweep", "--quiet", *band]
        run = lambda cmd: subprocess.run(cmd, check=True, capture_output=True)  # noqa: E731
        commands = _pair_ratios(lambda: run(scene_cmd), lambda: run(sweep_cmd), 5)

    header(f"Fig. 2 + 3 scene against the direct sweep: {len(scene.pa_frac)} amplitudes x "
           f"up/down x {grid.size} points")
    _ratio_row(f"scene, in process [s] vs sweep() (goal <= {GOAL}x)", layer)
    _ratio_row("`numerics scene` [s] vs `numerics sweep`, new process", commands)
    verdict = "met" if layer[2] <= GOAL else "NOT met"
    print(f"scene layer: {layer[2] - 1:+.1%} of the sweep's time (goal < +5 %: {verdict}); "
          f"App arrays bit-identical to sweep(): {'yes' if same else 'NO'}")
    print(f"medians of {PAIRS} interleaved pairs in process, of 5 for the commands (no figures "
          "in either: the scene copied without its [output] table; kernels cached); "
          "ratio: the median of the pairs' ratios")


def _largest_change(full: list[dict], other: list[dict], key: str) -> float:
    """Largest |other - full| of ``key`` over the points, over each curve's largest App."""
    worst = 0.0
    for a, b in zip(full, other, strict=True):
        x, y = np.asarray(a[key], float), np.asarray(b[key], float)
        change = np.abs(y - x) / np.nanmax(np.abs(a["app_m"]))
        change[np.isnan(x) & np.isnan(y)] = 0.0
        worst = max(worst, float(np.max(np.nan_to_num(change, nan=np.inf))))
    return worst


def auto_against_full(pa_frac: float, start: float, stop: float, count: int) -> None:
    auto = parse_scene(AUTO.format(pa_frac=pa_frac, start=start, stop=stop, count=count))
    full = replace(auto, effects=FULL)
    reference = run_scene(full)
    run_scene(auto)  # warm-up: compiles (or loads) the kernels of every model it tries
    times = _pair_ratios(lambda: run_scene(auto), lambda: run_scene(full), 5)
    chosen = run_scene(auto)
    header(f"effects = \"auto\" against the full model: {auto.title.removesuffix(', auto')}, "
           f"{count} points, sweep up")
    _ratio_row("auto, whole run_scene [s] vs full model", times)
    app = _largest_change(reference.observables, chosen.observables, "app_m")
    ymin = _largest_change(reference.observables, chosen.observables, "ymin_m")
    row("largest App change / max App vs tolerance", app, auto.tolerance, ratio=False)
    row("largest y_min change / max App vs tolerance", ymin, auto.tolerance, ratio=False)
    slower = times[2]
    print(f"auto takes {slower:.2f}x the full model's time ("
          + ("slower: the selection runs the sample several times" if slower > 1 else "faster")
          + f"); it ran the {chosen.route}: {Effects(**chosen.effects).describe()}")
    tried = ", ".join(f"{r['effect']} {r['seconds']:.3f} s ({r['verdict'].split(' (')[0]})"
                      for r in chosen.selection if r["seconds"] is not None)
    print(f"candidates on the sample: {tried}")
    print(f"its note: {chosen.selection_note}")


def main() -> None:
    scene_layer()
    for settings in AUTO_SCENES:
        auto_against_full(*settings)


if __name__ == "__main__":
    main()
