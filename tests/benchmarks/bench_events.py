"""What locating the contact switches within the step costs, and what it buys.

Baseline, measured in the same run: the route before the switches were located, the
tree of ROUTE_BEFORE (each step integrated straight over y = 0), extracted with
`git archive` and run with the same interpreter, its kernels in a cache folder of
their own. The two routes run in turn, so that a drift in the machine's load falls on
both alike.

- The Fig. 2 + 3 job (ten amplitudes up and down, 311 frequencies, compiled sweep),
  warm: the median of REPEATS calls in each route's process.
- The kernel without contact loss: RK4 lane-steps of ``advance_periods`` at 0.005 Q,
  where no lane comes near y = 0 (the straight path alone).
- Steps per period that an accuracy needs on a bouncing state (the paper's contact,
  490 Hz, 0.5 Q): the error after 3 periods against DOP853 with events (rtol 1e-13),
  and the least N of 64 ... 4096 (powers of 2) that reaches each accuracy, in each route.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from ._timing import header, row
from .bench_commands import ROOT, _old_tree

#: The last commit whose steps integrate straight over y = 0.
ROUTE_BEFORE = "472fbcb"
REPEATS = 5
ROUNDS = 3  # of each route's timing process, in turn
STEPS = (64, 128, 256, 512, 1024, 2048, 4096)
ACCURACIES = (1e-4, 1e-6, 1e-8)  # |y - y_reference| / y0 after 3 periods

#: Run in a route's tree: the job's and the kernel's warm medians [s] and [ns].
_TIMES = r"""
import json, statistics, sys, time
import numpy as np
from numerics import compiled_kernels, drive_table, sweep
from perturb import PAPER, PAPER_BAND_HZ, PAPER_PANEL_FRACTIONS, ContactModel, eq26_numbers

repeats = int(sys.argv[1])
grid = np.linspace(*PAPER_BAND_HZ, 311)
job = lambda: sweep(grid, PAPER_PANEL_FRACTIONS, engine="compiled")
job()
times = []
for _ in range(repeats):
    start = time.perf_counter(); job(); times.append(time.perf_counter() - start)
model = ContactModel(); kernels = compiled_kernels(model)
lanes, steps, periods = 64, 512, 20
f_e = np.linspace(800.0, 1800.0, lanes); p_a = np.full(lanes, 0.005 * PAPER.Q_n)
y = np.full(lanes, eq26_numbers().y0_m); v = np.zeros(lanes); dt = 1 / (steps * f_e)
drive, failed, limit = drive_table(steps), np.full(lanes, -1), np.full(lanes, np.inf)
kernels.advance_periods(y, v, dt, p_a, drive, 1, failed, limit)
kernel = []
for _ in range(4 * repeats):
    start = time.perf_counter()
    kernels.advance_periods(y, v, dt, p_a, drive, periods, failed, limit)
    kernel.append((time.perf_counter() - start) / (lanes * steps * periods) * 1e9)
print(json.dumps([statistics.median(times), statistics.median(kernel)]))
"""

#: Run in a route's tree: |y - y_ref| / y0 after 3 periods from (argv) at each N.
_ERRORS = r"""
import json, sys
from numerics import simulate
from perturb import PAPER, eq26_numbers

y, v, reference = (float(a) for a in sys.argv[1:4])
steps = json.loads(sys.argv[4])
errors = []
for n in steps:
    run = simulate(490.0, 0.5 * PAPER.Q_n, periods=3, steps_per_period=n, y_init_m=y,
                   v_init_m_s=v, record=("final",))
    errors.append(abs(run.y_final_m[0] - reference) / eq26_numbers().y0_m)
print(json.dumps(errors))
"""


def _run(tree: Path, cache: Path, snippet: str, *args: str) -> list:
    env = os.environ | {"PYTHONPATH": str(tree), "CONTACT_RESONANCES_CACHE": str(cache)}
    done = subprocess.run([sys.executable, "-c", snippet, *args], cwd=tree, env=env,
                          check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _bouncing_start() -> tuple[float, float, float]:
    """A state on the bouncing orbit (60 periods from a flight 2 um up, at 4096 steps)
    and DOP853's y after 3 periods from it."""
    from numerics import simulate
    from numerics._reference import reference_last_period
    from perturb import PAPER, ContactModel

    p_a = 0.5 * PAPER.Q_n
    start = simulate(490.0, p_a, periods=60, steps_per_period=4096, y_init_m=-2e-6,
                     record=("final",))
    y, v = float(start.y_final_m[0]), float(start.v_final_m_s[0])
    _, reference = reference_last_period(ContactModel(), 490.0, p_a, y, v, 3, rtol=1e-13,
                                         samples=2)
    return y, v, float(reference[-1])


def _least_steps(errors: list[float], accuracy: float) -> float:
    """The least N of STEPS whose error is within ``accuracy`` (nan: none)."""
    within = [n for n, e in zip(STEPS, errors) if e <= accuracy]
    return float(within[0]) if within else float("nan")


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        before = _old_tree(folder / "before", ROUTE_BEFORE)
        if before is None:
            print(f"\n(no git or no commit {ROUTE_BEFORE}: the events benchmark needs the "
                  "route before them)")
            return
        trees = {"events": ROOT, "before": before}
        caches = {name: folder / f"cache-{name}" for name in trees}
        times: dict[str, list] = {name: [] for name in trees}
        for _ in range(ROUNDS):
            for name, tree in trees.items():
                times[name].append(_run(tree, caches[name], _TIMES, str(REPEATS)))
        start = _bouncing_start()
        errors = {name: _run(tree, caches[name], _ERRORS, *map(repr, start), json.dumps(STEPS))
                  for name, tree in trees.items()}
    job = {name: float(np.median([t[0] for t in runs])) for name, runs in times.items()}
    kernel = {name: float(np.median([t[1] for t in runs])) for name, runs in times.items()}
    header(f"Contact switches located within the step, against the route before "
           f"({ROUTE_BEFORE}), medians of {ROUNDS} x {REPEATS}")
    row("Fig. 2 + 3 job, compiled, warm [s] vs before", job["events"], job["before"], "s",
        higher_is_better=False)
    row("kernel, no lane near y = 0 [ns/lane-step] vs before", kernel["events"],
        kernel["before"], "ns", higher_is_better=False)
    for n, new, old in zip(STEPS, errors["events"], errors["before"]):
        row(f"bouncing, 490 Hz, 0.5 Q: error / y0 at N = {n} vs before", new, old,
            higher_is_better=False)
    for accuracy in ACCURACIES:
        row(f"  steps per period for {accuracy:g} of y0 vs before",
            _least_steps(errors["events"], accuracy), _least_steps(errors["before"], accuracy),
            higher_is_better=False)


if __name__ == "__main__":
    main()
