"""A library's ValueError told in the command line's words: its arguments as options.

The library checks its input where it enters and names the argument in backticks
(```pa_max` must be above `pa_min` ...``, the house style); a command calls the same
checks rather than repeating them, and says the options the user typed instead.
"""

from __future__ import annotations

import argparse
import re
from typing import NoReturn

__all__ = ["option_error", "option_message"]

#: A name in backticks: an argument (``pa_max``, ``grid[0]``).
_NAMED = re.compile(r"`([\w\[\]]+)`")
#: A message that opens with the option it is about, as argparse's own do.
_OPENING = re.compile(r"(--[\w-]+) (must .*)", re.DOTALL)


def option_error(parser: argparse.ArgumentParser, error: ValueError,
                 options: dict[str, str]) -> NoReturn:
    """Exit 2 through ``parser.error`` with ``error``'s message, each argument it names
    replaced by its option (``options``: argument -> option, e.g. ``{"pa_max":
    "--pa-max"}``; names not in it are left as they are). A message about one option
    ("`pa_max` must ...") reads as argparse's ("argument --pa-max: must ...").
    """
    parser.error(option_message(error, options))


def option_message(error: ValueError, options: dict[str, str]) -> str:
    """``error``'s message with the arguments it names as options (``option_error``).

    Examples
    --------
    >>> option_message(ValueError("`pa_max` must be above `pa_min`, got 0.2 and 0.1."),
    ...                {"pa_min": "--pa-min", "pa_max": "--pa-max"})
    'argument --pa-max: must be above --pa-min, got 0.2 and 0.1'
    """
    text = _NAMED.sub(lambda name: options.get(name[1], name[0]), str(error)).rstrip(".")
    opening = _OPENING.fullmatch(text)
    return f"argument {opening[1]}: {opening[2]}" if opening else text
