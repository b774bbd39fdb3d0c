"""Command line of the simulator: `python -m numerics SUBCOMMAND`."""

from __future__ import annotations

import argparse
import sys

from .._backbone import exact_backbone
from .._backbone_table import format_backbone
from ._compare import add_compare_parser
from ._steady import add_attractors_parser, add_sweep_parser
from common import int_at_least, output_file
from .._info import format_info, model_info
from common import write_json


def _info(args: argparse.Namespace) -> int:
    info = model_info()
    print(format_info(info))
    write_json(args.json, info)
    return 0


def _backbone(args: argparse.Namespace) -> int:
    if not args.quiet:
        print(f"backbone: {args.points} energy levels ...", file=sys.stderr)
    backbone = exact_backbone(points=args.points)
    print(format_backbone(backbone))
    write_json(args.json, backbone.as_json())
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m numerics", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    info = sub.add_parser("info", help="print the model's static and linear figures")
    info.add_argument("--json", metavar="FILE", type=output_file,
                      help="also write them as JSON")
    info.set_defaults(run=_info)
    backbone = sub.add_parser(
        "backbone", help="exact frequency of free oscillation against amplitude"
    )
    backbone.add_argument("--points", type=int_at_least(1), default=200, metavar="N",
                          help="energy levels, log-spaced, >= 1 (default 200)")
    backbone.add_argument("--json", metavar="FILE", type=output_file,
                          help="also write the curve as JSON")
    backbone.add_argument("--quiet", action="store_true", help="no progress on stderr")
    backbone.set_defaults(run=_backbone)
    add_sweep_parser(sub)
    add_attractors_parser(sub)
    add_compare_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
