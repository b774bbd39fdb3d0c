"""paper_checks: the paper's claims as checks, its figures redrawn, and the report.

``python -m paper_checks [--quick] [--out DIR]`` writes DIR/report.md and
DIR/report.json (``make paper``).
"""

from ._claims import Claim
from ._registry import CHECKS, run_claims
from ._scene import PaperScene

__all__ = ["CHECKS", "Claim", "PaperScene", "run_claims"]
