"""`python -m numerics continue`: periodic orbits continued through their folds, with
stability: in f_e at one P_a (``--pa-frac``), or in P_a at one f_e (``--fe``).

One command for both: the option that fixes one parameter says which one is walked,
and the result's JSON has the same keys either way (a ``Continuation`` or a
``ForceContinuation``)."""

from __future__ import annotations

import argparse
from pathlib import Path

from perturb import EQ_2_6, FULL, PAPER_BAND_HZ, ContactModel
from perturb.common import (
    add_csv,
    int_at_least,
    nonnegative_float,
    output_file,
    plot_file,
    positive_float,
    write_table,
)
from perturb.model.set_option import add_model_option, model_parameters
from perturb.series.truncation import TRUNCATIONS

from ._errors import option_error
from ._steady import add_band_options, check_band, report, walk_steps_option

__all__ = ["add_continue_parser"]

#: The options of each kind of continuation (dest -> option), refused with the other.
IN_F_ONLY = {"fmin": "--fmin", "fmax": "--fmax", "series": "--series", "switch": "--switch",
             "truncation": "--truncation"}
IN_FORCE_ONLY = {"pa_min": "--pa-min", "pa_max": "--pa-max"}
#: The library's arguments as this command's options, for its error messages.
OPTIONS = {"pa_frac": "--pa-frac", "fmin_hz": "--fmin", "fmax_hz": "--fmax",
           "frequency_hz": "--fe", "pa_min": "--pa-min", "pa_max": "--pa-max",
           "period": "--period", "steps_per_period": "--steps"}


