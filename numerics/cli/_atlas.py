"""`python -m numerics atlas`: the attractor census over a grid of (f_e, P_a)."""

from __future__ import annotations

import argparse

from perturb import PAPER_PANEL_FRACTIONS, ContactModel
from perturb.common import add_csv, int_at_least, nonnegative_float, note, plot_file
from perturb.model.set_option import model_parameters

from ._errors import option_error
from ._steady import accuracy_options, add_band_options, report

__all__ = ["add_atlas_parser"]

#: How long --scheduler waits for the dask scheduler to answer [s].
CONNECT_TIMEOUT_S = 10


def add_atlas_parser(sub) -> None:
    parser = sub.add_parser("atlas", help="number of coexisting attractors over a grid of "
                            "(f_e, P_a), in worker processes or on a dask cluster")
    add_band_options(parser)
    parser.add_argument("--pa-min", type=nonnegative_float, default=min(PAPER_PANEL_FRACTIONS),
                        help="least P_a / Q (default %(default)s)")
    parser.add_argument("--pa-max", type=nonnegative_float, default=max(PAPER_PANEL_FRACTIONS),
                        help="largest P_a / Q (default %(default)s)")
    parser.add_argument("--grid", type=int_at_least(1), nargs=2, required=True,
                        metavar=("NF", "NP"), help="frequencies and amplitudes, ends included")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int_at_least(1),
                       help="worker processes on this machine (default: one per processor)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the tasks on the dask.distributed scheduler at ADDRESS "
                       "(e.g. tcp://host:8786; needs `pip install .[distributed]`)")
    parser.add_argument("--plot", metavar="FILE.png", type=plot_file,
                        help="the map of the number of attractors per cell")
    accuracy_options(parser)
    add_csv(parser)
    parser.set_defaults(run=_atlas, parser=parser)


#: The library's arguments as this command's options, for its error messages.
OPTIONS = {"fmin_hz": "--fmin", "fmax_hz": "--fmax", "pa_min": "--pa-min",
           "pa_max": "--pa-max", "grid": "--grid", "workers": "--workers",
           "steps_per_period": "--steps", "tol": "--tol"}


def _atlas(args: argparse.Namespace) -> int:
    from ..steady.multistability import atlas, check_axes

    try:  # the axes before connecting to a scheduler
        check_axes(args.fmin, args.fmax, args.pa_min, args.pa_max, args.grid)
    except ValueError as error:
        option_error(args.parser, error, OPTIONS)
    model = ContactModel(model_parameters(args))
    with _executor(args) as executor:
        try:
            result = atlas(args.fmin, args.fmax, args.pa_min, args.pa_max, grid=tuple(args.grid),
                           executor=executor, workers=args.workers, model=model,
                           steps_per_period=args.steps, tol=args.tol, quiet=args.quiet,
                           unchecked=args.unchecked)
        except ValueError as error:  # e.g. more lanes than the limit: before any work
            option_error(args.parser, error, OPTIONS)
    report(result, args, "plot_atlas")
    # Cells whose task failed are in the output, with the task's message; say so.
    return 1 if (result.status != 0).any() else 0


class _executor:
    """The dask client's executor for --scheduler (closed at the end), else None."""

    def __init__(self, args: argparse.Namespace) -> None:
        self.args, self.client = args, None

    def __enter__(self):
        if self.args.scheduler is None:
            return None
        try:
            from dask.distributed import Client
        except ImportError:
            self.args.parser.error("argument --scheduler: needs dask.distributed "
                                   "(pip install '.[distributed]')")
        note(f"connecting to {self.args.scheduler} ...", quiet=self.args.quiet)
        try:
            self.client = Client(self.args.scheduler, timeout=CONNECT_TIMEOUT_S)
        except (OSError, ValueError) as error:
            self.args.parser.error(f"argument --scheduler: cannot connect to "
                                   f"{self.args.scheduler!r}: {error}")
        return self.client.get_executor()

    def __exit__(self, *exc) -> None:
        if self.client is not None:
            self.client.close()
