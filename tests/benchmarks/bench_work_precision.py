"""What accuracy costs: the work-precision points of the report, measured in this run.

RK4 (steps per period), the perturbation series (order) and scipy's DOP853 (rtol)
against their error in A_pp; DOP853 at rtol 1e-9 is the baseline of each row.

Then the study's own time (issue 12: `make paper` runs it), as the report runs it
against the study with DOP853 also at rtol 1e-11 as it ran before 2026-11-23, in turn,
median of STUDY_REPEATS, after a first run that derives and compiles the series' orders
(every later run finds them in ``compile_series``'s cache, or on the disk).
"""

from __future__ import annotations

from paper_checks.work_precision import work_precision

from ._timing import header, interleaved_medians, row

STUDY_REPEATS = 3
#: The DOP853 settings of the study before 2026-11-23.
DOP853_RTOL_BEFORE = (1e-3, 1e-5, 1e-7, 1e-9, 1e-11)


def _study_before() -> None:
    work_precision(truncation="paper", dop853_rtols=DOP853_RTOL_BEFORE)


def main() -> None:
    result = work_precision(truncation="paper")  # the study of make paper
    by_name = {m.name: m for m in result.methods}
    baseline = by_name["DOP853"].seconds[by_name["DOP853"].settings.index(1e-9)]
    header("work-precision: time per App at the reference points, DOP853 rtol 1e-9 as baseline")
    for method in result.methods:
        for setting, error, seconds in zip(method.settings, method.errors, method.seconds):
            row(f"{method.name} {method.setting.split(' (')[0]} = {setting:g}, error "
                f"{error:.2e} [s]", seconds, baseline, "s", higher_is_better=False)
    now, before = interleaved_medians(lambda: work_precision(truncation="paper"), _study_before,
                                      repeats=STUDY_REPEATS)
    header(f"the work-precision study, wall time, median of {STUDY_REPEATS}; baseline: "
           "DOP853 also at rtol 1e-11 (before 2026-11-23), same run")
    row("the study as the report runs it [s]", now, before, "s", higher_is_better=False)


if __name__ == "__main__":
    main()
