"""The paper's claims, each a check with the paper's words and what was measured."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from perturb import PAPER_F_N0_HZ, Eq26

__all__ = ["Claim", "run_claims", "CLAIMS"]


@dataclass
class Claim:
    """One claim of the paper: its words, the measurement, and the verdict."""

    id: str
    statement: str
    passed: bool
    measured: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"id": self.id, "statement": self.statement, "passed": self.passed,
                "measured": self.measured}


def natural_frequency() -> Claim:
    f_n0 = Eq26().numeric()["f_n0_hz"]
    deviation = f_n0 / PAPER_F_N0_HZ - 1
    return Claim(
        id="f_n0",
        statement="the natural frequency of the considered system equals f_n0 = 1485 Hz "
        "(Section 3)",
        passed=abs(deviation) < 1e-3,
        measured={"f_n0_hz": f_n0, "paper_hz": PAPER_F_N0_HZ, "relative_deviation": deviation},
    )


#: Every check, in the order of the report.
CLAIMS: list[Callable[[], Claim]] = [natural_frequency]


def run_claims(quick: bool = False) -> list[Claim]:
    """Run every check of the paper's claims."""
    return [check() for check in CLAIMS]
