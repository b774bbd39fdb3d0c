"""`python -m numerics info`: the numbers of Eq. 2.6 for the paper's model (or ``--set``'s)."""

from __future__ import annotations

import argparse

from perturb.common import GLOSSARY, output_file, provenance, write_json
from perturb.model.set_option import add_model_option, model_parameters

__all__ = ["add_info_parser", "format_info"]


def format_info(info: dict[str, float]) -> str:
    """One aligned line per number, with what it means (from the glossary)."""
    return "\n".join(
        f"{key:<14} {value:>14.7g}   {GLOSSARY[key][0]}" for key, value in info.items()
    )


def add_info_parser(sub) -> None:
    parser = sub.add_parser("info", help="print the model's static and linear figures")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write them as JSON (-: to stdout)")
    add_model_option(parser)
    parser.set_defaults(run=_info)


def _info(args: argparse.Namespace) -> int:
    from perturb import eq26_numbers

    info = eq26_numbers(model_parameters(args)).as_dict()
    print(format_info(info))
    if args.json:  # the numbers, and where they come from
        write_json(args.json, info | {"provenance": provenance()})
    return 0
