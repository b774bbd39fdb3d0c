"""The toolkit's version: that of the installed distribution, read once, at first use."""

from __future__ import annotations

from importlib import metadata

__all__ = ["DISTRIBUTION", "VERSION"]

#: The distribution that installs perturb, numerics and paper_checks (pyproject.toml).
DISTRIBUTION = "contact-resonances"


def _installed() -> str:
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:  # run from a tree that is not installed
        return "unknown (not installed)"


VERSION = _installed()
