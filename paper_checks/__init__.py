"""paper_checks: the paper's claims as checks, and its figures redrawn."""

from ._claims import Claim, run_claims

__all__ = ["Claim", "run_claims"]
