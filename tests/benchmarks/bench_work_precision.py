"""What accuracy costs: the work-precision points of the report, measured in this run.

RK4 (steps per period), the perturbation series (order) and scipy's DOP853 (rtol)
against their error in A_pp; DOP853 at rtol 1e-9 is the baseline of each row.
"""

from __future__ import annotations

from paper_checks._work_precision import work_precision

from ._timing import header, row


def main() -> None:
    result = work_precision()
    by_name = {m.name: m for m in result.methods}
    baseline = by_name["DOP853"].seconds[by_name["DOP853"].settings.index(1e-9)]
    header("work-precision: time per App at the reference points, DOP853 rtol 1e-9 as baseline")
    for method in result.methods:
        for setting, error, seconds in zip(method.settings, method.errors, method.seconds):
            row(f"{method.name} {method.setting.split(' (')[0]} = {setting:g}, error "
                f"{error:.2e} [s]", seconds, baseline, "s", higher_is_better=False)


if __name__ == "__main__":
    main()
