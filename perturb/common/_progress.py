"""Progress on stderr for long work, through tqdm; silent with ``quiet``."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["progress", "note"]


def progress(total: int, label: str, *, quiet: bool = False) -> tqdm:
    """A progress bar over ``total`` steps: ``.update()`` per step, ``.close()`` at the end."""
    from tqdm import tqdm  # imported by the commands that show a bar only

    return tqdm(total=total, desc=label, disable=quiet, file=sys.stderr, leave=False,
                mininterval=0.1, dynamic_ncols=True)


def note(message: str, *, quiet: bool = False) -> None:
    """One line of progress on stderr (nothing with ``quiet``)."""
    if not quiet:
        print(message, file=sys.stderr, flush=True)
