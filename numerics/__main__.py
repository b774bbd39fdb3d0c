"""Command line of the simulator: `python -m numerics SUBCOMMAND`."""

from __future__ import annotations

import argparse
import json
import sys

from ._info import format_info, model_info


def _write_json(path: str | None, payload: dict) -> None:
    if path:
        with open(path, "w") as handle:
            json.dump(payload, handle, indent=2)
            handle.write("\n")


def _info(args: argparse.Namespace) -> int:
    info = model_info()
    print(format_info(info))
    _write_json(args.json, info)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m numerics", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    info = sub.add_parser("info", help="print the model's static and linear figures")
    info.add_argument("--json", metavar="FILE", help="also write them as JSON")
    info.set_defaults(run=_info)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
