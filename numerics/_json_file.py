"""Writing a command's result as JSON (`--json FILE`), the same way for every command."""

from __future__ import annotations

import json

__all__ = ["write_json"]


def write_json(path: str | None, payload: dict) -> None:
    """Write ``payload`` to ``path`` as indented JSON; do nothing when ``path`` is None."""
    if path:
        with open(path, "w") as handle:
            json.dump(payload, handle, indent=1)
            handle.write("\n")
