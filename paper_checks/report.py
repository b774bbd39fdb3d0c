"""The report: report.md (claims, figures, the printed series, accuracy and time) and
report.json."""

from __future__ import annotations

import json
import time
from pathlib import Path

from numerics.cli._info import format_info
from numerics.comparison.table import format_comparison
from perturb import text_report
from perturb.common import processors, provenance, write_atomically, write_json

from .claims import Claim
from .figures import draw_figures
from .registry import run_claims
from .scene import PaperScene, worker_pool

__all__ = ["write_report"]


def _format(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list) and len(value) > 12:
        return f"[{', '.join(_format(v) for v in value[:12])}, ...] ({len(value)} values)"
    if isinstance(value, list):
        return "[" + ", ".join(_format(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_format(v)}" for k, v in value.items()) + "}"
    return str(value)


def _claims_section(claims: list[Claim]) -> list[str]:
    passed = sum(c.passed for c in claims)
    lines = [f"## Claims: {passed} of {len(claims)} hold", "",
             "| # | claim (the paper's words) | holds | measured |", "|---|---|---|---|"]
    for i, c in enumerate(claims, 1):
        measured = "<br>".join(f"{k}: {_format(v)}" for k, v in c.measured.items())
        verdict = "yes" if c.passed else "**NO**"
        lines.append(f"| {i} | {c.statement} | {verdict} | {measured} |")
    notes = [c for c in claims if c.beyond or c.detail]
    if notes:
        lines += ["", "### Notes and findings beyond the paper", ""]
        lines += [f"- **{c.id}**: {c.detail}" for c in claims if c.detail]
        lines += [f"- **{c.id}**, beyond the paper: {c.beyond}" for c in claims if c.beyond]
    return lines


def _work_section(work) -> list[str]:
    lines = ["## What accuracy costs", "",
             "Largest relative error of A_pp over a few points against wall time "
             "(see `paper_checks/work_precision.py` for the points and references).", ""]
    for method in work.methods:
        lines += [f"**{method.name}** ({method.setting})", "",
                  "| setting | error | time [s] |", "|---|---|---|"]
        lines += [f"| {s:g} | {e:.3g} | {t:.3g} |"
                  for s, e, t in zip(method.settings, method.errors, method.seconds)]
        if "derive_seconds" in method.extra:
            lines += ["", _derive_line(method)]
        lines.append("")
    return lines + ["![work-precision](work-precision.png)", ""]


def _derive_line(method) -> str:
    """The time each order's formulas took at their first call: derived and compiled, or
    imported from the cache on disk (older reports do not say which)."""
    cached = method.extra.get("derive_cached", [None] * len(method.settings))
    how = {True: " (from the disk)", False: " (derived)", None: ""}
    return "Time to get each order's formulas (first call): " + ", ".join(
        f"N={n}: {t:.3g} s{how[c]}"
        for n, t, c in zip(method.settings, method.extra["derive_seconds"], cached))


def _runs_section(out: Path, this_run: dict) -> list[str]:
    """This run's wall time, and those of earlier runs into the same folder."""
    history_file = out / "runs.json"
    history = (json.loads(history_file.read_text(encoding="utf-8")) if history_file.exists()
               else [])
    history.append(this_run)
    write_json(history_file, history[-10:])
    lines = ["## Wall time of `python -m paper_checks` runs into this folder", "",
             "| run | wall time [s] | kernels compiled in the run | quick |", "|---|---|---|---|"]
    lines += [f"| {i} | {r['wall_s']:.1f} | {r['kernels_compiled']} | {r['quick']} |"
              for i, r in enumerate(history[-10:], 1)]
    return lines + ["", "A run that compiles kernels is a cold start (a fresh clone or an "
                    "empty cache); the others load them from the cache. "
                    "`make bench` measures both from an empty cache (`bench_paper.py`).", ""]


def write_report(out: Path, quick: bool = False, started: float | None = None,
                 kernels_cached_before: int = 0, kernel_files=None,
                 jobs: int | None = None) -> dict:
    """Check every claim, draw every figure, and write report.md and report.json.

    ``started`` is the perf_counter() at process start, so that the wall time
    includes the imports; ``kernel_files`` lists the compiled kernels after the run.
    The scenes run in ``jobs`` worker processes (default: one per processor; 1 runs
    them here, one after the other).
    """
    start = time.perf_counter() if started is None else started
    (out / "report.md").unlink(missing_ok=True)  # a run stopped before its end leaves none
    scene = PaperScene(quick=quick, out=out)
    with worker_pool(processors() if jobs is None else jobs) as pool:
        if pool is not None:
            scene.start(pool)
        # Printed while the workers run: 0.15 s of sympy's printing (its first use
        # here) that would otherwise follow the last of them.
        series = text_report(scene.series)
        # Before the claims: with workers, its parts end before the last scenes the claims
        # wait for, and its figure is drawn here meanwhile.
        work = scene.work_precision
        claims = run_claims(scene)
        figures = draw_figures(scene)
        scene.check_background()
    elapsed = time.perf_counter() - start
    lines = ["# The paper, checked and redrawn", "",
             "*Analysis of the primary and superharmonic contact resonances – Part 1*, "
             f"checked by `python -m paper_checks{' --quick' if quick else ''}`.", "",
             "## The model (Eq. 2.6 derived from Eq. 2.1–2.4)", "", "```",
             format_info(scene.info), "```", ""]
    lines += _claims_section(claims) + [""]
    lines += ["## Figures", ""] + [f"### {caption}\n\n![{caption}]({file})\n"
                                   for caption, file in figures.items()]
    lines += ["## Analytic against numerical", "",
              "Series of each order against the exact backbone and against RK4 steady states "
              "of the Eq. 2.6 model and of the full model (`python -m numerics compare`).", "",
              "```", format_comparison(scene.comparison), "```", ""]
    lines += ["## The perturbation series to ε⁴ (Eq. 2.7–2.10, A.1, A.2)", "", "```",
              series, "```", ""]
    lines += _work_section(work)
    lines += ["## Time of each computation", "", "| computation | settings | time [s] |",
              "|---|---|---|"]
    lines += [f"| {name} | {t['settings']} | {t['seconds']:.3g} |"
              for name, t in scene.timings.items()]
    compiled = len(kernel_files()) - kernels_cached_before if kernel_files else 0
    this_run = {"wall_s": elapsed, "kernels_compiled": compiled, "quick": quick}
    lines += [""] + _runs_section(out, this_run)
    origin = provenance()
    lines += ["", f"Toolkit {origin['version']}"
              + (f" (commit {origin['commit']})" if origin["commit"] else "")
              + f", Python {origin['python']}, "
              + ", ".join(f"{name} {v}" for name, v in origin["libraries"].items())
              + f"; written {origin['written_utc']}."]
    payload = {"claims": [c.as_dict() for c in claims], "elapsed_s": elapsed,
               "timings": scene.timings, "work_precision": work.as_dict(),
               "figures": figures, "quick": quick, "run": this_run, "provenance": origin}
    write_json(out / "report.json", payload)
    # The report last, whole or not at all (the old one was removed at the start).
    write_atomically(out / "report.md", "\n".join(lines) + "\n")
    return payload
