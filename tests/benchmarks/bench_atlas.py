"""The multistability atlas (issue 13, item 5): time per cell, and the issue's goal.

Grid: the paper's band 250-1800 Hz and P_a 0.05-0.5 Q. Baseline, measured in the same
run: ``attractor_census()`` called cell by cell in this process, the route without the
atlas. Beside it: the atlas in this process (the batching alone: many cells per kernel
call) and with the default pool (every processor). Then the time per cell against the
cells per task (``TASK_LANES``), the whole command as a new process, the atlas on a dask
LocalCluster of two workers if dask is installed, and the issue's goal: a 100 x 50
grid with 50 initial states per cell under 60 s on the 2-core machine, run once and
also extrapolated from the 20 x 10 grid. Medians of 3 runs, warm (kernels compiled).
"""

from __future__ import annotations

import logging
import os
import statistics
import subprocess
import sys
import time

import numpy as np

from numerics import atlas, attractor_census
from perturb.common import processors

from ._timing import header, median_time, row

BAND, AMPLITUDES = (250.0, 1800.0), (0.05, 0.5)
GRID = (20, 10)
GOAL_GRID, GOAL_S = (100, 50), 60.0
#: 50 initial states (the issue's count), a subset of the census's default 98: rest,
#: deep compression, release from above, velocities up and down.
STATES_50 = {"y_over_y0": (-29.0, -11.0, -4.0, -1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0),
             "v_over_omega0_y0": (-8.0, -1.0, 0.0, 1.0, 8.0)}
REPEATS = 3


def run(grid=GRID, **options):
    return atlas(*BAND, *AMPLITUDES, grid=grid, **options)


def cell_by_cell(grid=GRID) -> None:
    """The baseline: one census per cell, in this process."""
    for pa_frac in np.linspace(*AMPLITUDES, grid[1]):
        for frequency_hz in np.linspace(*BAND, grid[0]):
            attractor_census(frequency_hz, pa_frac)


def main() -> None:
    atlas(740.0, 760.0, 0.15, 0.15, grid=(2, 1), workers=1)  # compile / load the kernels
    cells = GRID[0] * GRID[1]
    serial = median_time(cell_by_cell, REPEATS)
    batched = median_time(lambda: run(workers=1), REPEATS)
    pooled = median_time(run, REPEATS)
    workers = processors()
    header(f"Atlas {GRID[0]} x {GRID[1]} cells, 98 initial states, {BAND[0]:g}-{BAND[1]:g} Hz, "
           f"{AMPLITUDES[0]:g}-{AMPLITUDES[1]:g} Q (medians of {REPEATS})")
    row("attractor_census() cell by cell [s]", serial, unit="s")
    row("atlas in this process [s] vs cell by cell", batched, serial, "s",
        higher_is_better=False)
    row(f"atlas, default pool ({workers} workers) [s] vs cell by cell", pooled, serial, "s",
        higher_is_better=False)
    row("  time per cell, pool [ms] vs cell by cell", pooled / cells * 1e3,
        serial / cells * 1e3, "ms", higher_is_better=False)
    _cells_per_task()
    _command()
    _dask()
    _goal(workers)


def _cells_per_task() -> None:
    """Time per cell against the size of a task (in this process: the batching alone)."""
    grid, times = (20, 5), {}
    for lanes in (98, 490, 2048, 8192):
        times[lanes] = median_time(
            lambda lanes=lanes: run(grid=grid, workers=1, task_lanes=lanes), REPEATS)
    header(f"Time per cell against lanes per task ({grid[0]} x {grid[1]} cells, in this "
           f"process; baseline: 1 cell per task)")
    for lanes, spent in times.items():
        row(f"task_lanes = {lanes} ({-(-lanes // 98)} cells) [ms per cell]",
            spent / (grid[0] * grid[1]) * 1e3, times[98] / (grid[0] * grid[1]) * 1e3, "ms",
            higher_is_better=False)


def _command() -> None:
    """`python -m numerics atlas --grid 20 10` as a new process, start-up included."""
    command = [sys.executable, "-m", "numerics", "atlas", "--grid", *map(str, GRID), "--quiet"]
    spent = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, env=os.environ)
        spent.append(time.perf_counter() - start)
    header("The command, as a new process (median of 3)")
    row(f"python -m numerics atlas --grid {GRID[0]} {GRID[1]} [s]", statistics.median(spent),
        unit="s")


def _dask() -> None:
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        print("\n(dask.distributed not installed: `pip install .[distributed]`; skipped)")
        return
    # Workers that lose the scheduler as the cluster closes log it; not a result here.
    with (LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                       dashboard_address=None, silence_logs=logging.CRITICAL) as cluster,
          Client(cluster) as client):
        # pure=False: dask would hand back the results of the same tasks it still holds.
        executor = client.get_executor(pure=False)
        start = time.perf_counter()
        run(executor=executor)  # the workers import the toolkit and load the kernels
        first = time.perf_counter() - start
        warm = median_time(lambda: run(executor=executor), REPEATS)
    pooled = median_time(run, REPEATS)
    header(f"dask LocalCluster (2 workers, 1 thread each), {GRID[0]} x {GRID[1]} cells")
    row("first atlas on new workers [s] vs default pool", first, pooled, "s",
        higher_is_better=False)
    row("warm [s] vs default pool", warm, pooled, "s", higher_is_better=False)


def _goal(workers: int) -> None:
    cells = GRID[0] * GRID[1]
    small = median_time(lambda: run(initial_states=STATES_50), REPEATS)
    start = time.perf_counter()
    found = run(grid=GOAL_GRID, initial_states=STATES_50)
    goal = time.perf_counter() - start
    goal_cells = GOAL_GRID[0] * GOAL_GRID[1]
    estimate = small / cells * goal_cells
    header(f"The goal: {GOAL_GRID[0]} x {GOAL_GRID[1]} cells, 50 initial states, "
           f"under {GOAL_S:g} s ({workers} workers)")
    row(f"{GRID[0]} x {GRID[1]} cells, 50 states [ms per cell]", small / cells * 1e3, unit="ms")
    row(f"  extrapolated to {goal_cells} cells [s] vs the goal", estimate, GOAL_S, "s",
        higher_is_better=False)
    row(f"{GOAL_GRID[0]} x {GOAL_GRID[1]} cells, 50 states, run once [s] vs the goal", goal,
        GOAL_S, "s", higher_is_better=False)
    row("  time per cell [ms] (x cells / workers: a cluster's run)",
        goal / goal_cells * 1e3, unit="ms")
    print(f"  goal {'met' if goal < GOAL_S else 'NOT met'}: {goal:.1f} s on {workers} "
          f"workers; {found.summary()}")


if __name__ == "__main__":
    main()
