"""`python -m numerics atlas`: the attractor census over a grid of (f_e, P_a) (issue 13)."""

from __future__ import annotations

import argparse

from common import int_at_least, nonnegative_float, note, output_file
from perturb import PAPER_PANEL_FRACTIONS, ContactModel
from perturb._model_option import model_parameters

from ._steady import _accuracy_options, add_band_options, report

__all__ = ["add_atlas_parser"]

#: How long --scheduler waits for the dask scheduler to answer [s].
CONNECT_TIMEOUT_S = 10


def add_atlas_parser(sub) -> None:
    parser = sub.add_parser("atlas", help="number of coexisting attractors over a grid of "
                            "(f_e, P_a), in worker processes or on a dask cluster (issue 13)")
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
    parser.add_argument("--plot", metavar="FILE.png", type=output_file,
                        help="the map of the number of attractors per cell")
    _accuracy_options(parser)
    parser.set_defaults(run=_atlas, parser=parser)


def _atlas(args: argparse.Namespace) -> int:
    _check_axes(args)
    from .._atlas import atlas

    model = ContactModel(model_parameters(args))
    with _executor(args) as executor:
        try:
            result = atlas(args.fmin, args.fmax, args.pa_min, args.pa_max, grid=tuple(args.grid),
                           executor=executor, workers=args.workers, model=model,
                           steps_per_period=args.steps, tol=args.tol, quiet=args.quiet)
        except ValueError as error:  # e.g. more lanes than the limit: before any work
            args.parser.error(str(error))
    report(result, args, "plot_atlas")
    # Cells whose task failed are in the output, with the task's message; say so.
    return 1 if (result.status != 0).any() else 0


def _check_axes(args: argparse.Namespace) -> None:
    """Each axis's ends in order, or equal with one point on it (else exit 2)."""
    for low, high, points in (("fmin", "fmax", args.grid[0]), ("pa_min", "pa_max", args.grid[1])):
        ends = getattr(args, low), getattr(args, high)
        names = [f"--{name.replace('_', '-')}" for name in (low, high)]
        if points == 1 and ends[0] != ends[1]:
            args.parser.error(f"argument {names[1]}: must equal {names[0]} with one point on "
                              f"its axis of --grid, got {ends[0]} and {ends[1]}")
        if points > 1 and not ends[0] < ends[1]:
            args.parser.error(f"argument {names[1]}: must be above {names[0]}, got {ends[0]} "
                              f"and {ends[1]}")


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
