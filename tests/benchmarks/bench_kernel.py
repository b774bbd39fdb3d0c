"""Kernel throughput: RK4 lane-steps per second on one core, full model with contact loss.

Baseline, in the same run: a straightforward compiled loop, one lane at a time,
that evaluates cos and pow in its right-hand side at every stage (the textbook
way). Also the one-off compile time, and what the on-disk cache leaves of it.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from numerics.kernels import compiled_kernels, drive_table
from perturb import PAPER, ContactModel, eq26_numbers

from ._textbook import PARAMETERS, textbook_rk4
from ._timing import header, median_time, row
from .bench_commands import ROOT, old_tree

LANES, STEPS, PERIODS = 1000, 128, 40


def _lanes(model):
    f_e = np.linspace(250.0, 1800.0, LANES)
    p_a = np.full(LANES, 0.5 * PAPER.Q_n)  # strong drive: most lanes lose contact
    y = np.full(LANES, eq26_numbers(model.parameters).y0_m)
    return f_e, p_a, y, np.zeros(LANES)


def throughput() -> tuple[float, float, float]:
    model = ContactModel()
    kernels = compiled_kernels(model)
    f_e, p_a, y, v = _lanes(model)
    drive = drive_table(STEPS)
    failed = np.full(LANES, -1)
    dt = 1.0 / (STEPS * f_e)
    limit = np.full(LANES, np.inf)
    kernels.advance_periods(y, v, dt, p_a, drive, 1, failed, limit)  # compile / load
    generated = median_time(
        lambda: kernels.advance_periods(y, v, dt, p_a, drive, PERIODS, failed, limit))
    lost = float(np.mean(_lost_contact(kernels, model)))
    args = (STEPS, PERIODS // 4, PARAMETERS)
    f2, p2, y2, v2 = _lanes(model)
    textbook_rk4(y2[:2], v2[:2], f2[:2], p2[:2], *args)  # compile / load
    textbook = median_time(lambda: textbook_rk4(y2, v2, f2, p2, *args), repeats=3)
    lane_steps = LANES * STEPS
    return lane_steps * PERIODS / generated, lane_steps * PERIODS / 4 / textbook, lost


def _lost_contact(kernels, model):
    f_e, p_a, y, v = _lanes(model)
    ymin, ymax = np.empty(LANES), np.empty(LANES)
    empty = np.empty((LANES, 0))
    limit = np.full(LANES, np.inf)
    kernels.advance_periods(y, v, 1 / (STEPS * f_e), p_a, drive_table(STEPS), 100,
                            np.full(LANES, -1), limit)
    kernels.record_periods(y, v, 1 / (STEPS * f_e), p_a, drive_table(STEPS), 1,
                           np.full(LANES, -1), 0, ymin, ymax, empty, empty,
                           np.empty((LANES, 0), np.int8), np.zeros(LANES, np.int64), empty, empty,
                           limit)
    return ymin < 0


_COMPILE_SNIPPET = (
    "import time; t=time.perf_counter(); from numerics import simulate;"
    "t1=time.perf_counter(); simulate(1000.0, 0.1, periods=2);"
    "print(t1-t, time.perf_counter()-t1)"
)


#: The route before the kernels copied their arrays in loops (``copy_into``) and stepped both
#: columns of the monodromy matrix from one evaluation of the partials
#: (``rk4_step_tangents``): the baseline of the compile time and of ``shoot_periods``.
ROUTE_BEFORE = "035305f"
ROUTE_REPEATS = 3
#: Run in a route's tree, its kernels cached: ns per lane-step of shoot_periods on one
#: lane and on 64.
_SHOOT_SNIPPET = ("from tests.benchmarks.bench_kernel import one_lane_against_many;"
                  "print(*one_lane_against_many())")


def compile_times(tree: Path = ROOT) -> list[tuple[float, float]]:
    """(import, first simulate()) in a fresh process with an empty cache, then again,
    with the code of ``tree``."""
    with tempfile.TemporaryDirectory() as cache:
        env = os.environ | {"CONTACT_RESONANCES_CACHE": cache, "PYTHONPATH": str(tree)}
        runs = [_run(tree, env, _COMPILE_SNIPPET) for _ in range(2)]
    return [tuple(float(x) for x in r) for r in runs]


def _run(tree: Path, env: dict, snippet: str) -> list[str]:
    return subprocess.run([sys.executable, "-c", snippet], env=env, cwd=tree,
                          capture_output=True, text=True, check=True).stdout.split()


def against_route_before() -> dict[str, tuple[float, float]] | None:
    """{figure: (this route, ROUTE_BEFORE's)}, medians of runs in turn: the first
    simulate() with an empty cache [s], and shoot_periods' ns per lane-step on one lane
    and on 64 (None without git or that commit)."""
    names = ("first simulate(), empty cache [s]", "shoot_periods, one lane [ns/lane-step]",
             "shoot_periods, 64 lanes [ns/lane-step]")
    with tempfile.TemporaryDirectory() as folder:
        before = old_tree(Path(folder) / "tree", ROUTE_BEFORE)
        if before is None:
            return None
        runs: dict[Path, list[list[float]]] = {ROOT: [], before: []}
        for _ in range(ROUTE_REPEATS):
            for tree, spent in runs.items():
                with tempfile.TemporaryDirectory() as cache:
                    env = os.environ | {"CONTACT_RESONANCES_CACHE": cache,
                                        "PYTHONPATH": str(tree)}
                    compile_s = float(_run(tree, env, _COMPILE_SNIPPET)[1])
                    spent.append([compile_s, *map(float, _run(tree, env, _SHOOT_SNIPPET))])
    medians = {tree: np.median(np.array(spent), axis=0) for tree, spent in runs.items()}
    return {name: (medians[ROOT][i], medians[before][i]) for i, name in enumerate(names)}


def one_lane_against_many(lanes: int = 64, steps: int = 1024) -> tuple[float, float]:
    """ns per lane-step of ``shoot_periods`` (the state and monodromy, as a Newton step
    needs) on one lane and on ``lanes`` lanes (of the same orbit): one lane waits on its
    own chain of stages (latency), many lanes fill the core (throughput). Continuation
    walks one orbit at a time: one lane."""
    model = ContactModel()
    kernels, drive = compiled_kernels(model), drive_table(steps)
    y0, q = eq26_numbers(model.parameters).y0_m, model.parameters.Q_n

    def run(n):
        y, v = np.full(n, -27.0 * y0), np.zeros(n)
        kernels.shoot_periods(y, v, np.full(n, 1.0 / (steps * 400.0)), np.full(n, 0.15 * q),
                              drive, 4, np.empty((n, 2, 2)))

    run(1), run(lanes)  # compiled / loaded
    return tuple(1e9 * median_time(lambda n=n: run(n), repeats=7) / (4 * steps * n)
                 for n in (1, lanes))


def batch_widths(steps: int = 128) -> dict[tuple[str, int], float]:
    """ns per step of a whole batch of n lanes (contact lost), by kernel and n: the
    kernels' vector loops take VECTOR_LANES lanes at a time and the lanes left over run
    one by one; ``shoot_periods`` and ``record_periods`` pad a batch to whole vectors
    where two or more are left over, ``advance_periods`` does not."""
    model = ContactModel()
    k, drive = compiled_kernels(model), drive_table(steps)
    y0, q = eq26_numbers(model.parameters).y0_m, model.parameters.Q_n

    def run(name, n):
        y, v = np.full(n, -27.0 * y0), np.zeros(n)
        dt, p_a = np.full(n, 1.0 / (steps * 400.0)), np.full(n, 0.15 * q)
        if name == "shoot_periods":
            k.shoot_periods(y, v, dt, p_a, drive, 4, np.empty((n, 2, 2)))
        elif name == "advance_periods":
            k.advance_periods(y, v, dt, p_a, drive, 4, np.full(n, -1), np.full(n, np.inf))
        else:
            k.record_periods(y, v, dt, p_a, drive, 4, np.full(n, -1), 0, np.empty(n),
                             np.empty(n), np.empty((n, 64)), np.empty((n, 64)),
                             np.empty((n, 64), dtype=np.int8), np.zeros(n, dtype=np.int64),
                             np.empty((n, 0)), np.empty((n, 0)), np.full(n, np.inf))

    cases = [("advance_periods", 4), ("advance_periods", 8), ("shoot_periods", 8),
             ("shoot_periods", 9), ("shoot_periods", 16), ("shoot_periods", 20),
             ("record_periods", 1), ("record_periods", 20)]
    for case in cases:
        run(*case)  # compiled / loaded
    return {case: 1e9 * median_time(lambda case=case: run(*case), repeats=7) / (4 * steps)
            for case in cases}


def main() -> None:
    generated, textbook, lost = throughput()
    header(f"RK4 kernel: {LANES} lanes, full model, {lost:.0%} of lanes lose contact, one core")
    row("generated batched kernel [lane-steps/s]", generated, textbook, "/s")
    row("  goal [lane-steps/s]", 1e8, None)
    many, one = one_lane_against_many()[::-1]
    row("shoot_periods, 64 lanes [ns/lane-step] vs one lane [ns/step]", many, one, "ns",
        higher_is_better=False)
    width = batch_widths()
    vector = compiled_kernels(ContactModel()).VECTOR_LANES
    header(f"batches and whole vectors ({vector} lanes): ns per step of the whole batch")
    row("advance_periods, 4 lanes (one by one) vs 8 (one vector loop)",
        width["advance_periods", 4], width["advance_periods", 8], "ns", higher_is_better=False)
    row("shoot_periods, 9 lanes (the 9th alone) vs 8", width["shoot_periods", 9],
        width["shoot_periods", 8], "ns", higher_is_better=False)
    row("shoot_periods, 20 lanes (run as 24) vs 16", width["shoot_periods", 20],
        width["shoot_periods", 16], "ns", higher_is_better=False)
    row("record_periods, 20 lanes (run as 24) vs 1 lane", width["record_periods", 20],
        width["record_periods", 1], "ns", higher_is_better=False)
    (import_cold, cold), (import_warm, warm) = compile_times()
    header("compile cost: a fresh process, empty cache (baseline) then cached")
    row("first simulate(), kernels cached on disk [s]", warm, cold, "s", higher_is_better=False)
    row("import numerics (numba, sympy) [s]", import_warm, import_cold, "s",
        higher_is_better=False)
    against = against_route_before()
    if against is not None:
        header(f"this route against {ROUTE_BEFORE} (array copies as slice assignments, "
               f"one tangent step a column), median of {ROUTE_REPEATS} in turn")
        for name, (now, before) in against.items():
            row(name, now, before, "s" if name.endswith("[s]") else "ns",
                higher_is_better=False)

if __name__ == "__main__":
    main()
