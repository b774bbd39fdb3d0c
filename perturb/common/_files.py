"""Files written whole or not at all.

Every file the toolkit writes (results, figures, reports, caches) is written to a
temporary file beside the target, then renamed onto it (``replacing``,
``write_atomically``). A reader never sees half a file, an interrupted or failed write
leaves nothing behind, and an existing symlink at the target is replaced, never
written through (nothing lands outside the folder asked for). A target that is no file
(a device or a pipe, such as ``/dev/stdout``) is written to as the stream it is.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["replacing", "write_atomically"]


@contextmanager
def replacing(path: str | Path) -> Iterator[Path]:
    """The path to write ``path``'s new content to; renamed onto ``path`` when the block
    ends without an error, removed when it raises.

    The temporary name keeps the suffix (a figure's format is told by it) and names the
    process and thread (two writers never share one).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     with replacing(f"{folder}/a.txt") as tmp:
    ...         _ = tmp.write_text("whole")
    ...     print(sorted(p.name for p in Path(folder).iterdir()))
    ['a.txt']
    """
    path = Path(path)
    if _stream(path):  # nothing to replace: written as it is
        yield path
        return
    tmp = path.with_name(f".{path.stem}.tmp{os.getpid()}-{threading.get_ident()}{path.suffix}")
    try:
        yield tmp
        tmp.replace(path)
    except OSError as error:
        tmp.unlink(missing_ok=True)
        if error.errno is not None and error.filename in (str(tmp), tmp):
            # Said of the file asked for, not of the temporary one.
            raise OSError(error.errno, error.strerror, str(path)) from error
        raise
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _stream(path: Path) -> bool:
    """Whether ``path`` is a stream rather than a file: a device or a pipe, or a link to
    a process's file descriptor (``/dev/stdout`` is one, whatever stdout points to)."""
    if path.exists() and not path.is_file():
        return True
    return path.is_symlink() and os.readlink(path).startswith(("/proc/", "/dev/fd/"))


def write_atomically(path: str | Path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` whole or not at all (``replacing``).

    If the write fails (a full disk, text that cannot be encoded), the error is raised
    and ``path`` is as it was. A path that is this process's standard output
    (``/dev/stdout``) is written through ``sys.stdout``, so that what is printed after
    it follows it instead of overwriting it.
    """
    if _is_stdout(Path(path)):
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    with replacing(path) as target:
        target.write_text(text, encoding=encoding)


def _is_stdout(path: Path) -> bool:
    try:
        return _stream(path) and os.path.samestat(os.stat(path), os.fstat(sys.stdout.fileno()))
    except (OSError, ValueError, AttributeError):  # no stdout, or one without a descriptor
        return False
