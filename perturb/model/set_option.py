"""`--set NAME=VALUE`: the model's parameters on every command that depends on them
(numerics' commands, `perturb response`), as in a scene's [model]."""

from __future__ import annotations

import argparse

from perturb.common import name_value

from .parameters import parameters_with

__all__ = ["add_model_option", "model_parameters"]


def add_model_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--set", dest="model_set", metavar="NAME=VALUE", type=name_value,
                        action="append", default=[],
                        help="replace one of the paper's model parameters (S, c_n, m2, h_n, "
                        "l, M, g; SI units); repeatable")
    parser.set_defaults(parser=parser)


def model_parameters(args: argparse.Namespace):
    """The parameters that ``--set`` asks for (the paper's without it), or exit 2."""
    try:
        return parameters_with(dict(args.model_set))
    except ValueError as error:
        args.parser.error(f"argument --set: {error}")
