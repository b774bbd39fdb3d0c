"""`python -m numerics sweep` and `python -m numerics attractors`."""

from __future__ import annotations

import argparse

import numpy as np

from perturb import PAPER_BAND_HZ, PAPER_PANEL_FRACTIONS, ContactModel
from perturb.common import (
    add_csv,
    add_unchecked,
    int_at_least,
    nonnegative_float,
    note,
    output_file,
    plot_file,
    positive_float,
    write_table,
)
from perturb.model.set_option import add_model_option, model_parameters

from ..steady.census import attractor_census
from ..steady.options import MAX_STEPS
from ..steady.shooting import DEFAULTS
from ..steady.sweeps import DIRECTIONS, MAX_STATES, sweep

__all__ = ["add_sweep_parser", "add_attractors_parser"]


def walk_steps_option(text: str) -> int | str:
    """--steps of a walk (continue, folds): "auto" or an integer from 4 to MAX_STEPS (2^20:
    at the paper's contact a continuation at that N holds 240 MB, tests/benchmarks/
    bench_limits.py)."""
    return "auto" if text == "auto" else int_at_least(
        4, MAX_STEPS, "the steps bound of every command, 2^20")(text)


#: The largest --steps of a steady state: its refinements double the steps up to MAX_STEPS.
MAX_STEADY_STEPS = MAX_STEPS // 2 ** DEFAULTS["refinements"]


def _steady_steps(text: str) -> int | str:
    """--steps of sweep and attractors: "auto" or an integer from 4 to MAX_STEADY_STEPS."""
    return "auto" if text == "auto" else int_at_least(
        4, MAX_STEADY_STEPS, f"each of its {DEFAULTS['refinements']} refinements doubles it, "
        f"up to the steps bound of every command, 2^20")(text)


def accuracy_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--steps", type=_steady_steps, default=DEFAULTS["steps_per_period"],
                        help=f"RK4 steps per period, an integer from 4 to {MAX_STEADY_STEPS} "
                        "or 'auto' (at least 128, more at low f_e; the default)")
    parser.add_argument("--tol", type=positive_float, default=DEFAULTS["tol"],
                        help="relative settling tolerance (default %(default)s)")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write the result as JSON "
                        "(-: to stdout, other lines to stderr)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_unchecked(parser)
    add_model_option(parser)


def add_sweep_parser(sub) -> None:
    parser = sub.add_parser("sweep", help="steady states swept up/down in f_e (Fig. 2, 3)")
    parser.add_argument("--pa-frac", type=nonnegative_float, nargs="+",
                        default=list(PAPER_PANEL_FRACTIONS),
                        help="force amplitudes P_a / Q (default: the paper's ten)")
    add_band_options(parser)
    parser.add_argument("--points", type=int_at_least(2, MAX_STATES, "the most steady states "
                                                      "of one sweep, 1.1 GB at the limit"),
                        default=311, help="frequencies from --fmin to --fmax, evenly spaced "
                        "(default: %(default)s: 5 Hz steps over the paper's band)")
    parser.add_argument("--direction", choices=DIRECTIONS, default="both",
                        help="sweep up, down or both ways (default: %(default)s)")
    parser.add_argument("--plot", metavar="FILE.png", type=plot_file,
                        help="Fig. 2 there, and Fig. 3 beside it (FILE-extrema.png)")
    accuracy_options(parser)
    add_csv(parser)
    parser.set_defaults(run=_sweep, parser=parser)


def add_band_options(parser: argparse.ArgumentParser) -> None:
    """--fmin and --fmax, the paper's band by default (``check_band`` relates them)."""
    parser.add_argument("--fmin", type=positive_float, default=PAPER_BAND_HZ[0],
                        help=f"lowest f_e [Hz] (default: {PAPER_BAND_HZ[0]:g}, the paper's band)")
    parser.add_argument("--fmax", type=positive_float, default=PAPER_BAND_HZ[1],
                        help=f"highest f_e [Hz], above --fmin (default: {PAPER_BAND_HZ[1]:g})")


def check_band(args: argparse.Namespace) -> None:
    """--fmax above --fmin, or exit 2 (two options: no argparse type can check it)."""
    if not args.fmin < args.fmax:
        args.parser.error(f"argument --fmax: must be above --fmin, got {args.fmin} and "
                          f"{args.fmax}")


def report(result, args: argparse.Namespace, plot: str) -> None:
    """A command's result: to ``--json`` if asked, printed, and drawn to ``--plot`` by
    ``numerics.plots.<plot>`` if asked."""
    if args.json:
        result.to_json(args.json)
    write_table(result, args)
    print(result)
    if args.plot:
        from .. import plots

        getattr(plots, plot)(result, args.plot)


def _sweep(args: argparse.Namespace) -> int:
    check_band(args)
    if args.plot:  # Fig. 3 goes beside Fig. 2: that file must be writable too
        try:
            output_file(_extrema_path(args.plot))
        except argparse.ArgumentTypeError as error:
            args.parser.error(f"argument --plot: Fig. 3 goes to {_extrema_path(args.plot)!r}: "
                              f"{error}")
    states = args.points * len(args.pa_frac) * (2 if args.direction == "both" else 1)
    if states > MAX_STATES:
        args.parser.error(f"--points x --pa-frac x directions asks for {states} steady states, "
                          f"more than the limit of {MAX_STATES} (1.1 GB at the limit); "
                          f"split the band")
    model = ContactModel(model_parameters(args))
    result = sweep(np.linspace(args.fmin, args.fmax, args.points), args.pa_frac,
                   direction=args.direction, model=model, steps_per_period=args.steps,
                   tol=args.tol, quiet=args.quiet, unchecked=args.unchecked)
    if args.json:
        result.to_json(args.json)
    write_table(result, args)
    print(result)
    if args.plot:
        from ..plots import plot_app, plot_extrema

        plot_app(result, args.plot)
        plot_extrema(result, _extrema_path(args.plot))
    return 0


def _extrema_path(plot: str) -> str:
    """Where Fig. 3 goes: beside Fig. 2, FILE-extrema.png."""
    stem = plot[:-4] if plot.endswith(".png") else plot
    return f"{stem}-extrema.png"


def add_attractors_parser(sub) -> None:
    parser = sub.add_parser("attractors", help="coexisting steady states at one (P_a, f_e)")
    parser.add_argument("--pa-frac", type=nonnegative_float, required=True, help="P_a / Q")
    parser.add_argument("--fe", type=positive_float, required=True, help="f_e [Hz]")
    accuracy_options(parser)
    add_csv(parser)
    parser.set_defaults(run=_attractors, parser=parser)


def _attractors(args: argparse.Namespace) -> int:
    model = ContactModel(model_parameters(args))
    note(f"attractors at {args.fe} Hz, {args.pa_frac} Q ...", quiet=args.quiet)
    census = attractor_census(args.fe, args.pa_frac, model=model, steps_per_period=args.steps,
                        tol=args.tol, unchecked=args.unchecked)
    if args.json:
        census.to_json(args.json)
    write_table(census, args)
    print(census)
    return 0
