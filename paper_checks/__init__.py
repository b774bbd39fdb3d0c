"""paper_checks: the paper's claims as checks, its figures redrawn, and the report.

``python -m paper_checks [--quick] [--out DIR]`` writes DIR/report.md and
DIR/report.json (``make paper``). The paper's figures are scenes,
``paper_checks/scenes/*.toml``, run by ``numerics.scenes.run_scene``; importing this
package registers the scene study ``work_precision``.
"""

from ._claims import Claim
from ._registry import CHECKS, run_claims
from ._scene import PaperScene

__all__ = ["CHECKS", "Claim", "PaperScene", "run_claims"]
