"""Whole commands as a user runs them: a new process each, `--quiet`, kernels cached.

Issue 12, item 1 (start-up): `python -m numerics sweep` (the Fig. 2 + 3 job),
`info` and `attractors --pa-frac 0.5 --fe 490`, each the median of several runs,
beside the same command run by the old route in the same run: the tree of
BASELINE_COMMIT (before the model's numbers were cached and the packages' imports
made lazy), extracted with `git archive` into a temporary folder and run with the
same interpreter. Without git (or that commit), the issue's own measurements are
printed as the baseline instead, and the header says so.

Each route runs every command once before the timing, so that its kernels are
in the cache (the old route's kernel files have other keys than the new one's);
the two routes then run in turn, so that a drift in the machine's load falls on
both alike. On a shared machine the wall time grows with the others' load; the
CPU time of the process (user + system) is printed too, as it grows much less.
"""

from __future__ import annotations

import io
import os
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

from ._timing import header, row

ROOT = Path(__file__).resolve().parents[2]
#: The last commit before issue 12's start-up work: the old route.
BASELINE_COMMIT = "f60ea91"
REPEATS = 5

COMMANDS = {
    "sweep": ["sweep", "--quiet"],
    "info": ["info"],  # prints seven numbers; it has no progress to silence
    "attractors": ["attractors", "--pa-frac", "0.5", "--fe", "490", "--quiet"],
}
#: `make compiled`'s build of the paper model's compiled sweep driver.
_BUILD_DRIVER = "from numerics import sweep; sweep([1000.0], 0.1, engine='compiled')"
#: Issue 12's table: the wall time measured when it was filed, and the goal [s].
ISSUE = {"sweep": (3.4, 1.2), "info": (1.4, 0.5), "attractors": (1.8, 1.0)}

#: Run a command in this process and print which heavy modules it imported.
_WHICH_MODULES = (
    "import runpy, sys\n"
    "sys.argv = ['numerics', *sys.argv[1:]]\n"
    "try:\n"
    "    runpy.run_module('numerics', run_name='__main__', alter_sys=True)\n"
    "except SystemExit:\n"
    "    pass\n"
    "heavy = ('sympy', 'scipy.optimize', 'numba', 'matplotlib')\n"
    "print(' '.join(m for m in heavy if m in sys.modules) or 'none', file=sys.stderr)\n"
)


def old_tree(folder: Path, commit: str = BASELINE_COMMIT) -> Path | None:
    """The tree of ``commit`` in ``folder``, or None without git or the commit."""
    try:
        archive = subprocess.run(["git", "archive", commit], cwd=ROOT, check=True,
                                 capture_output=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    return folder


def cpu_of_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _runner(tree: Path):
    """A function that runs ``python ARGS`` on the code of ``tree`` and returns its
    wall time and CPU time [s] (cwd and PYTHONPATH: the tree, so its packages shadow
    any other)."""
    env = os.environ | {"PYTHONPATH": str(tree)}

    def run(args: list[str]) -> tuple[float, float]:
        cpu, start = cpu_of_children(), time.perf_counter()
        subprocess.run([sys.executable, *args], cwd=tree, env=env, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.perf_counter() - start, cpu_of_children() - cpu

    return run


def _heavy_modules(tree: Path, args: list[str]) -> str:
    env = os.environ | {"PYTHONPATH": str(tree)}
    done = subprocess.run([sys.executable, "-c", _WHICH_MODULES, *args], cwd=tree, env=env,
                          check=True, capture_output=True, text=True)
    return done.stderr.strip().splitlines()[-1]


def _medians(runs: dict, args: list[str]) -> dict[str, tuple[float, float]]:
    """Median wall time and CPU time of each route, the routes run in turn."""
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in runs}
    for _ in range(REPEATS):
        for name, run in runs.items():
            times[name].append(run(args))
    return {name: tuple(statistics.median(column) for column in zip(*spent))
            for name, spent in times.items()}


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        old = old_tree(Path(folder))
        runs = {"new": _runner(ROOT)}
        if old is not None:
            runs["old"] = _runner(old)
        for args in COMMANDS.values():  # fill each route's kernel cache, untimed
            for run in runs.values():
                run(["-m", "numerics", *args])
        # The new route's sweep takes the compiled driver once it is built (`make
        # compiled`, the first call of _BUILD_DRIVER); build it here, untimed, so that the
        # figure does not depend on what ran before the benchmark.
        runs["new"](["-c", _BUILD_DRIVER])
        imports = _medians(runs, ["-c", "import numerics.cli"])
        wall = {name: _medians(runs, ["-m", "numerics", *args])
                for name, args in COMMANDS.items()}
        heavy = {name: _heavy_modules(ROOT, args) for name, args in COMMANDS.items()}
    source = (f"old route ({BASELINE_COMMIT}) in this run" if old is not None
              else "the issue's measurement (no git tree of the old route here)")
    header(f"Whole commands, new process each, median of {REPEATS}; baseline: {source}")
    for name in COMMANDS:
        baseline = wall[name]["old"][0] if old is not None else ISSUE[name][0]
        row(f"{name}: wall time [s]", wall[name]["new"][0], baseline, "s",
            higher_is_better=False)
        if old is not None:
            row(f"{name}: CPU time [s]", wall[name]["new"][1], wall[name]["old"][1], "s",
                higher_is_better=False)
    if old is not None:
        for column, what in enumerate(("wall", "CPU")):
            row(f"import numerics.cli (before any work): {what} [s]", imports["new"][column],
                imports["old"][column], "s", higher_is_better=False)
    print("commands: " + "; ".join(f"python -m numerics {' '.join(args)}"
                                   for args in COMMANDS.values()))
    print("goals [s]: " + ", ".join(f"{n} <= {g}" for n, (_, g) in ISSUE.items()))
    print("heavy modules imported (new route, cache warm): "
          + "; ".join(f"{name}: {found}" for name, found in heavy.items()))
    print("new route: the compiled sweep driver built before the timing (make compiled); "
          "without it the sweep takes the Python route")


if __name__ == "__main__":
    main()
