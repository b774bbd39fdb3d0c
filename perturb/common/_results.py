"""The contract every result object of the toolkit keeps.

A result is a dataclass made with ``@result``. It carries the model that made
it (``model``: parameters and effects, as data) and the settings; ``str`` gives
a one-line summary, followed by a table where the result is a table; ``repr``
is that one line, never an array; ``as_dict()`` is strict JSON (NaN and
infinity as ``null``, with ``"kind"`` naming the class), ``to_json(path)``
writes it, and ``load(path)`` reads any result file back into its object, so a
figure can be redrawn from a saved run without computing it again.
"""

from __future__ import annotations

import importlib
import json
import math
import types
import typing
from dataclasses import MISSING, dataclass, fields
from pathlib import Path

import numpy as np

from ._files import write_atomically
from ._json import jsonable, write_json
from ._provenance import provenance
from ._status import Status

__all__ = ["Result", "result", "load", "from_dict", "RESULT_CLASSES"]

#: Every result class by name, filled in by ``@result``; ``load`` looks here.
RESULT_CLASSES: dict[str, type] = {}
#: Packages whose modules define result classes (imported by ``load`` on demand; their
#: names are imported at first use, PEP 562, so ``load`` asks for them by name).
_PACKAGES = ("perturb", "numerics")


class Result:
    """Base of the result classes: summary, short repr, strict JSON and its way back.

    A result that is a table of lanes (points) names the field that counts them in
    ``LANES``; ``from_dict`` then checks that every other array field has as many rows,
    except those in ``NOT_PER_LANE``.
    """

    LANES = None  # the name of the field whose length is the number of lanes
    NOT_PER_LANE: tuple[str, ...] = ()
    #: Where a result read from a file came from (its ``"provenance"``); None for one
    #: computed in this process (its file gets this process's when written).
    provenance = None

    def summary(self) -> str:
        """One line: what the result holds and how long it took."""
        return type(self).__name__

    def table(self) -> str:
        """The rows of the result, where it is a table ("" otherwise)."""
        return ""

    def __str__(self) -> str:
        table = self.table()
        return self.summary() + ("\n" + table if table else "")

    def __repr__(self) -> str:
        name, line = type(self).__name__, self.summary()
        return f"<{line}>" if line.startswith(name) else f"<{name}: {line}>"

    def derived(self) -> dict:
        """Values computed from the fields that the JSON also shows (not read back)."""
        return {}

    def as_dict(self) -> dict:
        """Strict-JSON data: every field, the derived values, and ``"kind"``."""
        data = {"kind": type(self).__name__}
        data.update({f.name: jsonable(getattr(self, f.name)) for f in fields(self)})
        data.update(jsonable(self.derived()))
        return data

    def to_json(self, path: str | Path) -> None:
        """Write ``as_dict()`` to ``path`` (UTF-8, strict JSON), with the file's
        ``"provenance"``: versions, commit and when it was written."""
        write_json(path, _Written(self))  # as_dict() once: its lists are not walked again

    def csv_rows(self) -> list[dict]:
        """The result as rows of a table, one a lane (point), each a mapping from column
        name to value: the per-lane columns (a column of pairs as two columns ``_0``,
        ``_1``, a complex one as ``_real`` and ``_imag``), and the lane's own scalars
        (``pa_frac``, ``direction``, ...). A result that holds tables (a sweep's runs,
        a continuation's branches) stacks theirs, each row with the table's index.
        Per-lane lists (every extremum of a period) are left out. A ValueError says
        when the result is no table."""
        if self.LANES is not None:
            return _lane_rows(self)
        own = _own_scalars(self)  # the result's own numbers go on every row
        hints = typing.get_type_hints(type(self))
        for f in fields(self):
            parts = getattr(self, f.name)
            if not (_holds_results(hints.get(f.name)) or isinstance(parts, list) and parts
                    and all(isinstance(part, Result) for part in parts)):
                continue
            if not parts:  # an empty table: no rows (a census that found no attractor)
                return []
            if all(part.LANES for part in parts):
                index = f.name.removesuffix("es") if f.name.endswith("ches") else \
                    f.name.removesuffix("s")
                return [{**own, index: k, **{key: value for key, value in row.items()
                                             if value is not None or key not in own}}
                        for k, table in enumerate(parts) for row in table.csv_rows()]
            return [own | _scalars(part) for part in parts]  # a row each (attractors)
        rows = _column_rows(self)
        if rows:
            return rows
        raise ValueError(f"a {type(self).__name__} is not a table: it has no CSV form.")

    def to_csv(self, path: str | Path) -> None:
        """Write ``csv_rows()`` to ``path`` (UTF-8, a header of the glossary's names,
        units in the names; empty cells where a value could not be computed)."""
        write_atomically(path, _csv_text(self.csv_rows()))

    @classmethod
    def from_dict(cls, data: dict):
        """The object that ``as_dict`` described; derived keys are recomputed, not read."""
        hints = typing.get_type_hints(cls)
        missing = [f.name for f in fields(cls) if f.name not in data and _required(f)]
        if missing:
            raise ValueError(f"{cls.__name__} data lacks the key(s) {missing}.")
        values = {f.name: _decode(hints[f.name], data[f.name]) for f in fields(cls)
                  if f.name in data}
        _check_values(cls, values)
        return cls(**values)


