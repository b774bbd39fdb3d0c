"""Argument types of every command line: bad input is an argparse error naming the option.

argparse reports a failed type as ``argument --fmin: must be a finite number > 0,
got '0'`` and exits with status 2, before any computation starts. Output paths
are checked the same way, so that no result is lost at the end of a long run.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
from pathlib import Path

__all__ = ["positive_float", "nonnegative_float", "int_at_least", "output_file", "output_dir",
           "run_command", "name_value"]


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text!r}")
    return value


def positive_float(text: str) -> float:
    value = _finite(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def nonnegative_float(text: str) -> float:
    value = _finite(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text!r}")
    return value


def name_value(text: str) -> tuple[str, float]:
    """``NAME=VALUE`` (as ``--set m2=1.5``): the name and the finite number.

    Whether the name is known is for the command to say (it knows the names).
    """
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"must be NAME=VALUE, got {text!r}")
    return name.strip(), _finite(value.strip())


def int_at_least(minimum: int, maximum: int | None = None):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}, got {text!r}")
        if maximum is not None and value > maximum:
            raise argparse.ArgumentTypeError(f"must be an integer <= {maximum}, got {text!r}")
        return value

    parse.__name__ = f"integer >= {minimum}"
    return parse


def _writable_folder(folder: Path) -> bool:
    """Whether a file can be created in ``folder`` (tried, since root passes os.access)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


def output_file(text: str) -> str:
    """A file to write: not a folder, in a folder that exists and takes new files."""
    path = Path(text).expanduser()
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a folder, not a file")
    folder = path.parent
    if not folder.is_dir():
        raise argparse.ArgumentTypeError(f"folder {str(folder)!r} does not exist")
    if path.exists() and not os.access(path, os.W_OK) or not _writable_folder(folder):
        raise argparse.ArgumentTypeError(f"cannot write {text!r}")
    return text


def output_dir(text: str) -> str:
    """A folder to write into: created if missing (its parent must exist), and writable."""
    path = Path(text).expanduser()
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} exists and is not a folder")
    if not path.exists():
        if not path.parent.is_dir():
            raise argparse.ArgumentTypeError(f"folder {str(path.parent)!r} does not exist")
        try:
            path.mkdir()
        except OSError as error:
            raise argparse.ArgumentTypeError(f"cannot create {text!r}: {error.strerror}") from None
    if not _writable_folder(path):
        raise argparse.ArgumentTypeError(f"cannot write into {text!r}")
    return text


def run_command(args: argparse.Namespace) -> int:
    """Run a parsed command; a reader of stdout that goes away (``| head``) is no error."""
    try:
        return args.run(args) or 0
    except BrokenPipeError:
        # Python's advice: point stdout at devnull so that the exit flush cannot fail too.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
