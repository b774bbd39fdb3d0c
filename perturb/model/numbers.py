"""The numbers of Eq. 2.6 at a parameter set: derived by sympy once, then read from disk.

``Eq26`` (``eq26.py``) derives the coefficients of Eq. 2.6 from the model's
forces; at a parameter set their values are one small record, ``Eq26Numbers``,
which is all that most commands need (y0, omega0, c, eps h, ...). It is written
to the cache (``cache.py``) the first time a parameter set is seen, so that a
later process reads eight floats instead of importing sympy and deriving them.
"""

from __future__ import annotations

import hashlib
import json
import math
import warnings
from dataclasses import asdict, dataclass, fields
from functools import lru_cache
from pathlib import Path

from ..cache import MODEL_SOURCES, CacheWarning, cache_key, usable_cache_dir, write_atomically
from .parameters import PAPER, ContactParameters

__all__ = ["Eq26Numbers", "eq26_numbers", "numbers_path"]

#: The files whose text shapes the numbers (a change to one derives them again).
_SOURCES = (*MODEL_SOURCES, Path(__file__).with_name("eq26.py"), Path(__file__))


@dataclass(frozen=True)
class Eq26Numbers:
    """The numbers of Eq. 2.6 at one parameter set, in SI units (names: the glossary).

    Attributes
    ----------
    y0_m : float
        Static deflection y0, where the spring carries the weight [m].
    f_n0_hz : float
        Natural frequency of the linearised system, omega0 / (2 pi) [Hz].
    omega0_rad_s : float
        omega0 [rad/s].
    Q_n : float
        Weight Q = M g [N].
    c_per_s : float
        c, half the linear damping coefficient over M [1/s].
    h_per_m_s2 : float
        eps h, the quadratic stiffness over M [1/(m s^2)].
    damping_ratio : float
        c / omega0.
    G_per_P_a : float
        G / P_a = 1 / M [1/kg].
    """

    y0_m: float
    f_n0_hz: float
    omega0_rad_s: float
    Q_n: float
    c_per_s: float
    h_per_m_s2: float
    damping_ratio: float
    G_per_P_a: float

    @property
    def fastest_rate_per_s(self) -> float:
        """The largest |eigenvalue| of the linearised contact, u'' + 2c u' + omega0^2 u:
        omega0 when underdamped, c + sqrt(c^2 - omega0^2) when overdamped [1/s]. A
        step resolves the contact where this rate times dt is small."""
        c, omega0 = self.c_per_s, self.omega0_rad_s
        return max(omega0, c + math.sqrt(max(c * c - omega0 * omega0, 0.0)))

    def as_dict(self) -> dict[str, float]:
        """The eight numbers by name, in the order of the fields."""
        return asdict(self)


def eq26_numbers(parameters: ContactParameters = PAPER) -> Eq26Numbers:
    """The numbers of Eq. 2.6 at ``parameters``: from the cache on disk, or derived by
    ``Eq26`` (sympy) and written there; once per parameter set and process.

    Examples
    --------
    >>> numbers = eq26_numbers()
    >>> round(numbers.f_n0_hz, 2), round(numbers.y0_m * 1e9, 1)
    (1485.59, 225.2)
    >>> list(numbers.as_dict())[:3]
    ['y0_m', 'f_n0_hz', 'omega0_rad_s']
    """
    if not isinstance(parameters, ContactParameters):
        raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
    return _numbers(parameters)


def numbers_path(parameters: ContactParameters) -> Path:
    """The cache file of the numbers at ``parameters``."""
    return usable_cache_dir() / f"numbers_{cache_key(parameters, _SOURCES)}.json"


@lru_cache(maxsize=128)
def _numbers(parameters: ContactParameters) -> Eq26Numbers:
    path = numbers_path(parameters)
    cached = _read(path, parameters)
    if cached is not None:
        return cached
    from .eq26 import derive_numbers

    numbers = derive_numbers(parameters)
    values = numbers.as_dict()
    positive = ("y0_m", "f_n0_hz", "omega0_rad_s")
    off = ", ".join(f"{k} = {v!r}" for k, v in values.items()
                    if not math.isfinite(v) or (k in positive and v <= 0))
    if off:
        raise ValueError(f"`parameters` give no finite equilibrium in contact ({off}; "
                         f"y0 solves S c_n y0^m2 = M g): {parameters}")
    _write(path, parameters, numbers)
    return numbers


def _read(path: Path, parameters: ContactParameters) -> Eq26Numbers | None:
    """The numbers stored at ``path`` for ``parameters``, or None when the file is
    missing, unreadable, truncated, edited (its checksum does not match), or holds
    anything else than eight finite floats for exactly these parameters (it is then
    derived and written again)."""
    try:
        record = json.loads(path.read_text())
        numbers = record["numbers"]
        names = [f.name for f in fields(Eq26Numbers)]
        if record["sha256"] != _checksum(record["parameters"], numbers):
            return None
        if record["parameters"] != parameters.as_dict() or list(numbers) != names:
            return None
        if not all(type(x) is float and math.isfinite(x) for x in numbers.values()):
            return None
        return Eq26Numbers(**numbers)
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError):
        return None


def _checksum(parameters: dict, numbers: dict) -> str:
    """SHA-256 of the record's data in a canonical text (floats by their shortest repr,
    which reads back to the same bits)."""
    text = json.dumps({"parameters": parameters, "numbers": numbers}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _write(path: Path, parameters: ContactParameters, numbers: Eq26Numbers) -> None:
    data = {"parameters": parameters.as_dict(), "numbers": numbers.as_dict()}
    record = {**data, "sha256": _checksum(**data)}
    try:
        write_atomically(path, json.dumps(record, indent=1) + "\n")
    except OSError as error:  # a full disk: the numbers are still right, only not kept
        warnings.warn(f"could not write {str(path)!r}: {error}", CacheWarning, stacklevel=4)
