"""A claim of the paper: its words, what was measured, and the verdict."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Claim"]


@dataclass
class Claim:
    """One claim of the paper, checked.

    ``measured`` holds the figures the verdict rests on; ``beyond`` says what the
    toolkit found that the paper does not report (empty if nothing).
    """

    id: str
    statement: str
    passed: bool
    measured: dict = field(default_factory=dict)
    detail: str = ""
    beyond: str = ""

    def as_dict(self) -> dict:
        out = {"id": self.id, "statement": self.statement, "passed": bool(self.passed),
               "measured": _plain(self.measured)}
        if self.detail:
            out["detail"] = self.detail
        if self.beyond:
            out["beyond"] = self.beyond
        return out


def _plain(value):
    """JSON-ready: numpy scalars and arrays to Python numbers and lists."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return value.tolist()
    return value
