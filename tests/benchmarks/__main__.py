"""`make bench`: run every tests/benchmarks/bench_*.py main(), or those named.

    python -m tests.benchmarks [--record FILE] [NAME ...]   e.g. `kernel` for bench_kernel.py

``--record FILE`` also writes every figure with its baseline and ratio as JSON, with
the machine and the versions it ran on: the docs site's benchmark page
(docs/benchmarks.md) is drawn from it.
"""

from __future__ import annotations

import importlib
import json
import os
import pkgutil
import platform
import sys
import time
from importlib import metadata

import tests.benchmarks as package

from ._timing import RECORD


def main(argv: list[str]) -> int:
    record = None
    if argv[:1] == ["--record"]:
        if len(argv) < 2:
            print("--record needs a FILE")
            return 2
        from pathlib import Path

        record, argv = Path(argv[1]), argv[2:]
    modules = pkgutil.iter_modules(package.__path__)
    names = sorted(m.name for m in modules if m.name.startswith("bench_"))
    chosen = [n for n in names if not argv or n.removeprefix("bench_") in argv]
    if argv and not chosen:
        print(f"unknown benchmark {argv}; valid: {[n.removeprefix('bench_') for n in names]}")
        return 2
    for name in chosen:
        importlib.import_module(f"tests.benchmarks.{name}").main()
    if record is not None:
        record.write_text(json.dumps(_machine() | {"benchmarks": chosen, "sections": RECORD},
                                     indent=1) + "\n", encoding="utf-8")
    return 0


def _machine() -> dict:
    """What the figures were measured on."""
    versions = {name: metadata.version(name)
                for name in ("contact-resonances", "numpy", "scipy", "numba", "sympy")}
    return {"date": time.strftime("%Y-%m-%d"), "python": platform.python_version(),
            "machine": platform.machine(), "processors": len(os.sched_getaffinity(0)),
            "versions": versions}


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
