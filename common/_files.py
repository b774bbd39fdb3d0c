"""Files written whole or not at all.

Every file the toolkit writes (results, caches) goes through ``write_atomically``: a
temporary file beside the target, then a rename. A reader never sees half a file, an
interrupted or failed write leaves nothing behind, and an existing symlink at the
target is replaced, never written through (nothing lands outside the folder asked for).
A target that is no file (a device or a pipe, such as ``/dev/stdout``) is written to
as the stream it is.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

__all__ = ["write_atomically"]


def write_atomically(path: str | Path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename.

    If the write fails (a full disk, text that cannot be encoded), the temporary file
    is removed and the error raised; ``path`` is as it was.
    """
    path = Path(path)
    if path.exists() and not path.is_file():  # a device or a pipe (/dev/stdout): a stream,
        path.write_text(text, encoding=encoding)  # nothing to replace
        return
    # Process and thread: two threads of one process must not share a temporary file.
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}-{threading.get_ident()}")
    try:
        tmp.write_text(text, encoding=encoding)
        tmp.replace(path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
