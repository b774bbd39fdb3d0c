"""One JSON writer for every command of every package: strict, UTF-8, indented.

Strict JSON has no NaN or infinity; ``jsonable`` writes them as ``null`` (a
value that could not be computed, or a point that did not settle). Reading a
file back, ``null`` in a numeric array becomes NaN again (``common.load``).
"""

from __future__ import annotations

import json
import math
from dataclasses import fields, is_dataclass
from enum import Enum
from pathlib import Path

import numpy as np

__all__ = ["jsonable", "write_json", "dumps"]


def _number(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _array(array: np.ndarray):
    if np.iscomplexobj(array):
        # A complex array is stored as its two real parts (Floquet multipliers).
        return {"real": _array(array.real), "imag": _array(array.imag)}
    if array.dtype.kind == "f":
        return [_array(row) for row in array] if array.ndim > 1 else [
            _number(float(x)) for x in array]
    return jsonable(array.tolist())


def jsonable(value):
    """``value`` as plain JSON types: NaN and infinity become None, arrays lists.

    Examples
    --------
    >>> jsonable({"app_m": np.array([1e-7, np.nan]), "period": np.int64(2)})
    {'app_m': [1e-07, None], 'period': 2}
    """
    if hasattr(value, "as_dict"):
        return value.as_dict()
    if isinstance(value, Enum):
        return value.value
    if isinstance(value, np.ndarray):
        return _array(value)
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return _number(float(value))
    if isinstance(value, (complex, np.complexfloating)):
        return {"real": _number(value.real), "imag": _number(value.imag)}
    if isinstance(value, dict):
        return {str(key): jsonable(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(item) for item in value]
    if is_dataclass(value):
        return {f.name: jsonable(getattr(value, f.name)) for f in fields(value)}
    return value


def dumps(payload) -> str:
    """Strict JSON text (``allow_nan=False``) of ``payload``."""
    return json.dumps(jsonable(payload), indent=1, allow_nan=False, ensure_ascii=False)


def write_json(path: str | Path | None, payload) -> None:
    """Write ``payload`` to ``path`` as strict, UTF-8 JSON; nothing when ``path`` is None."""
    if path:
        Path(path).write_text(dumps(payload) + "\n", encoding="utf-8")
