"""`python -m paper_checks [--quick] [--out DIR]`: check the paper's claims, redraw its
figures, and write DIR/report.md and DIR/report.json (DIR is out/ by default).

Exit status: 0 when every claim holds; 1 when a claim fails (each failure printed) or
the run fails (one line that says why; the traceback in a log file it names, when the
failure is the toolkit's own); 2 for bad options."""

from __future__ import annotations

import os
import time
from pathlib import Path


def _process_start() -> float:
    """``time.perf_counter()`` at this process's start, so that the run's wall time
    includes the interpreter's start and the imports of the package ``paper_checks``,
    which run before this module (about 1 s). Linux: from /proc (10 ms ticks);
    elsewhere the time this module is imported."""
    try:
        # Field 22 of /proc/self/stat, the start in clock ticks after boot; the fields
        # after the command's closing parenthesis begin at field 3.
        ticks = int(Path("/proc/self/stat").read_text().rsplit(")", 1)[1].split()[19])
        running = time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, AttributeError):
        return time.perf_counter()
    return time.perf_counter() - running


_START = _process_start()

import argparse  # noqa: E402
import atexit  # noqa: E402
import gc  # noqa: E402
import sys  # noqa: E402

from perturb.common import add_version, int_at_least, output_dir, program, run_command  # noqa: E402


def _kernel_files() -> set[str]:
    from numerics.kernels.codegen import cache_dir

    return {p.name for p in cache_dir().glob("kernel_*.py")}


def build_parser() -> argparse.ArgumentParser:
    """The command line of ``python -m paper_checks``."""
    parser = argparse.ArgumentParser(prog=program("paper_checks"), description=__doc__)
    add_version(parser)
    parser.add_argument("--quick", action="store_true", help="coarser grids (for tests)")
    parser.add_argument("--out", default="out", type=output_dir,
                        help="output folder, created if its parent exists (default: out)")
    parser.add_argument("--quiet", action="store_true", help="print nothing but failures")
    # One worker per processor by default: two workers measured 9.0 and 9.5 s against
    # 11.4 and 12.8 s for one process on the 2-core machine, second runs, medians of 3
    # and 4, when other work left about one processor idle (load about 1); at a load of
    # 2 they gained nothing (12.4 s against 11.8 s, median of 4). 2026-11-23, before
    # the scenes became one task each (paper_checks/scene.py); make bench prints both.
    parser.add_argument("--jobs", type=int_at_least(1), default=None,
                        help="worker processes that run the scenes and draw their figures "
                             "(default: one per processor; 1: all in this process)")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    args.parser, args.run = parser, _run
    return run_command(args)  # what goes wrong is said in one line, never a traceback


def _run(args: argparse.Namespace) -> int:
    try:
        return _check(args)
    except ValueError as error:  # past the options, no input of the user's is at fault
        raise RuntimeError(str(error)) from error


def _check(args: argparse.Namespace) -> int:
    out = Path(args.out)  # checked (and created) by its type, before any work
    from .report import write_report

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


def _exit(code: int) -> None:
    """Exit with ``code`` once the exit handlers have run (matplotlib's, numba's, ...),
    without the interpreter's teardown of every module and object, which took 0.55 to
    0.63 s after a run (0.32 s after the imports alone; 2026-11-23): the files are
    written and closed by then."""
    atexit._run_exitfuncs()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    # The command runs without the cyclic garbage collector, and so do the processes
    # it forks: its imports and the kernels' loading create objects that all stay, and
    # the collections kept looking through them (`bench_paper.py` times the start with
    # the collector on and off). The figures' and the compilers' reference cycles then
    # stay until the process ends: measured once by hand (2026-11-23, no benchmark),
    # 36 MB more at the peak with the kernels cached (363 against 327 MB), 75 MB more in
    # the largest process of a run that compiles them (421 against 347 MB).
    gc.disable()
    _exit(main())
