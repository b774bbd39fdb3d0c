"""Checks of the simulator's inputs, where they enter; each error names the argument."""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["lane_array", "positive_int", "RECORDABLE", "check_record"]

#: The observables a run can record, and what each one stores.
RECORDABLE = {
    "final": "state (y, v) at the end of the run",
    "minmax": "min and max of y over the recorded periods",
    "extrema": "every local extremum of y over the recorded periods",
    "history": "y and v after every step of the recorded periods",
}


def lane_array(name: str, value, lanes: int | None = None, *, positive: bool = False):
    """A float64 array over lanes; finite, >= 0 (or > 0 with ``positive``)."""
    array = np.atleast_1d(np.asarray(value, dtype=float))
    if array.ndim != 1 or array.size == 0:
        raise ValueError(
            f"`{name}` must be a scalar or a non-empty 1-dimensional array, got shape "
            f"{array.shape}.")
    bad = ~np.isfinite(array) | (array <= 0 if positive else array < 0)
    if bad.any():
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"`{name}` must be finite and {bound}, got {float(array[bad][0])!r}.")
    if lanes is not None and array.shape[0] not in (1, lanes):
        raise ValueError(f"`{name}` has {array.shape[0]} lanes, expected 1 or {lanes}.")
    return array


def finite_array(name: str, value):
    array = np.atleast_1d(np.asarray(value, dtype=float))
    if array.ndim != 1 or not np.isfinite(array).all():
        raise ValueError(f"`{name}` must be finite and at most 1-dimensional, got {value!r}.")
    return array


def positive_int(name: str, value, minimum: int = 1) -> int:
    """An integer >= minimum, or a ValueError naming the argument."""
    number = value if isinstance(value, numbers.Real) and not isinstance(value, bool) else None
    if number is None or not math.isfinite(number) or int(number) != number or number < minimum:
        raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}.")
    return int(number)


def check_record(record) -> tuple[str, ...]:
    names = (record,) if isinstance(record, str) else tuple(record)
    unknown = [name for name in names if name not in RECORDABLE]
    if unknown:
        raise ValueError(
            f"`record` has unknown observable {unknown[0]!r}; valid: {sorted(RECORDABLE)}."
        )
    return names
