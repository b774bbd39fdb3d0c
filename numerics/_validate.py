"""What a simulation can record; the input checks themselves live in ``common``."""

from __future__ import annotations

from common import check_choice

__all__ = ["RECORDABLE", "check_record"]

#: The observables a run can record, and what each one stores.
RECORDABLE = {
    "final": "state (y, v) at the end of the run",
    "minmax": "min and max of y over the recorded periods",
    "extrema": "every local extremum of y over the recorded periods",
    "history": "y and v after every step of the recorded periods",
}


def check_record(record) -> tuple[str, ...]:
    """The names in ``record`` (one name or a sequence), each one of RECORDABLE."""
    names = (record,) if isinstance(record, str) else tuple(record)
    for name in names:
        check_choice("record", name, sorted(RECORDABLE))
    return names
