"""`make bench`: run every tests/benchmarks/bench_*.py main(), or those named.

    python -m tests.benchmarks [NAME ...]     e.g. `kernel` for bench_kernel.py
"""

from __future__ import annotations

import importlib
import pkgutil
import sys

import tests.benchmarks as package


def main(argv: list[str]) -> int:
    modules = pkgutil.iter_modules(package.__path__)
    names = sorted(m.name for m in modules if m.name.startswith("bench_"))
    chosen = [n for n in names if not argv or n.removeprefix("bench_") in argv]
    if argv and not chosen:
        print(f"unknown benchmark {argv}; valid: {[n.removeprefix('bench_') for n in names]}")
        return 2
    for name in chosen:
        importlib.import_module(f"tests.benchmarks.{name}").main()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
