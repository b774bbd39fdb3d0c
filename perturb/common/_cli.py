"""Argument types of every command line: bad input is an argparse error naming the option.

argparse reports a failed type as ``argument --fmin: must be a finite number > 0,
got '0'`` and exits with status 2, before any computation starts. Output paths
are checked the same way, so that no result is lost at the end of a long run.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import tempfile
from pathlib import Path

__all__ = ["positive_float", "nonnegative_float", "int_at_least", "output_file", "output_dir",
           "plot_file", "run_command", "name_value", "PLOT_FORMATS", "add_allow_slow",
           "add_unchecked", "add_version", "describe"]


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


def int_at_least(minimum: int, maximum: int | None = None, why: str = ""):
    """An argparse type: an integer in [minimum, maximum]; ``why`` says in the error why
    the maximum is there."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}, got {text!r}")
        if maximum is not None and value > maximum:
            reason = f" ({why})" if why else ""
            raise argparse.ArgumentTypeError(
                f"must be an integer <= {maximum}, got {text!r}{reason}")
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
    """A file to write: not a folder, in a folder that exists and takes new files; "-" is
    standard output (the JSON writer's ``STDOUT``)."""
    if text == "-":
        return text
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


#: What matplotlib's Agg backend writes, by extension (``tests/test_cli_errors.py`` holds
#: it to matplotlib's own list, which takes importing matplotlib to ask).
PLOT_FORMATS = ("avif", "eps", "gif", "jpeg", "jpg", "pdf", "pgf", "png", "ps", "raw", "rgba",
                "svg", "svgz", "tif", "tiff", "webp")


def plot_file(text: str) -> str:
    """A figure to write (``output_file``) in a format that matplotlib draws, told by its
    extension: checked before the work, not after it."""
    suffix = Path(text).suffix.lower().lstrip(".")
    if suffix not in PLOT_FORMATS:
        kind = f".{suffix}" if suffix else "a file with no extension"
        raise argparse.ArgumentTypeError(f"{text!r}: cannot draw a figure as {kind}; the "
                                         f"formats are {', '.join(PLOT_FORMATS)}")
    return output_file(text)


def add_allow_slow(parser: argparse.ArgumentParser) -> None:
    """``--allow-slow``: take a series order above the one measured to take about a
    minute (a command refuses it otherwise, exit status 2, naming the limit)."""
    parser.add_argument("--allow-slow", action="store_true",
                        help="take an order above the one measured to take about a minute "
                             "(refused otherwise)")


def add_unchecked(parser: argparse.ArgumentParser) -> None:
    """``--unchecked``: go past the ranges of f_e, P_a and the contact where the answers
    are measured to hold (refused otherwise, exit status 2, naming the range)."""
    parser.add_argument("--unchecked", action="store_true",
                        help="go past the ranges of f_e, P_a and the contact where the "
                             "answers are measured to hold (at your own risk)")


def run_command(args: argparse.Namespace) -> int:
    """Run a parsed command and say in one line what went wrong, never in a traceback.

    - a reader of stdout that goes away (``| head``) is no error;
    - bad input found by the toolkit (a ``ValueError`` whose message names the argument,
      "`name` ..."): its message, exit status 2;
    - a file system that fails (a full disk, a folder removed): its message, status 1;
    - anything else, another ``ValueError`` included: its message, and its traceback in
      a log file that the line names, status 1.
    """
    try:
        if getattr(args, "json", None) == "-":
            return _json_on_stdout(args)
        return args.run(args) or 0
    except BrokenPipeError:
        # Python's advice: point stdout at devnull so that the exit flush cannot fail too.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except ValueError as error:
        if not str(error).startswith("`"):  # not the toolkit's word on an argument
            print(f"{_prog(args)}: error: {error} (the traceback is in {_traceback_log()})",
                  file=sys.stderr)
            return 1
        print(f"{_prog(args)}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"{_prog(args)}: error: {error.strerror or error}"
              f"{f': {error.filename!r}' if error.filename else ''}", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001 - the last resort: said in one line, kept in a log
        log = _traceback_log()
        print(f"{_prog(args)}: internal error ({sys.exc_info()[1]!r}); the traceback is in "
              f"{log}", file=sys.stderr)
        return 1


class _Version(argparse.Action):
    """``--version``: the toolkit's version, read only when asked for."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="show the toolkit's version and exit"):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from ._version import VERSION

        print(f"{parser.prog} {VERSION}")  # on stdout, as argparse's own "version" action
        parser.exit()


def describe(subcommands, examples: dict[str, str]) -> None:
    """Give each subcommand of ``subcommands`` (``add_subparsers``' result) its one-line
    help as the description of its own --help, and its example from ``examples``."""
    helps = {action.dest: action.help for action in subcommands._choices_actions}
    for name, command in subcommands.choices.items():
        command.description = command.description or helps[name]
        command.epilog = f"example:\n  {examples[name]}"
        command.formatter_class = argparse.RawDescriptionHelpFormatter


def program(package: str) -> str:
    """The command's name as the user typed it: its console script
    (``contact-numerics`` for ``numerics``, ``contact-paper-checks`` for
    ``paper_checks``), or ``python -m PACKAGE``."""
    script = "contact-" + package.replace("_", "-")
    return script if Path(sys.argv[0]).name == script else f"python -m {package}"


def csv_file(text: str) -> str:
    """A CSV file to write (as ``output_file``, but a file: no "-")."""
    if text == "-":
        raise argparse.ArgumentTypeError("CSV goes to a file (--json - writes to stdout)")
    return output_file(text)


def add_csv(parser: argparse.ArgumentParser) -> None:
    """``--csv FILE``: the result's table (``Result.to_csv``), units in the column names."""
    parser.add_argument("--csv", metavar="FILE", type=csv_file,
                        help="also write the result's table as CSV, a row a point, units in "
                             "the column names (default: none)")


def write_table(result, args: argparse.Namespace) -> None:
    """The result's CSV, where ``--csv`` asks for it."""
    if getattr(args, "csv", None):
        result.to_csv(args.csv)


def add_version(parser: argparse.ArgumentParser) -> None:
    """``--version`` on a command line."""
    parser.add_argument("--version", action=_Version)


def _json_on_stdout(args: argparse.Namespace) -> int:
    """``args.run`` with ``--json -``: the JSON on stdout alone, every other line the
    command prints on stderr."""
    from ._json import JSON_STDOUT

    token = JSON_STDOUT.set(sys.stdout)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            return args.run(args) or 0
    finally:
        JSON_STDOUT.reset(token)


def _prog(args: argparse.Namespace) -> str:
    parser = getattr(args, "parser", None)
    return parser.prog if parser is not None else Path(sys.argv[0]).name


def _traceback_log() -> str:
    """Write the current exception's traceback to a new log file; its path."""
    import traceback

    handle, path = tempfile.mkstemp(prefix="contact-resonances-error-", suffix=".log")
    with os.fdopen(handle, "w", encoding="utf-8") as log:
        log.write(" ".join(sys.argv) + "\n\n" + traceback.format_exc())
    return path
