"""The peak memory of a command run in a new process: the largest resident set of the
command and of the children it waited for, from the kernel's accounting of a fresh
wrapper process (so earlier commands of the caller do not count)."""

from __future__ import annotations

import subprocess
import sys

#: The memory every accepted input stays within.
BUDGET_BYTES = 2 * 2**30

_WRAPPER = """
import resource, subprocess, sys, time
start = time.perf_counter()
try:
    code = subprocess.run(sys.argv[2:], timeout=float(sys.argv[1]),
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE).returncode
except subprocess.TimeoutExpired:
    code = None  # still working when the window closed: killed
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
print(code, peak, time.perf_counter() - start)
"""


def peak_memory(argv: list[str], window_s: float, cwd=None, env=None
                ) -> tuple[int | None, int, float]:
    """(exit code, or None if still running after ``window_s`` and killed; peak resident
    bytes; seconds) of ``argv`` run in a new process."""
    out = subprocess.run([sys.executable, "-c", _WRAPPER, str(window_s), *argv],
                         capture_output=True, text=True, check=True, cwd=cwd, env=env)
    code, peak, seconds = out.stdout.split()
    return (None if code == "None" else int(code)), int(peak), float(seconds)
