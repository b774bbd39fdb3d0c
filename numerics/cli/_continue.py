"""`python -m numerics continue`: periodic orbits continued in f_e at one P_a (issue 13)."""

from __future__ import annotations

import argparse
from pathlib import Path

from common import int_at_least, output_file, positive_float
from perturb import EQ_2_6, FULL, ContactModel
from perturb._model_option import add_model_option, model_parameters

from ._steady import _steps, add_band_options, check_band

__all__ = ["add_continue_parser"]


def add_continue_parser(sub) -> None:
    parser = sub.add_parser("continue", help="periodic orbits continued in f_e through their "
                            "folds, with stability (issue 13)")
    parser.add_argument("--pa-frac", type=positive_float, required=True, help="P_a / Q")
    add_band_options(parser)
    parser.add_argument("--period", type=int_at_least(1, 8), default=1,
                        help="p of the orbit continued (default 1)")
    parser.add_argument("--steps", type=_steps, default="auto",
                        help="RK4 steps per period, fixed along the branch: an integer >= 4 "
                        "or 'auto' (the default: at least 512)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON")
    parser.add_argument("--plot", metavar="FILE.png", type=output_file,
                        help="App against f_e: stable solid, unstable dashed, bifurcations "
                        "marked")
    parser.add_argument("--series", metavar="N", type=int_at_least(0, MAX_SERIES_ORDER),
                        help="also the order-N perturbation series (N <= "
                        f"{MAX_SERIES_ORDER}), each root with the stability of the orbit it "
                        "describes (issue 13, item 3); the branch continued is then the "
                        "series' own model, Eq. 2.6, --plot draws the series over it, and "
                        "--json FILE writes the series' stability to FILE-series.json too")
    parser.add_argument("--switch", action="store_true",
                        help="also continue the branch of period 2p born at each period "
                        "doubling found (branch switching)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_model_option(parser)
    parser.set_defaults(run=_continue, parser=parser)


def _continue(args: argparse.Namespace) -> int:
    check_band(args)
    from .._continuation import continue_orbits

    parameters = model_parameters(args)
    model = ContactModel(parameters, FULL if args.series is None else EQ_2_6)
    try:
        # The series first: it is quick, and a value it refuses stops before the branch.
        stability = None if args.series is None else _series(args, parameters)
        result = continue_orbits(args.pa_frac, args.fmin, args.fmax, model=model,
                                 period=args.period, steps_per_period=args.steps,
                                 quiet=args.quiet)
        if args.switch:
            from .._branch_switch import with_doubled_branches

            result = with_doubled_branches(result, quiet=args.quiet)
    except ValueError as error:  # e.g. a band out of the model's reach: before any work
        args.parser.error(str(error))
    if args.json:
        result.to_json(args.json)
        if stability is not None:
            stability.to_json(Path(args.json).with_name(Path(args.json).stem + "-series.json"))
    print(result)
    if stability is not None:
        print(stability)
    if args.plot:
        from ..plots import plot_continuation, plot_series_stability

        if stability is None:
            plot_continuation(result, args.plot)
        else:
            plot_series_stability(stability, result, args.plot)
    # No point continued at all (no orbit to start from): said by each branch's message.
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

    from .._series_stability import series_stability

    response = frequency_response(np.linspace(args.fmin, args.fmax, SERIES_POINTS),
                                  args.pa_frac, args.series, parameters=parameters)
    return series_stability(response)
