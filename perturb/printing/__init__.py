"""The derived series printed for people: text, LaTeX, JSON, and the paper's names.

- ``report``: ``text_report``, ``latex_report`` and ``series_json``;
- ``derivation``: the derivation step by step in the paper's names;
- ``names``: the paper's A0-A19, phi0-phi9 and b1-b4 in the engine's names, and where
  the paper's print differs from the derivation.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "text_report": ".report",
    "latex_report": ".report",
    "series_json": ".report",
    "derivation_text": ".derivation",
    "derivation_latex": ".derivation",
    "PAPER_NAMES": ".names",
    "PAPER_DIFFERENCES": ".names",
    "paper_names": ".names",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "PAPER_DIFFERENCES",
    "PAPER_NAMES",
    "derivation_latex",
    "derivation_text",
    "latex_report",
    "paper_names",
    "series_json",
    "text_report",
]
