"""`python -m paper_checks [--quick] [--out DIR]`: check the paper's claims, redraw its
figures, and write DIR/report.md and DIR/report.json (DIR is out/ by default)."""

from __future__ import annotations

import time

_START = time.perf_counter()  # before the heavy imports: the run's wall time includes them

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from common import int_at_least, output_dir  # noqa: E402
from numerics._codegen import cache_dir  # noqa: E402

from ._report import write_report  # noqa: E402


def _kernel_files() -> set[str]:
    return {p.name for p in cache_dir().glob("kernel_*.py")}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m paper_checks", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="coarser grids (for tests)")
    parser.add_argument("--out", default="out", type=output_dir,
                        help="output folder, created if its parent exists (default: out)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but failures")
    # One job by default: on the shared 2-core machine two workers measured slower
    # (make bench: 16.6 s against 14.2 s for a second run).
    parser.add_argument("--jobs", type=int_at_least(1), default=1,
                        help="worker processes that run the scenes and draw their figures "
                             "(default 1: all in this process)")
    args = parser.parse_args(argv)
    out = Path(args.out)  # checked (and created) by its type, before any work
    cached = _kernel_files()
    report = write_report(out, quick=args.quick, started=_START,
                          kernels_cached_before=len(cached), kernel_files=_kernel_files,
                          jobs=args.jobs)
    for claim in report["claims"]:
        if not args.quiet or not claim["passed"]:
            mark = "pass" if claim["passed"] else "FAIL"
            print(f"[{mark}] {claim['id']}: {claim['statement']}")
    if not args.quiet:
        print(f"report: {out / 'report.md'} ({report['elapsed_s']:.1f} s)")
    return 0 if all(c["passed"] for c in report["claims"]) else 1


if __name__ == "__main__":
    sys.exit(main())
