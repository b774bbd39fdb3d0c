"""`python -m paper_checks [--quick] [--out DIR]`: check the paper, write the report."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from numerics._info import format_info, model_info

from ._claims import run_claims


def write_report(out: Path, quick: bool) -> int:
    start = time.perf_counter()
    claims = run_claims(quick=quick)
    elapsed = time.perf_counter() - start
    out.mkdir(parents=True, exist_ok=True)
    lines = ["# The paper, checked", "", "## The model", "", "```", format_info(model_info()),
             "```", "", "## Claims", "", "| claim | passed | measured |", "|---|---|---|"]
    lines += [f"| {c.statement} | {'yes' if c.passed else '**no**'} | "
              f"{', '.join(f'{k}={v:.6g}' for k, v in c.measured.items())} |" for c in claims]
    lines += ["", f"Elapsed: {elapsed:.2f} s"]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    payload = {"claims": [c.as_dict() for c in claims], "elapsed_s": elapsed}
    (out / "report.json").write_text(json.dumps(payload, indent=2) + "\n")
    for claim in claims:
        print(f"[{'pass' if claim.passed else 'FAIL'}] {claim.id}: {claim.statement}")
    print(f"report: {out / 'report.md'}")
    return 0 if all(c.passed for c in claims) else 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m paper_checks", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="coarser grids (for tests)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    args = parser.parse_args(argv)
    return write_report(Path(args.out), args.quick)


if __name__ == "__main__":
    sys.exit(main())