def _scalars(part: Result) -> dict:
    """The numbers and words of a result that is one row (an attractor): its scalar
    fields and derived values, and its short arrays as numbered columns."""
    values = {f.name: getattr(part, f.name) for f in fields(part)} | part.derived()
    row = {}
    for key, value in values.items():
        if isinstance(value, (str, bool, int, float, complex, np.integer, np.floating)):
            row[key] = value
        elif isinstance(value, np.ndarray) and value.ndim == 1 and value.size <= 8:
            row |= {f"{key}_{k}": item for k, item in enumerate(value)}
    return _split_complex(row)


def _split_complex(row: dict) -> dict:
    out = {}
    for key, value in row.items():
        if isinstance(value, (complex, np.complexfloating)):
            out[f"{key}_real"], out[f"{key}_imag"] = value.real, value.imag
        else:
            out[key] = value
    return out


def _holds_results(hint) -> bool:
    """Whether a field's type is a list of results (``list[Attractor]``)."""
    args = typing.get_args(hint)
    return (typing.get_origin(hint) is list and len(args) == 1 and isinstance(args[0], type)
            and issubclass(args[0], Result))


def _own_scalars(result: Result) -> dict:
    """A result's own numbers and words (``pa_frac``, ``order``), for every row of the
    tables it holds; the model, settings and times are left out."""
    values = {f.name: getattr(result, f.name) for f in fields(result)}
    return {key: value for key, value in values.items()
            if isinstance(value, (str, bool, int, float, np.integer, np.floating))
            and key != "elapsed_s"}


def _column_rows(result: Result) -> list[dict]:
    """The rows of the longest set of equal-length 1-D arrays of a result (a height
    sweep's heights, a hysteresis loop's phases), its scalars beside; [] if none."""
    values = {f.name: getattr(result, f.name) for f in fields(result)}
    columns = {key: value for key, value in values.items()
               if isinstance(value, np.ndarray) and value.ndim == 1 and value.size > 1}
    if not columns:
        return []
    lengths = [value.size for value in columns.values()]
    n = max(set(lengths), key=lambda size: (lengths.count(size), size))
    scalars = {key: value for key, value in values.items()
               if isinstance(value, (str, bool, int, float, np.integer, np.floating))
               and key != "elapsed_s"}
    kept = {key: value for key, value in columns.items() if value.size == n}
    return [{**scalars, **{key: value[i] for key, value in kept.items()}} for i in range(n)]


