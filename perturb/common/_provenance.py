"""Where a result file comes from: the toolkit's version (and its commit, when it runs
from a git checkout), the versions of the libraries that computed it, and when it was
written. Every result file (``Result.to_json``, each command's ``--json``) carries it as
``"provenance"``; ``load`` reads it back as the object's ``provenance`` attribute, and
a loaded result written again keeps it (only ``written_utc`` is new). The version and
commit are read once a process."""

from __future__ import annotations

import functools
import platform
import subprocess
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

__all__ = ["provenance"]

#: The libraries whose versions shape the numbers.
LIBRARIES = ("numpy", "scipy", "sympy", "numba")
_TREE = Path(__file__).resolve().parents[2]


@functools.lru_cache(maxsize=1)
def _fixed() -> dict:
    from ._version import VERSION

    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return {"version": VERSION, "commit": _commit(), "python": platform.python_version(),
            "libraries": versions}


def _commit() -> str | None:
    """The checkout's commit, with "+changes" when its tracked files differ from it; None
    outside a git checkout (an installed wheel)."""
    if not (_TREE / ".git").exists():
        return None
    try:
        head = subprocess.run(["git", "-C", str(_TREE), "rev-parse", "HEAD"],
                              capture_output=True, text=True, timeout=10)
        # --no-optional-locks: a status of ours never takes the index lock from the user's
        dirty = subprocess.run(["git", "--no-optional-locks", "-C", str(_TREE), "status",
                                "--porcelain", "--untracked-files=no"], capture_output=True,
                               text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    if head.returncode != 0:
        return None
    return head.stdout.strip() + ("+changes" if dirty.stdout.strip() else "")


def provenance() -> dict:
    """The provenance of a result written now.

    Examples
    --------
    >>> sorted(provenance())
    ['commit', 'libraries', 'python', 'version', 'written_utc']
    """
    return _fixed() | {"written_utc": datetime.now(timezone.utc).isoformat(timespec="seconds")}
