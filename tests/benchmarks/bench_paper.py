"""`make paper`'s job, `python -m paper_checks`, from an empty kernel cache and again.

Goals: under 60 s from a fresh clone (nothing compiled or cached yet), under 20 s
on a second run. Baseline: the goal itself (the ratio says how far under it).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

from ._timing import header, row

GOALS = {"cold": 60.0, "warm": 20.0}


def _run(env: dict, out: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "paper_checks", "--out", out, "--quiet"], env=env,
                   check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = os.environ | {"CONTACT_RESONANCES_CACHE": cache}
        cold = _run(env, out)
        warm = _run(env, out)
    header("`python -m paper_checks` (make paper), wall time, goal as baseline")
    row("first run, empty kernel cache [s]", cold, GOALS["cold"], "s", higher_is_better=False)
    row("second run, kernels cached [s]", warm, GOALS["warm"], "s", higher_is_better=False)


if __name__ == "__main__":
    main()