def _lane_rows(table: Result) -> list[dict]:
    """``Result.csv_rows`` of a table of lanes."""
    n = len(getattr(table, table.LANES))
    scalars, columns = {}, {}
    values = {f.name: getattr(table, f.name) for f in fields(table)} | table.derived()
    for key in table.NOT_PER_LANE:  # not one value a lane, whatever its length
        values.pop(key, None)
    for key, value in values.items():
        if isinstance(value, (str, bool, int, float, np.integer, np.floating)):
            scalars[key] = value
        elif (isinstance(value, list) and len(value) == n
              and all(isinstance(v, str) for v in value)):
            columns[key] = value
        elif (isinstance(value, np.ndarray) and len(value) == n
              and (value.ndim == 1 or value.ndim == 2 and value.shape[1] <= _WIDEST)):
            parts = [(key, value)] if value.ndim == 1 else [
                (f"{key}_{k}", value[:, k]) for k in range(value.shape[1])]
            for name, column in parts:
                if np.iscomplexobj(column):
                    columns[f"{name}_real"], columns[f"{name}_imag"] = column.real, column.imag
                else:
                    columns[name] = column
    scalars.pop("elapsed_s", None)
    return [{**scalars, **{name: column[i] for name, column in columns.items()}}
            for i in range(n)]


#: A per-lane array of at most this many columns (the two multipliers) is a column each;
#: wider ones (a history of every step) are in the JSON only.
_WIDEST = 8


def _csv_text(rows: list[dict]) -> str:
    import csv
    import io

    names = list(dict.fromkeys(name for row in rows for name in row))
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(names)
    for row in rows:
        writer.writerow([_cell(row.get(name, "")) for name in names])
    return text.getvalue()


def _cell(value):
    if isinstance(value, (float, np.floating)) and not math.isfinite(value):
        return ""  # could not be computed
    value = jsonable(value)
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back the same float
    return value


class _Written:
    """A result as its file holds it: ``as_dict()`` and the file's provenance."""

    def __init__(self, result: Result):
        self.result = result

    def as_dict(self) -> dict:
        """The result's data, with where it was computed: a result read from a file keeps
        the provenance it was computed with; only ``written_utc`` is new."""
        now = provenance()
        origin = self.result.provenance
        return self.result.as_dict() | {
            "provenance": now if origin is None else origin | {"written_utc": now["written_utc"]}}


def _check_values(cls, values: dict) -> None:
    """Refuse values that no result of ``cls`` holds: a status that is no ``Status``, a
    negative App, a frequency that is not positive, lanes of different lengths."""
    name = cls.__name__
    for key, value in values.items():
        if not isinstance(value, np.ndarray):
            continue
        if key == "status" and value.size:  # [] reads back as floats
            codes = {int(s) for s in Status}
            if value.dtype.kind not in "iu" or not set(np.unique(value).tolist()) <= codes:
                raise ValueError(f"{name}: `status` must hold the integer codes {sorted(codes)}"
                                 f" of common.Status, got {_sample(value)}.")
        if key.endswith("app_m") or key == "frequency_hz":
            if value.dtype.kind not in "iuf":
                raise ValueError(f"{name}: `{key}` must hold numbers, got {_sample(value)}.")
            bad = np.isfinite(value) & ((value < 0) if key.endswith("app_m") else (value <= 0))
            if bad.any():
                limit = ">= 0" if key.endswith("app_m") else "> 0"
                raise ValueError(f"{name}: `{key}` must be {limit}, got {_sample(value[bad])}.")
    if cls.LANES is None or not isinstance(values.get(cls.LANES), np.ndarray):
        return
    lanes = len(values[cls.LANES])
    for key, value in values.items():
        if key in cls.NOT_PER_LANE or not isinstance(value, (np.ndarray, list)):
            continue
        if np.ndim(value) if isinstance(value, np.ndarray) else True:
            if len(value) != lanes:
                raise ValueError(f"{name}: `{key}` has {len(value)} rows where "
                                 f"`{cls.LANES}` has {lanes} lanes.")


