"""The whole Fig. 2 + Fig. 3 job: ten amplitudes, up and down, 311 frequencies.

Baselines, measured in the same run:
- the Python-driven sweep (``engine="python"``: ``steady_states`` once per frequency),
  which the compiled sweep (one call per sweep) replaced;
- a plain compiled brute force (the paper's method: 150 periods of 400 steps per
  point from the previous point's state, no early stop), on two of the twenty
  runs, extrapolated;
- scipy's solve_ivp (DOP853, rtol 1e-9, 150 periods per point), on a few points,
  extrapolated.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from numerics import sweep
from numerics.kernels import compiled_kernels
from numerics.steady import sweep_compiled
from perturb import PAPER, PAPER_BAND_HZ, PAPER_PANEL_FRACTIONS, ContactModel, eq26_numbers

from ._textbook import PARAMETERS, brute_force_sweep, dop853_point
from ._timing import header, interleaved_medians, row

GRID = np.linspace(*PAPER_BAND_HZ, 311)
BRUTE = {"steps": 400, "periods": 150}
DOP853_POINTS = 3

_COLD = (
    "import sys, time, numpy as np; t = time.perf_counter();"
    "from numerics import sweep; from perturb import PAPER_PANEL_FRACTIONS as P;"
    "sweep(np.linspace(250, 1800, 311), P, engine=sys.argv[1]); print(time.perf_counter() - t)"
)


def cold_start(engine: str = "compiled") -> float:
    """The job in a fresh process with an empty kernel cache (import and compile included)."""
    with tempfile.TemporaryDirectory() as cache:
        env = os.environ | {"CONTACT_RESONANCES_CACHE": cache}
        out = subprocess.run([sys.executable, "-c", _COLD, engine], env=env,
                             capture_output=True, text=True, check=True)
    return float(out.stdout)


def brute_force(result) -> tuple[float, float]:
    """Seconds for the whole job, extrapolated from one amplitude up and down; and the
    largest relative App difference to the fast sweep on those runs."""
    y0 = eq26_numbers().y0_m
    frac = PAPER_PANEL_FRACTIONS[-1]
    p_a = frac * PAPER.Q_n
    brute_force_sweep(GRID[:2], p_a, y0, 8, 2, PARAMETERS)  # compile / load
    start = time.perf_counter()
    apps = [brute_force_sweep(grid, p_a, y0, BRUTE["steps"], BRUTE["periods"], PARAMETERS)
            for grid in (GRID, GRID[::-1])]
    elapsed = time.perf_counter() - start
    fast = [np.asarray(result.run(frac, d).app_m) for d in ("up", "down")]
    worst = max(np.max(np.abs(a / b - 1)) for a, b in zip(apps, fast))
    return elapsed * len(result.runs) / 2, worst


def dop853(result) -> float:
    """Seconds for the whole job, extrapolated from a few points."""
    y0 = eq26_numbers().y0_m
    points = GRID[:: len(GRID) // DOP853_POINTS][:DOP853_POINTS]
    start = time.perf_counter()
    for f in points:
        dop853_point(f, 0.3 * PAPER.Q_n, y0, BRUTE["periods"])
    per_point = (time.perf_counter() - start) / len(points)
    return per_point * sum(len(r.frequency_hz) for r in result.runs)


def in_one_thread(job):
    """``job`` with the compiled sweep sweeping all its lanes in one thread."""
    def run():
        threads = sweep_compiled.sweep_threads
        sweep_compiled.sweep_threads = lambda lanes, least: 1
        try:
            return job()
        finally:
            sweep_compiled.sweep_threads = threads
    return run


def _json_seconds(result) -> tuple[float, float]:
    """Medians, in turns: ``to_json`` of the job's result, and the text the json module
    gives with an indent (the pure-Python encoder) of the same data."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "job.json"
        return interleaved_medians(
            lambda: result.to_json(path),
            lambda: json.dumps(result.as_dict(), indent=1, allow_nan=False,
                               ensure_ascii=False), repeats=5)


def main() -> None:
    # engine="compiled": the default "auto" takes it only once its driver is built.
    job = lambda: sweep(GRID, PAPER_PANEL_FRACTIONS, engine="compiled")  # noqa: E731
    unchecked = lambda: sweep(GRID, PAPER_PANEL_FRACTIONS, app_rtol=None,  # noqa: E731
                              engine="compiled")
    python_route = lambda: sweep(GRID, PAPER_PANEL_FRACTIONS, engine="python")  # noqa: E731
    result = job()
    warm, warm_python = interleaved_medians(job, python_route, repeats=7)
    threaded, one_thread = interleaved_medians(job, in_one_thread(job), repeats=7)
    # 11 pairs: at load 1.0 (2026-11-23), with 7, the checked job took 0.221 s here and
    # 0.165 s in its pairs with the Python route just before: the machine, not the check.
    warm_checked, warm_unchecked = interleaved_medians(job, unchecked, repeats=11)
    # max_checked_steps=0: no jump check (``SweepRun.jumps`` then falls back to App's ratio).
    without_check = lambda: sweep(GRID, PAPER_PANEL_FRACTIONS, engine="compiled",  # noqa: E731
                                  max_checked_steps=0)
    jumps_checked, jumps_unchecked = interleaved_medians(job, without_check, repeats=9)
    cold, cold_python = cold_start(), cold_start("python")
    brute, brute_gap = brute_force(result)
    scipy_s = dop853(result)
    points = sum(len(r.frequency_hz) for r in result.runs)
    header(f"Fig. 2 + 3 job: {len(result.runs)} sweeps x {len(GRID)} points = {points} "
           f"steady states")
    row("compiled sweep, warm [s] vs Python-driven (goal 0.1)", warm, warm_python, "s",
        higher_is_better=False)
    threads = sweep_compiled.sweep_threads(len(result.runs),
                                           compiled_kernels(ContactModel()).VECTOR_LANES)
    row(f"  its lanes in {threads} thread(s), one per core [s] vs in one", threaded,
        one_thread, "s", higher_is_better=False)
    row("shooting sweep, kernels cached [s] vs brute force", warm, brute, "s",
        higher_is_better=False)
    row("shooting sweep, kernels cached [s] vs DOP853", warm, scipy_s, "s",
        higher_is_better=False)
    row("with the step-error check [s] vs without (goal >= 0.83x)", warm_checked,
        warm_unchecked, "s",
        higher_is_better=False)
    row("with the jump check [s] vs without (the ratio of App alone)", jumps_checked,
        jumps_unchecked, "s", higher_is_better=False)
    row("cold start: import + compile + job [s] vs Python-driven", cold, cold_python, "s",
        higher_is_better=False)
    written, indented = _json_seconds(result)
    row("writing its JSON [s] (goal 0.3) vs the json module with an indent", written,
        indented, "s", higher_is_better=False)
    row("goals: warm [s], cold [s]", 1.0, None)
    row("", 15.0, None)
    print(f"brute force: {BRUTE['periods']} periods x {BRUTE['steps']} steps, two runs timed "
          f"({brute / len(result.runs) * 2:.1f} s), extrapolated to {len(result.runs)}; "
          f"largest App difference to the fast sweep: {brute_gap:.2e} (relative)")
    print(f"DOP853 (rtol 1e-9): {DOP853_POINTS} points timed, extrapolated to {points}")
    refined = sum(int((r.steps_used > r.steps_used.min()).sum()) for r in result.runs)
    print(f"{result.summary()}; {refined} points refined by the step-error check")


if __name__ == "__main__":
    main()
