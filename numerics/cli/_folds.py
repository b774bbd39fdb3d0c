"""`python -m numerics folds`: fold curves in the (f_e, P_a) plane, with cusps."""

from __future__ import annotations

import argparse

from perturb import FULL, ContactModel
from perturb.common import add_csv, output_file, plot_file, positive_float
from perturb.model.set_option import add_model_option, model_parameters

from ._steady import add_band_options, check_band, report, walk_steps_option

__all__ = ["add_folds_parser"]


def add_folds_parser(sub) -> None:
    parser = sub.add_parser("folds", help="fold curves of period-1 orbits in the (f_e, P_a) "
                            "plane, with the cusps where bistable regions are born")
    add_band_options(parser)
    parser.add_argument("--pa-min", type=positive_float, required=True, help="least P_a / Q")
    parser.add_argument("--pa-max", type=positive_float, required=True, help="largest P_a / Q")
    parser.add_argument("--seed-pa-frac", type=positive_float, nargs="+", metavar="PA",
                        help="P_a / Q at which one-parameter continuation looks for folds to "
                        "start from (default: --pa-max and the band's middle)")
    parser.add_argument("--steps", type=walk_steps_option, default="auto",
                        help="RK4 steps per period, fixed over the box: an integer >= 4 or "
                        "'auto' (the default: at least 512)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON "
                        "(-: to stdout, other lines to stderr)")
    add_csv(parser)
    parser.add_argument("--plot", metavar="FILE.png", type=plot_file,
                        help="the fold curves in the (f_e, P_a / Q) plane, cusps marked")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_model_option(parser)
    parser.set_defaults(run=_folds, parser=parser)


def _folds(args: argparse.Namespace) -> int:
    check_band(args)
    if not args.pa_min < args.pa_max:
        args.parser.error(f"argument --pa-max: must be above --pa-min, got {args.pa_min} and "
                          f"{args.pa_max}")
    from ..continuation.folds import fold_curves

    try:
        result = fold_curves(args.fmin, args.fmax, args.pa_min, args.pa_max,
                             model=ContactModel(model_parameters(args), FULL),
                             seed_pa_fracs=args.seed_pa_frac, steps_per_period=args.steps,
                             quiet=args.quiet)
    except ValueError as error:  # e.g. a band out of the model's reach: before any work
        args.parser.error(str(error))
    report(result, args, "plot_folds")
    # No fold in the box at the seeds: nothing to continue.
    return 0 if result.fold_curves else 1
