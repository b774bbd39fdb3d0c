"""Command line of the simulator: `python -m numerics SUBCOMMAND`.

One module per subcommand; each adds its parser with argparse types from
``common`` (bad input or an unwritable output path exits 2 naming the option,
before any work) and writes JSON through ``common.write_json``.
"""

from __future__ import annotations

import argparse

from perturb.common import add_version, describe, program, run_command

from ._atlas import add_atlas_parser
from ._backbone import add_backbone_parser
from ._compare import add_compare_parser
from ._continue import add_continue_parser
from ._folds import add_folds_parser
from ._info import add_info_parser
from ._scene import add_scene_parser
from ._steady import add_attractors_parser, add_sweep_parser

__all__ = ["build_parser", "main", "DESCRIPTION", "EXAMPLES"]

#: What ``python -m numerics --help`` says the command line is.
DESCRIPTION = ("The simulator of the contact model from the command line: the model's "
               "figures, steady states and frequency sweeps, coexisting attractors, periodic "
               "orbits continued through their folds, fold curves, the multistability atlas, "
               "the exact backbone, the series against RK4, and scenes (a study written as "
               "a TOML file). Each subcommand's --help says more, with an example.")
#: One example of each subcommand, shown by its --help (a test parses each).
EXAMPLES = {
    "info": "python -m numerics info --set m2=1.5",
    "backbone": "python -m numerics backbone --points 50 --json backbone.json",
    "sweep": "python -m numerics sweep --pa-frac 0.1 --fmin 500 --fmax 1500 --points 21",
    "attractors": "python -m numerics attractors --pa-frac 0.5 --fe 490",
    "compare": "python -m numerics compare --orders 2 4 --pa-frac 0.05",
    "scene": "python -m numerics scene linear-contact",
    "continue": "python -m numerics continue --pa-frac 0.05 --fmin 1300 --fmax 1600",
    "atlas": ("python -m numerics atlas --fmin 1150 --fmax 1550 --pa-min 0.02 --pa-max 0.08 "
              "--grid 21 8"),
    "folds": "python -m numerics folds --fmin 1300 --fmax 1500 --pa-min 0.03 --pa-max 0.05",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=program("numerics"), description=DESCRIPTION)
    sub = parser.add_subparsers(dest="command", required=True)
    for add in (add_info_parser, add_backbone_parser, add_sweep_parser, add_attractors_parser,
                add_compare_parser, add_scene_parser, add_continue_parser, add_atlas_parser,
                add_folds_parser):
        add(sub)
    describe(sub, EXAMPLES)
    for command in (parser, *sub.choices.values()):
        add_version(command)
    return parser


def main(argv: list[str] | None = None) -> int:
    return run_command(build_parser().parse_args(argv))
