"""`python -m numerics backbone`: the exact frequency of free oscillation against amplitude."""

from __future__ import annotations

import argparse

from perturb.common import add_csv, int_at_least, note, output_file, positive_float, write_table
from perturb.model.set_option import add_model_option, model_parameters

__all__ = ["add_backbone_parser"]


def _points(text: str) -> int:
    """--points: an integer from 1 to the backbone's MAX_POINTS."""
    from ..backbone.exact import MAX_POINTS

    return int_at_least(1, MAX_POINTS, "computed in chunks, 0.4 GB at the limit")(text)


def add_backbone_parser(sub) -> None:
    parser = sub.add_parser(
        "backbone", help="exact frequency of free oscillation against amplitude"
    )
    parser.add_argument("--points", type=_points, default=200, metavar="N",
                        help="energy levels, log-spaced, >= 1 (default 200)")
    parser.add_argument("--app-min", type=positive_float, metavar="M",
                        help="least A_pp [m]; with --app-max, the levels run from A_pp = "
                             "APP_MIN to APP_MAX (default: u_max = y_max - y0 from 1e-6 y0 "
                             "to 3 y0, A_pp 0.45 pm to 4.8 um)")
    parser.add_argument("--app-max", type=positive_float, metavar="M",
                        help="largest A_pp [m], e.g. 2.5e-5 for the bouncing branches of "
                             "Fig. 2; needs --app-min")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the curve as JSON (-: to stdout; numerics.load reads "
                        "a file back)")
    add_csv(parser)
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_model_option(parser)
    parser.set_defaults(run=_backbone, parser=parser)


def _app_range(args: argparse.Namespace) -> tuple[float, float] | None:
    """(--app-min, --app-max), or None; both or neither, min below max (else exit 2)."""
    if args.app_min is None and args.app_max is None:
        return None
    if args.app_min is None or args.app_max is None:
        given, missing = (("--app-min", "--app-max") if args.app_max is None
                          else ("--app-max", "--app-min"))
        args.parser.error(f"argument {missing}: needed with {given}")
    if not args.app_min < args.app_max:
        args.parser.error(f"argument --app-max: must be above --app-min, got {args.app_min:g} "
                          f"and {args.app_max:g}")
    return args.app_min, args.app_max


def _backbone(args: argparse.Namespace) -> int:
    app_range = _app_range(args)  # before any work
    parameters = model_parameters(args)
    from perturb import ContactModel

    from ..backbone.exact import exact_backbone

    span = "" if app_range is None else f", A_pp {app_range[0]:g}..{app_range[1]:g} m"
    note(f"backbone: {args.points} energy levels{span} ...", quiet=args.quiet)
    backbone = exact_backbone(app_range_m=app_range, points=args.points,
                              model=ContactModel(parameters))
    backbone.to_json(args.json)  # before printing: a closed pipe loses nothing
    write_table(backbone, args)
    print(backbone)
    return 0
