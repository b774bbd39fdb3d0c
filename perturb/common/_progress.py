"""Progress on stderr for long work, through tqdm: drawn on a terminal, silent with
``quiet``; where stderr is not a terminal (a log file, a pipe, CI) bars are drawn only
when the environment variable ``CONTACT_RESONANCES_PROGRESS`` is "always"."""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["progress", "note", "PROGRESS_VARIABLE"]

#: The environment variable that draws progress bars where stderr is not a terminal.
PROGRESS_VARIABLE = "CONTACT_RESONANCES_PROGRESS"


def progress(total: int, label: str, *, quiet: bool = False) -> tqdm:
    """A progress bar over ``total`` steps: ``.update()`` per step, ``.close()`` at the end;
    drawn only where stderr is a terminal (or ``PROGRESS_VARIABLE`` says "always"), never
    with ``quiet``."""
    from tqdm import tqdm  # imported by the commands that show a bar only

    return tqdm(total=total, desc=label, disable=not _drawn(quiet), file=sys.stderr,
                leave=False, mininterval=0.1, dynamic_ncols=True)


def _drawn(quiet: bool) -> bool:
    if quiet:
        return False
    if os.environ.get(PROGRESS_VARIABLE, "").lower() == "always":
        return True
    isatty = getattr(sys.stderr, "isatty", None)
    return bool(isatty and isatty())


def note(message: str, *, quiet: bool = False) -> None:
    """One line of progress on stderr (nothing with ``quiet``)."""
    if not quiet:
        print(message, file=sys.stderr, flush=True)