def _sample(value: np.ndarray) -> str:
    """The first entries of ``value``, for a message."""
    shown = np.ravel(value)[:3].tolist()
    return f"{shown}{' ...' if np.size(value) > 3 else ''}"


def _required(f) -> bool:
    return f.default is MISSING and f.default_factory is MISSING


def result(cls):
    """Make ``cls`` a result dataclass (no generated repr or eq) and register it."""
    cls = dataclass(repr=False, eq=False, kw_only=True)(cls)
    RESULT_CLASSES[cls.__name__] = cls
    return cls


def _denull(value):
    if value is None:
        return math.nan
    if isinstance(value, list):
        return [_denull(item) for item in value]
    return value


def _array(value) -> np.ndarray | None:
    if value is None:
        return None
    if isinstance(value, dict) and set(value) == {"real", "imag"}:
        return _array(value["real"]) + 1j * _array(value["imag"])
    return np.asarray(_denull(value))


def _decode(hint, value):
    """``value`` read from JSON, turned back into the type that ``hint`` names."""
    if value is None:
        return math.nan if hint is float else None
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin in (typing.Union, types.UnionType):
        options = [a for a in args if a is not type(None)]
        return _decode(options[0], value) if len(options) == 1 else value
    if hint is np.ndarray:
        return _array(value)
    if isinstance(hint, type) and issubclass(hint, Result):
        return hint.from_dict(value)
    if origin is list and args:
        return [_decode(args[0], item) for item in value]
    if origin is tuple:
        return tuple(value)
    if hint is float:
        return float(value)
    if hint is complex:
        return complex(value["real"], value["imag"])
    return value


def from_dict(data: dict):
    """The result object that ``data`` (an ``as_dict()``) describes."""
    kind = data.get("kind") if isinstance(data, dict) else None
    if kind not in RESULT_CLASSES:
        _import_result_classes(kind)
    if kind not in RESULT_CLASSES:
        raise ValueError(
            f"not a result of this toolkit: `kind` is {kind!r}; known kinds: "
            f"{sorted(RESULT_CLASSES)}."
        )
    found = RESULT_CLASSES[kind].from_dict(data)
    if isinstance(data.get("provenance"), dict):  # a file's: where it comes from
        found.provenance = data["provenance"]
    return found


def _import_result_classes(kind) -> None:
    """Import the class named ``kind`` (it registers itself), else every public name."""
    for package in _PACKAGES:
        module = importlib.import_module(package)
        if isinstance(kind, str) and kind in module.__all__:
            getattr(module, kind)
    if kind not in RESULT_CLASSES:  # a nested result's kind, or none of the toolkit's
        for package in _PACKAGES:
            module = importlib.import_module(package)
            for name in module.__all__:
                getattr(module, name)


def load(path: str | Path):
    """Read a result file written by ``to_json`` or ``--json`` back into its object.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from numerics import simulate
    >>> run = simulate([1000.0], 0.1, periods=20)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     run.to_json(f"{folder}/run.json")
    ...     back = load(f"{folder}/run.json")
    >>> type(back).__name__, bool(np.all(back.app_m == run.app_m))
    ('Simulation', True)
    """
    with open(path, encoding="utf-8") as handle:
        try:
            data = json.load(handle)
        except json.JSONDecodeError as error:
            raise ValueError(f"{str(path)!r} is not JSON: {error}") from None
        except UnicodeDecodeError:
            raise ValueError(f"{str(path)!r} is not JSON: not UTF-8 text.") from None
        except RecursionError:
            raise ValueError(f"{str(path)!r} is not a result: nested too deep.") from None
    try:
        return from_dict(data)
    except (ValueError, TypeError, KeyError, IndexError, AttributeError) as error:
        raise ValueError(f"{str(path)!r} is not a result of this toolkit: {error}") from None
    except RecursionError:
        raise ValueError(f"{str(path)!r} is not a result: nested too deep.") from None
