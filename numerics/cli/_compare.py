"""`python -m numerics compare`: the series against the exact backbone and RK4."""

from __future__ import annotations

import argparse

from perturb.common import (
    add_allow_slow,
    add_unchecked,
    int_at_least,
    nonnegative_float,
    output_file,
    plot_file,
)
from perturb.model.set_option import add_model_option, model_parameters
from perturb.series.truncation import TRUNCATIONS

__all__ = ["add_compare_parser"]


def add_compare_parser(sub) -> None:
    parser = sub.add_parser(
        "compare", help="perturbation series of each order against the exact backbone and RK4"
    )
    parser.add_argument("--orders", type=int_at_least(0), nargs="+", default=[2, 4, 6],
                        help="series orders, integers >= 0 (default 2 4 6)")
    parser.add_argument("--pa-frac", type=nonnegative_float, nargs="+",
                        default=[0.05, 0.10, 0.15],
                        help="force amplitudes P_a / Q, finite, >= 0 (default 0.05 0.10 0.15)")
    parser.add_argument("--truncation", choices=TRUNCATIONS, default="consistent",
                        help="the series: every term of the contact's equation up to the "
                        "order (consistent, the default) or Eq. 2.6's (paper)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON "
                        "(-: to stdout, other lines to stderr)")
    parser.add_argument("--plot", metavar="FILE.png", type=plot_file,
                        help="draw the comparison there")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_allow_slow(parser)
    add_unchecked(parser)
    add_model_option(parser)
    parser.set_defaults(run=_compare)


def _compare(args: argparse.Namespace) -> int:
    from perturb import ContactModel

    from ..comparison.study import compare

    # --orders and --pa-frac are checked by their argparse types (exit 2, naming
    # the option); compare() checks them again for callers from Python.
    result = compare(sorted(set(args.orders)), sorted(set(args.pa_frac)),
                     model=ContactModel(model_parameters(args)), quiet=args.quiet,
                     truncation=args.truncation, allow_slow=args.allow_slow,
                     unchecked=args.unchecked)
    if args.json:
        result.to_json(args.json)
    print(result)
    if args.plot:
        from ..plots import plot_comparison  # matplotlib only when a plot is asked for

        plot_comparison(result, args.plot)
    return 0
