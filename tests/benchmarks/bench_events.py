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
- Steps per period that an accuracy needs on a bouncing state at 0.5 Q: the error after
  3 periods against DOP853 with events (rtol 1e-13), and the least N of 64 ... 4096
  (powers of 2) that reaches each accuracy, in each route; for the paper's contact
  (490 Hz), the spring-dashpot one (m2 = 1, l = 0, 700 Hz) and m2 = 1.5, l = 0.5
  (490 Hz), each with the paper's y0 and c (c_n and h_n rescaled, as
  tests/test_events.py's ``contact``).
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
from .bench_commands import ROOT, old_tree

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
from numerics import sweep
try:
    from numerics.kernels import compiled_kernels, drive_table
except ImportError:  # a route's tree from before the kernels had their own folder
    from numerics import compiled_kernels, drive_table
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

#: (name, m2, l, f_e [Hz]) of the contacts whose bouncing states are measured.
CONTACTS = (("paper's contact", 2.0, 1.0, 490.0), ("spring-dashpot", 1.0, 0.0, 700.0),
            ("m2 = 1.5, l = 0.5", 1.5, 0.5, 490.0))

#: Run in a route's tree: |y - y_ref| / y0 after 3 periods at each N, for each
#: (m2, l, f_e, y, v, y_ref) of argv[1] (JSON).
_ERRORS = r"""
import json, sys
from numerics import simulate
from perturb import PAPER, ContactModel, eq26_numbers, parameters_with

y0 = eq26_numbers().y0_m
steps = json.loads(sys.argv[2])
errors = []
for m2, l, f_e, y, v, reference in json.loads(sys.argv[1]):
    model = ContactModel(parameters_with({"m2": m2, "l": l,
                                          "c_n": PAPER.Q_n / (PAPER.S * y0**m2),
                                          "h_n": PAPER.h_n * y0**PAPER.l / y0**l}))
    row = []
    for n in steps:
        run = simulate(f_e, 0.5 * PAPER.Q_n, periods=3, steps_per_period=n, model=model,
                       y_init_m=y, v_init_m_s=v, record=("final",))
        row.append(abs(run.y_final_m[0] - reference) / y0)
    errors.append(row)
print(json.dumps(errors))
"""


def _run(tree: Path, cache: Path, snippet: str, *args: str) -> list:
    env = os.environ | {"PYTHONPATH": str(tree), "CONTACT_RESONANCES_CACHE": str(cache)}
    done = subprocess.run([sys.executable, "-c", snippet, *args], cwd=tree, env=env,
                          check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _bouncing_starts() -> list[tuple]:
    """For each of CONTACTS: (m2, l, f_e, y, v, y_ref), a state on its bouncing orbit (60
    periods from a flight 2 um up, at 4096 steps) and DOP853's y after 3 periods."""
    from numerics.simulation.reference import reference_last_period
    from perturb import PAPER, ContactModel
    from tests.test_events import bouncing_start, contact

    starts = []
    for _, m2, l, f_e in CONTACTS:
        model = ContactModel(contact(m2, l))
        p_a = 0.5 * PAPER.Q_n
        y, v = bouncing_start(model, f_e, p_a)
        _, reference = reference_last_period(model, f_e, p_a, y, v, 3, rtol=1e-13, samples=2)
        starts.append((m2, l, f_e, y, v, float(reference[-1])))
    return starts


def _least_steps(errors: list[float], accuracy: float) -> float:
    """The least N of STEPS whose error is within ``accuracy`` (nan: none)."""
    within = [n for n, e in zip(STEPS, errors) if e <= accuracy]
    return float(within[0]) if within else float("nan")


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        before = old_tree(folder / "before", ROUTE_BEFORE)
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
        starts = json.dumps(_bouncing_starts())
        errors = {name: _run(tree, caches[name], _ERRORS, starts, json.dumps(STEPS))
                  for name, tree in trees.items()}
    job = {name: float(np.median([t[0] for t in runs])) for name, runs in times.items()}
    kernel = {name: float(np.median([t[1] for t in runs])) for name, runs in times.items()}
    header(f"Contact switches located within the step, against the route before "
           f"({ROUTE_BEFORE}), medians of {ROUNDS} x {REPEATS}")
    row("Fig. 2 + 3 job, compiled, warm [s] vs before", job["events"], job["before"], "s",
        higher_is_better=False)
    row("kernel, no lane near y = 0 [ns/lane-step] vs before", kernel["events"],
        kernel["before"], "ns", higher_is_better=False)
    for c, (name, _m2, _l, f_e) in enumerate(CONTACTS):
        new_errors, old_errors = errors["events"][c], errors["before"][c]
        print(f"{name}, bouncing at {f_e:g} Hz, 0.5 Q:")
        for n, new, old in zip(STEPS, new_errors, old_errors):
            row(f"  error / y0 after 3 periods at N = {n} vs before", new, old,
                higher_is_better=False)
        slopes = np.log2(np.array(new_errors[:-1]) / np.array(new_errors[1:]))
        print(f"  slopes of the error, N = {STEPS[0]} ... {STEPS[-1]}: "
              + ", ".join(f"{slope:.1f}" for slope in slopes))
        for accuracy in ACCURACIES:
            row(f"  steps per period for {accuracy:g} of y0 vs before",
                _least_steps(new_errors, accuracy), _least_steps(old_errors, accuracy),
                higher_is_better=False)


if __name__ == "__main__":
    main()
