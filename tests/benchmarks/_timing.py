"""Timing helpers shared by the benchmarks: medians of repeats, and a table row."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

__all__ = ["median_time", "interleaved_medians", "row", "header", "RECORD"]

#: Every header and row printed in this process, in order: what ``make bench`` writes
#: for the docs site's benchmark page (``python -m tests.benchmarks --record FILE``).
RECORD: list[dict] = []


def median_time(function: Callable[[], object], repeats: int = 5) -> float:
    """Median wall time of ``function()`` over ``repeats`` calls [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def interleaved_medians(first: Callable[[], object], second: Callable[[], object],
                        repeats: int = 7) -> tuple[float, float]:
    """Median wall times of two functions run in turn, so that a drift in the machine's
    load falls on both alike (an A/B pair on a shared machine)."""
    times: tuple[list[float], list[float]] = ([], [])
    for _ in range(repeats):
        for function, spent in zip((first, second), times):
            start = time.perf_counter()
            function()
            spent.append(time.perf_counter() - start)
    return statistics.median(times[0]), statistics.median(times[1])


def header(title: str) -> None:
    RECORD.append({"section": title, "rows": []})
    print(f"\n## {title}")
    print(f"{'figure':<52} {'value':>14} {'baseline':>14} {'ratio':>9}")


def row(name: str, value: float, baseline: float | None = None, unit: str = "",
        higher_is_better: bool = True, ratio: bool = True) -> None:
    """One line: figure, its baseline from the same run, and the ratio (x better).

    ``ratio=False`` prints the baseline without a ratio, for figures whose ratio
    means nothing (an error at rounding level against one of order 1).
    """
    if not RECORD:
        RECORD.append({"section": "", "rows": []})
    entry = {"figure": name, "value": value, "baseline": baseline, "unit": unit,
             "ratio": None}
    RECORD[-1]["rows"].append(entry)
    if baseline is None:
        print(f"{name:<52} {value:>11.4g} {unit:<2}")
        return
    if not ratio:
        print(f"{name:<52} {value:>11.4g} {unit:<2} {baseline:>11.4g} {unit:<2} {'-':>8} ")
        return
    ratio = value / baseline if higher_is_better else baseline / value
    entry["ratio"] = ratio
    print(f"{name:<52} {value:>11.4g} {unit:<2} {baseline:>11.4g} {unit:<2} {ratio:>8.1f}x")
