"""One JSON writer for every command of every package: strict, UTF-8, one key a line.

Strict JSON has no NaN or infinity; ``jsonable`` writes them as ``null`` (a
value that could not be computed, or a point that did not settle). Reading a
file back, ``null`` in a numeric array becomes NaN again (``common.load``).

The top level has one key per line, and each value is written on its line by the
json module's C encoder: an ``indent`` would send the whole file through its
pure-Python encoder, some 3x slower on a 3 MB sweep (``tests/test_json.py``).
"""

from __future__ import annotations

import contextvars
import json
import math
import sys
from dataclasses import fields, is_dataclass
from enum import Enum
from pathlib import Path

import numpy as np

from ._files import write_atomically

__all__ = ["jsonable", "write_json", "dumps", "STDOUT", "JSON_STDOUT"]

#: The path that names standard output (``--json -``).
STDOUT = "-"
#: Where JSON for ``STDOUT`` goes: the command's own stdout, kept by ``run_command``
#: while the command's other prints go to stderr (so that stdout is JSON alone).
JSON_STDOUT: contextvars.ContextVar = contextvars.ContextVar("json_stdout", default=None)


def _number(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _array(array: np.ndarray):
    if np.iscomplexobj(array):
        # A complex array is stored as its two real parts (Floquet multipliers).
        return {"real": _array(array.real), "imag": _array(array.imag)}
    if array.dtype.kind == "f":
        if array.ndim == 1:  # most arrays are short: Python's floats are quicker here
            values = array.tolist()
            if all(map(math.isfinite, values)):
                return values
            return [x if math.isfinite(x) else None for x in values]
        finite = np.isfinite(array)
        if finite.all():
            return array.tolist()
        values = array.astype(object)
        values[~finite] = None
        return values.tolist()
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


_ENCODER = json.JSONEncoder(allow_nan=False, ensure_ascii=False)


def dumps(payload) -> str:
    """Strict JSON text (``allow_nan=False``) of ``payload``: a mapping with one key a
    line, each value on its line.

    Examples
    --------
    >>> print(dumps({"kind": "Example", "app_m": np.array([1e-7, np.nan])}))
    {
     "kind": "Example",
     "app_m": [1e-07, null]
    }
    """
    data = jsonable(payload)
    if not isinstance(data, dict) or not data:
        return _ENCODER.encode(data)
    lines = (f" {_ENCODER.encode(key)}: {_ENCODER.encode(value)}" for key, value in data.items())
    return "{\n" + ",\n".join(lines) + "\n}"


def write_json(path: str | Path | None, payload) -> None:
    """Write ``payload`` to ``path`` as strict, UTF-8 JSON, whole or not at all
    (``write_atomically``); to standard output when ``path`` is "-" (``STDOUT``); nothing
    when ``path`` is None."""
    if path is not None and str(path) == STDOUT:
        stream = JSON_STDOUT.get() or sys.stdout
        stream.write(dumps(payload) + "\n")
        stream.flush()
    elif path:
        write_atomically(path, dumps(payload) + "\n")
