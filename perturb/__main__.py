"""Command line of the perturbation engine: ``python -m perturb {derive,backbone,response}``.

- ``derive --order N [--latex FILE] [--json FILE] [--pretty | --steps]``: the series of
  the equation in contact printed order by order (text on stdout); with ``--steps`` the
  derivation study, step by step: Eq. 2.6's in the paper's names unless
  ``--truncation consistent`` asks for the contact's own, in the engine's names (text,
  and LaTeX with ``--latex``).
- ``backbone --order N [--app-m A [A ...]] [--json FILE]``: omega/omega0 of the free
  undamped oscillator as exact coefficients of alpha (a / y0; h a / omega0^2 for Eq. 2.6),
  and with ``--app-m`` the backbone's frequency at those peak-to-peak amplitudes.
- ``response --order N --pa-frac F --fmin HZ --fmax HZ --points M [--json FILE]``:
  the analytic frequency response, all branches, with the validity flag.

Each takes ``--truncation consistent|paper`` (every term of the contact's equation up
to the order, the default; or Eq. 2.6's) and ``--set NAME=VALUE`` (the contact).

Every option is checked by its argparse type before any work: a bad number, or
an output file that cannot be written (a folder, a missing folder, no
permission), exits with status 2 and names the option. Progress goes to stderr
(``--quiet`` silences it). JSON is strict and UTF-8 (``common.write_json``); the
``backbone`` and ``response`` files are result objects that ``common.load``
reads back. Their keys are documented in ``docs/perturb.md``.
"""

from __future__ import annotations

import argparse
import sys
import time
from functools import partial

import numpy as np

from perturb.common import (
    add_allow_slow,
    add_csv,
    add_version,
    describe,
    int_at_least,
    nonnegative_float,
    note,
    output_file,
    positive_float,
    program,
    progress,
    provenance,
    run_command,
    write_atomically,
    write_json,
    write_table,
)

from .model.parameters import PAPER_BAND_HZ
from .model.set_option import add_model_option, model_parameters
from .response.frequency import MAX_FREQUENCIES, frequency_response
from .series.slow_orders import check_slow_order
from .series.truncation import TRUNCATIONS

# derive and backbone import sympy in their commands: `response` with its order's
# kernels built needs none of it.

def _derive(args: argparse.Namespace) -> None:
    from .printing.derivation import derivation_latex, derivation_text
    from .printing.report import latex_report, series_json, text_report
    from .series.lindstedt import derive

    stages = []  # (stage, seconds): every stage that ran, timed on its own

    def timed(stage, work):
        start = time.perf_counter()
        out = work()
        stages.append((stage, time.perf_counter() - start))
        return out

    parameters = model_parameters(args)
    # The derivation study is the paper's (Eq. 2.6 in its names) unless told otherwise.
    truncation = args.truncation or ("paper" if args.steps else "consistent")
    # Derived, simplified and printed: the "derive" limits (``series.slow_orders``).
    check_slow_order(args.order, "derive", truncation, parameters, allow_slow=args.allow_slow)
    series = timed("derivation", lambda: derive(args.order, truncation, parameters))
    bar = progress(args.order + 1, "closed forms and text, order by order", quiet=args.quiet)
    if args.steps:  # the derivation study, in the paper's names
        report, latex_of = partial(derivation_text, series), derivation_latex
    else:
        report, latex_of = partial(text_report, series, pretty=args.pretty), latex_report
    text = timed("closed forms and text", lambda: report(each_order=bar.update))
    bar.close()
    if args.latex:  # the files first: a reader of stdout that goes away loses nothing
        latex = timed("LaTeX", lambda: latex_of(series))
        write_atomically(args.latex, latex)
    if args.json:
        timed("JSON", lambda: write_json(args.json,
                                         series_json(series) | {"provenance": provenance()}))
    print(text, end="")
    note("; ".join(f"{stage} {seconds:.2f} s" for stage, seconds in stages), quiet=args.quiet)


def _backbone(args: argparse.Namespace) -> None:
    from .series.free_backbone import backbone_series

    series = backbone_series(args.order, args.truncation, model_parameters(args),
                             allow_slow=args.allow_slow)
    note(f"backbone series to order {args.order} in {series.elapsed_s:.3f} s", quiet=args.quiet)
    data = series.as_dict()
    if args.app_m:
        frequency = series.frequency_at_app_hz(args.app_m)
        data |= {"app_m": list(args.app_m),
                 "frequency_hz": [float(f) if np.isfinite(f) else None for f in frequency]}
    if args.json:
        write_json(args.json, data | {"provenance": provenance()})
        note(f"wrote {args.json}", quiet=args.quiet)
    print(series)
    if args.app_m:
        for app, f in zip(args.app_m, frequency):
            shown = f"{f:.6f} Hz" if np.isfinite(f) else "no series orbit in contact has it"
            print(f"  App {app:.6g} m: {shown}")


