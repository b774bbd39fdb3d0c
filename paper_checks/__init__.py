"""paper_checks: the paper's claims as checks, its figures redrawn, and the report.

``python -m paper_checks [--quick] [--out DIR]`` writes DIR/report.md and
DIR/report.json (``make paper``). The paper's figures are scenes,
``paper_checks/scenes/*.toml``, run by ``numerics.scenes.run_scene``; importing
``paper_checks.work_precision`` (as ``PaperScene``'s module does) registers the scene
study ``work_precision``.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562), so that `python -m paper_checks` imports them after
# it has turned the garbage collector off (paper_checks/__main__.py).
_LAZY = {"__version__": ("perturb.common._version", "VERSION"), "Claim": ".claims",
         "CHECKS": ".registry", "run_claims": ".registry",
         "PaperScene": ".scene"}

__all__ = ["CHECKS", "Claim", "PaperScene", "run_claims"]

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())
