"""`python -m numerics scene FILE.toml|NAME`: run a scene, print its summary, write its
outputs; `--list` lists the bundled scenes."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from perturb.common import output_dir, output_file

__all__ = ["add_scene_parser"]


def add_scene_parser(sub) -> None:
    parser = sub.add_parser("scene", help="run a scene: a study written as a TOML file")
    parser.add_argument("file", metavar="FILE.toml|NAME", nargs="?",
                        help="the scene file, or the name of a bundled scene (--list)")
    parser.add_argument("--list", action="store_true",
                        help="list the bundled scenes (the paper's figures and the "
                             "examples) and stop")
    parser.add_argument("--out", type=output_dir, metavar="DIR",
                        help="folder for the figures and files the scene asks for "
                             "(default: out/scenes/NAME, NAME the file's stem)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON "
                        "(-: to stdout, other lines to stderr)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    parser.set_defaults(run=_scene, parser=parser)


def _scene(args: argparse.Namespace) -> int:
    from ..scenes import SceneError, read_scene, run_scene
    from ..scenes.bundled import find_scene, scene_list

    if args.list:
        print(scene_list())
        return 0
    if args.file is None:
        args.parser.error("a scene file or a bundled scene's name is required (--list)")
    try:
        path = find_scene(args.file)
        scene = read_scene(path)
    except (SceneError, FileNotFoundError) as error:  # one line: the file, the key, the value
        print(f"error: {error}", file=sys.stderr)
        return 2
    out = Path(args.out) if args.out else Path("out") / "scenes" / path.stem
    try:
        run = run_scene(scene, out=out, json=args.json, quiet=args.quiet)
    except ValueError as error:  # a value the schema let through and the study refused
        print(f"error: {args.file}: {error}", file=sys.stderr)
        return 2
    print(run)
    return 0
