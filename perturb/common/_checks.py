"""Checks of inputs where they enter, shared by all three packages.

Each check returns the value in the form the toolkit uses, or raises a
ValueError (a KeyError for a lookup) that names the argument and its value, so
that no bare ZeroDivisionError, IndexError or StopIteration reaches a user.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping

import numpy as np

__all__ = [
    "check_real",
    "check_positive",
    "check_int",
    "check_choice",
    "check_pair",
    "check_keys",
    "lane_array",
    "finite_array",
    "lookup",
]


def check_real(name: str, value) -> float:
    """One real, finite number (not bool, str, or a sequence)."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, (bool, np.bool_, str)) or not isinstance(value, numbers.Real):
        raise ValueError(f"`{name}` must be one real number, got {value!r}.")
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"`{name}` must be finite, got {value!r}.")
    return number


def check_positive(name: str, value, *, allow_zero: bool = False) -> float:
    """One finite number > 0 (>= 0 with ``allow_zero``).

    Examples
    --------
    >>> check_positive("tol", 1e-6)
    1e-06
    >>> check_positive("pa_frac", [0.1, 0.2])
    Traceback (most recent call last):
    ...
    ValueError: `pa_frac` must be one real number, got [0.1, 0.2].
    """
    number = check_real(name, value)
    if number < 0 or (number == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"`{name}` must be {bound}, got {value!r}.")
    return number


def check_int(name: str, value, minimum: int = 1, maximum: int | None = None,
              why: str = "") -> int:
    """An integer in [minimum, maximum] (a float with an integer value is accepted);
    ``why`` says in the error why the maximum is there."""
    ok = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if not ok or not math.isfinite(value) or int(value) != value or value < minimum:
        raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}.")
    if maximum is not None and value > maximum:
        reason = f": {why}" if why else ""
        raise ValueError(f"`{name}` must be an integer <= {maximum}, got {value!r}{reason}.")
    return int(value)


def check_choice(name: str, value, choices: Iterable):
    """One of ``choices``; the error lists them."""
    choices = tuple(choices)
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"`{name}` must be one of {choices}, got {value!r}.")
    return value


def check_pair(name: str, value, *, positive: bool = False) -> tuple[float, float]:
    """Two finite numbers (lo, hi) with lo < hi (and lo > 0 with ``positive``)."""
    try:
        lo, hi = (check_real(name, x) for x in value)
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be two numbers (lo, hi), got {value!r}.") from None
    if not lo < hi or (positive and lo <= 0):
        bound = "0 < lo < hi" if positive else "lo < hi"
        raise ValueError(f"`{name}` must be (lo, hi) with {bound}, got {value!r}.")
    return lo, hi


def check_keys(name: str, value, required: Iterable[str]) -> Mapping:
    """A mapping that has every key of ``required`` (and no others)."""
    required = tuple(required)
    if not isinstance(value, Mapping):
        raise ValueError(f"`{name}` must be a mapping with keys {required}, got {value!r}.")
    missing = [key for key in required if key not in value]
    unknown = [key for key in value if key not in required]
    if missing or unknown:
        raise ValueError(f"`{name}` must have exactly the keys {required}; missing "
                         f"{missing}, unknown {unknown}.")
    return value


def lane_array(name: str, value, lanes: int | None = None, *, positive: bool = False):
    """A float64 array over lanes; finite, >= 0 (or > 0 with ``positive``)."""
    if _not_numbers(value):
        raise ValueError(f"`{name}` must be real numbers, got {value!r}.")
    try:
        array = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be real numbers, got {value!r}.") from None
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


def _not_numbers(value) -> bool:
    """Text or booleans, which numpy would turn into numbers without a word."""
    kind = np.asarray(value).dtype.kind
    if kind in "fiuc":
        return False
    if kind != "O":
        return True  # str, bytes, bool
    return any(isinstance(item, (str, bytes, bool, np.bool_))
               for item in np.ravel(np.asarray(value, dtype=object)))


def finite_array(name: str, value):
    """A finite float64 array of at most one dimension."""
    try:
        array = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be real numbers, got {value!r}.") from None
    if array.ndim != 1 or array.size == 0 or not np.isfinite(array).all():
        raise ValueError(f"`{name}` must be finite, non-empty and at most 1-dimensional, got "
                         f"{value!r}.")
    return array


def lookup(name: str, items: Iterable, match, describe) -> object:
    """The first item that ``match`` accepts, or a KeyError listing what there is.

    ``describe(item)`` names an item in the error message.
    """
    items = list(items)
    for item in items:
        if match(item):
            return item
    raise KeyError(f"no {name}; available: {[describe(item) for item in items]}")
