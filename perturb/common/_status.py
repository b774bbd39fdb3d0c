"""One status per lane: an integer with named values, as scipy's ``OdeResult.status``.

Every per-lane result of the toolkit (a simulated lane, a steady state, a sweep
point, a lane of the attractor census) carries ``status`` and ``message``;
``settled``, ``failed`` and the like are derived from the status.
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["Status"]


class Status(IntEnum):
    """What became of a lane.

    Examples
    --------
    >>> Status(0).name, Status.FAILED.value
    ('SUCCESS', -1)
    >>> Status.NOT_SETTLED.describe()
    'not settled: the stroboscopic state did not repeat within the cap'
    """

    #: The state became non-finite or diverged (|y| beyond the divergence limit).
    FAILED = -1
    #: The lane did what was asked: a simulation ran to its end; a steady state settled.
    SUCCESS = 0
    #: Ran to the cap without its stroboscopic state repeating within the tolerance.
    NOT_SETTLED = 1
    #: Settled, but its estimated discretisation error exceeds the tolerance.
    UNDER_RESOLVED = 2

    def describe(self) -> str:
        return _DESCRIPTIONS[self]


_DESCRIPTIONS = {
    Status.FAILED: "failed: the state became non-finite or diverged",
    Status.SUCCESS: "success: ran to the end, or settled within the tolerance",
    Status.NOT_SETTLED: "not settled: the stroboscopic state did not repeat within the cap",
    Status.UNDER_RESOLVED: "under-resolved: settled, but the step error exceeds the tolerance",
}
