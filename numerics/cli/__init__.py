"""Command line of the simulator: `python -m numerics SUBCOMMAND`.

One module per subcommand; each adds its parser with argparse types from
``common`` (bad input or an unwritable output path exits 2 naming the option,
before any work) and writes JSON through ``common.write_json``.
"""

from __future__ import annotations

import argparse

from perturb.common import add_version, run_command

from ._atlas import add_atlas_parser
from ._backbone import add_backbone_parser
from ._compare import add_compare_parser
from ._continue import add_continue_parser
from ._folds import add_folds_parser
from ._info import add_info_parser
from ._scene import add_scene_parser
from ._steady import add_attractors_parser, add_sweep_parser

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m numerics", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    for add in (add_info_parser, add_backbone_parser, add_sweep_parser, add_attractors_parser,
                add_compare_parser, add_scene_parser, add_continue_parser, add_atlas_parser,
                add_folds_parser):
        add(sub)
    for command in (parser, *sub.choices.values()):
        add_version(command)
    return parser


def main(argv: list[str] | None = None) -> int:
    return run_command(build_parser().parse_args(argv))