def add_continue_parser(sub) -> None:
    parser = sub.add_parser("continue", help="periodic orbits continued through their folds, "
                            "with stability: in f_e at one P_a (--pa-frac), or in P_a at one "
                            "f_e (--fe)")
    fixed = parser.add_mutually_exclusive_group(required=True)
    fixed.add_argument("--pa-frac", type=positive_float,
                       help="P_a / Q: continue in f_e, over --fmin to --fmax")
    fixed.add_argument("--fe", type=positive_float,
                       help="f_e [Hz]: continue in P_a, over --pa-min to --pa-max")
    in_f = parser.add_argument_group(
        "continuation in f_e (with --pa-frac; the band defaults to the paper's, "
        f"{PAPER_BAND_HZ[0]:g}-{PAPER_BAND_HZ[1]:g} Hz)")
    add_band_options(in_f)
    parser.set_defaults(fmin=None, fmax=None)  # the paper's band, given --pa-frac
    in_force = parser.add_argument_group("continuation in P_a (with --fe; both required)")
    in_force.add_argument("--pa-min", type=nonnegative_float, help="least P_a / Q")
    in_force.add_argument("--pa-max", type=positive_float, help="largest P_a / Q")
    parser.add_argument("--period", type=int_at_least(1, 8), default=1,
                        help="p of the orbit continued (default 1)")
    parser.add_argument("--steps", type=walk_steps_option, default="auto",
                        help="RK4 steps per period, fixed along the branch: an integer >= 4 "
                        "or 'auto' (the default: at least 512)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON "
                        "(-: to stdout, other lines to stderr)")
    add_csv(parser)
    parser.add_argument("--plot", metavar="FILE.png", type=plot_file,
                        help="App against the parameter walked (f_e or P_a / Q): stable solid, "
                        "unstable dashed, bifurcations marked")
    in_f.add_argument("--series", metavar="N", type=int_at_least(0, MAX_SERIES_ORDER),
                      help="also the order-N perturbation series (N <= "
                      f"{MAX_SERIES_ORDER}), each root with the stability of the orbit it "
                      "describes; the branch continued is then the series' own model "
                      "(Eq. 2.6 with --truncation paper), --plot draws the series over it, "
                      "and --json FILE writes the series' stability to FILE-series.json too")
    in_f.add_argument("--truncation", choices=TRUNCATIONS,
                      help="with --series: the contact's consistent series (the default; "
                      "the full model continued) or Eq. 2.6's (paper; Eq. 2.6 continued)")
    in_f.add_argument("--switch", action="store_true",
                      help="also continue the branch of period 2p born at each period "
                      "doubling found (branch switching)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_model_option(parser)
    parser.set_defaults(run=_continue, parser=parser)


def _continue(args: argparse.Namespace) -> int:
    if args.fe is not None:
        return _continue_in_force(args)
    _refuse(args, IN_FORCE_ONLY, "--pa-frac")
    args.fmin = PAPER_BAND_HZ[0] if args.fmin is None else args.fmin
    args.fmax = PAPER_BAND_HZ[1] if args.fmax is None else args.fmax
    check_band(args)
    from ..continuation.walk import continue_orbits

    if args.truncation is not None and args.series is None:
        args.parser.error("argument --truncation: goes with --series")
    if args.json == "-" and args.series is not None:
        args.parser.error("argument --json: '-' writes one result on stdout; with --series "
                          "give a file (the series' stability goes beside it)")
    args.truncation = args.truncation or "consistent"
    parameters = model_parameters(args)
    eq26 = args.series is not None and args.truncation == "paper"
    model = ContactModel(parameters, EQ_2_6 if eq26 else FULL)
    try:
        # The series first: it is quick, and a value it refuses stops before the branch.
        stability = None if args.series is None else _series(args, parameters)
        result = continue_orbits(args.pa_frac, args.fmin, args.fmax, model=model,
                                 period=args.period, steps_per_period=args.steps,
                                 quiet=args.quiet)
        if args.switch:
            from ..continuation.branch_switch import with_doubled_branches

            result = with_doubled_branches(result, quiet=args.quiet)
    except ValueError as error:  # e.g. a band out of the model's reach: before any work
        option_error(args.parser, error, OPTIONS)
    if args.json:
        result.to_json(args.json)
        if stability is not None:
            stability.to_json(Path(args.json).with_name(Path(args.json).stem + "-series.json"))
    write_table(result, args)
    print(result)
    if stability is not None:
        print(stability)
    if args.plot:
        from ..plots import plot_continuation, plot_series_stability

        if stability is None:
            plot_continuation(result, args.plot)
        else:
            plot_series_stability(stability, result, args.plot)
    return _found(result)


def _continue_in_force(args: argparse.Namespace) -> int:
    """--fe: the force-response curve at one f_e, from --pa-min to --pa-max."""
    _refuse(args, IN_F_ONLY, "--fe")
    for dest, option in IN_FORCE_ONLY.items():
        if getattr(args, dest) is None:
            args.parser.error(f"argument {option}: required with --fe")
    from ..continuation.force import continue_in_force

    try:
        result = continue_in_force(args.fe, args.pa_min, args.pa_max,
                                   model=ContactModel(model_parameters(args), FULL),
                                   period=args.period, steps_per_period=args.steps,
                                   quiet=args.quiet)
    except ValueError as error:  # e.g. --pa-max below --pa-min: before any work
        option_error(args.parser, error, OPTIONS)
    report(result, args, "plot_force_continuation")
    return _found(result)


def _refuse(args: argparse.Namespace, options: dict[str, str], given: str) -> None:
    """Exit 2 if any of ``options`` (those of the other kind of continuation) was given."""
    for dest, option in options.items():
        if getattr(args, dest) not in (None, False):
            args.parser.error(f"argument {option}: not with {given}")


def _found(result) -> int:
    """0, or 1 where no point was continued at all (no orbit to start from: said by each
    branch's message)."""
    return 0 if any(b.frequency_hz.size for b in result.branches) else 1


#: Frequencies of the series' response across the band (``--series``).
SERIES_POINTS = 301
#: The highest order --series takes: a bound, so that a typo does not start a derivation
#: that runs for minutes after the branch is done (`perturb derive --order 30`: 76 s).
MAX_SERIES_ORDER = 12


def _series(args: argparse.Namespace, parameters):
    """The order-N series across the band, each root with its stability; printed."""
    import numpy as np

    from perturb import frequency_response

    from ..comparison.root_stability import series_stability

    response = frequency_response(np.linspace(args.fmin, args.fmax, SERIES_POINTS),
                                  args.pa_frac, args.series, parameters=parameters,
                                  truncation=args.truncation)
    return series_stability(response)