def _response(args: argparse.Namespace) -> None:
    frequency_hz = np.linspace(args.fmin, args.fmax, args.points)
    check_slow_order(args.order, "response", args.truncation, model_parameters(args),
                     allow_slow=args.allow_slow)  # before the note of the work
    note(f"response of order {args.order} at {args.points} frequencies ...", quiet=args.quiet)
    response = frequency_response(frequency_hz, args.pa_frac, args.order,
                                  parameters=model_parameters(args), truncation=args.truncation,
                                  allow_slow=args.allow_slow)
    note(f"done in {response.elapsed_s:.2f} s", quiet=args.quiet)
    if args.json:
        response.to_json(args.json)
        note(f"wrote {args.json}", quiet=args.quiet)
    write_table(response, args)
    print(response)


#: What ``python -m perturb --help`` says the command line is.
DESCRIPTION = ("The perturbation series of the contact model from the command line: derived "
               "to any order and printed (text, LaTeX, JSON, or step by step in the paper's "
               "names), its backbone, and the analytic frequency response it predicts. Each "
               "subcommand's --help says more, with an example.")
#: One example of each subcommand, shown by its --help (a test parses each).
EXAMPLES = {
    "derive": "python -m perturb derive --order 4 --truncation paper --steps",
    "backbone": "python -m perturb backbone --order 6 --app-m 1e-7 2e-7",
    "response": "python -m perturb response --order 6 --pa-frac 0.05 --fmin 1300 --fmax 1500",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=program("perturb"), description=DESCRIPTION)
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    commands = parser.add_subparsers(dest="command", required=True)
    order = int_at_least(0)

    derive_cmd = commands.add_parser("derive", help="derive and print the perturbation series")
    derive_cmd.add_argument("--order", type=order, required=True,
                            help="order N of the series (the powers of eps up to N)")
    derive_cmd.add_argument("--latex", metavar="FILE", type=output_file,
                            help="also write the series as a LaTeX document")
    derive_cmd.add_argument("--json", metavar="FILE", type=output_file,
                            help="also write the series as JSON (-: to stdout)")
    layout = derive_cmd.add_mutually_exclusive_group()
    layout.add_argument("--pretty", action="store_true", help="2-d unicode formulas")
    layout.add_argument("--steps", action="store_true",
                        help="the derivation step by step: Eq. 2.6's in the paper's names "
                        "(Eq. 2.8-A.2), or with --truncation consistent the contact's own")
    derive_cmd.set_defaults(run=_derive)

    backbone_cmd = commands.add_parser("backbone", help="backbone series omega/omega0(alpha)")
    backbone_cmd.add_argument("--order", type=order, required=True,
                              help="order N of the backbone series")
    backbone_cmd.add_argument("--app-m", type=positive_float, nargs="+", metavar="A",
                              help="peak-to-peak amplitudes [m] at which to give the "
                              "backbone's frequency (App of the series orbit)")
    backbone_cmd.add_argument("--json", metavar="FILE", type=output_file,
                              help="also write the backbone as JSON (-: to stdout)")
    backbone_cmd.set_defaults(run=_backbone)

    response_cmd = commands.add_parser("response", help="analytic frequency response")
    response_cmd.add_argument("--order", type=order, default=6,
                              help="order N of the series (default: %(default)s)")
    response_cmd.add_argument("--pa-frac", type=nonnegative_float, required=True,
                              help="force amplitude P_a / Q")
    response_cmd.add_argument("--fmin", type=positive_float, default=PAPER_BAND_HZ[0],
                              help="lowest excitation frequency [Hz] (default: %(default)g)")
    response_cmd.add_argument("--fmax", type=positive_float, default=PAPER_BAND_HZ[1],
                              help="highest excitation frequency [Hz], above --fmin "
                              "(default: %(default)g)")
    response_cmd.add_argument("--points", type=int_at_least(1, MAX_FREQUENCIES), default=311,
                              help="frequencies from --fmin to --fmax (default: %(default)s)")
    response_cmd.add_argument("--json", metavar="FILE", type=output_file,
                              help="also write the response as JSON (-: to stdout)")
    add_csv(response_cmd)
    add_model_option(response_cmd)
    response_cmd.set_defaults(run=_response)
    for sub in (derive_cmd, backbone_cmd):
        add_model_option(sub)
    for sub in (derive_cmd, backbone_cmd, response_cmd):
        sub.add_argument("--truncation", choices=TRUNCATIONS,
                         default=None if sub is derive_cmd else "consistent",
                         help="consistent: every term k_j u^j, d_j u^j u' of the contact's "
                         "equation up to the order (the default"
                         + ("; derive --steps prints Eq. 2.6's derivation unless given "
                            "--truncation consistent"
                            if sub is derive_cmd else "") + "); paper: Eq. 2.6")
        add_allow_slow(sub)
        # SUPPRESS: a --quiet given before the command is not reset here.
        sub.add_argument(
            "--quiet", action="store_true", default=argparse.SUPPRESS, help="no progress on stderr"
        )
    describe(commands, EXAMPLES)
    for command in (parser, *commands.choices.values()):
        add_version(command)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "response" and not args.fmax > args.fmin:
        # Relates two options, so it cannot be a type: checked before any work.
        parser.error(f"argument --fmax: must be above --fmin ({args.fmin!r}), got {args.fmax!r}")
    return run_command(args)


if __name__ == "__main__":
    sys.exit(main())
