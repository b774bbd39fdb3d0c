"""Command line of the perturbation engine: ``python -m perturb {derive,backbone,response}``.

- ``derive --order N [--latex FILE] [--json FILE] [--pretty]``: the series of Eq. 2.6
  printed order by order (text on stdout).
- ``backbone --order N [--json FILE]``: omega/omega0 of the free undamped
  oscillator as exact coefficients of alpha = h a / omega0^2.
- ``response --order N --pa-frac F --fmin HZ --fmax HZ --points M [--json FILE]``:
  the analytic frequency response, all branches, with the validity flag.

Progress goes to stderr (``--quiet`` silences it); JSON keys are fixed by
issue 4 and documented in ``docs/perturb.md``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np

from ._backbone_series import backbone_series
from ._lindstedt import derive
from ._parameters import PAPER_BAND_HZ
from ._printing import latex_report, series_json, text_report
from ._response import frequency_response


def _progress(args: argparse.Namespace, message: str) -> None:
    if not args.quiet:
        print(message, file=sys.stderr, flush=True)


def _write_json(path: str, data: dict) -> None:
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(data, handle, indent=1)
        handle.write("\n")


def _derive(args: argparse.Namespace) -> None:
    start = time.perf_counter()
    _progress(args, f"deriving Eq. 2.6 to order {args.order} ...")
    series = derive(args.order)
    _progress(args, f"derived in {time.perf_counter() - start:.2f} s")
    print(text_report(series, pretty=args.pretty), end="")
    if args.latex:
        with open(args.latex, "w", encoding="utf-8") as handle:
            handle.write(latex_report(series))
        _progress(args, f"wrote {args.latex}")
    if args.json:
        _write_json(args.json, series_json(series))
        _progress(args, f"wrote {args.json}")


def _backbone(args: argparse.Namespace) -> None:
    start = time.perf_counter()
    series = backbone_series(args.order)
    _progress(args, f"backbone series to order {args.order} in {time.perf_counter() - start:.3f} s")
    print("omega/omega0 = sum_k c_k alpha^k, alpha = h a / omega0^2 (a: first-harmonic amplitude)")
    for k, q in enumerate(series.coefficients):
        print(f"  c_{k} = {q}")
    if args.json:
        data = {
            "order": series.order,
            "amplitude": "first-harmonic",
            "coefficients": series.as_strings(),
        }
        _write_json(args.json, data)
        _progress(args, f"wrote {args.json}")


def _response(args: argparse.Namespace) -> None:
    start = time.perf_counter()
    frequencies = np.linspace(args.fmin, args.fmax, args.points)
    _progress(args, f"response of order {args.order} at {args.points} frequencies ...")
    response = frequency_response(frequencies, args.pa_frac, args.order)
    _progress(args, f"done in {time.perf_counter() - start:.2f} s")
    print(response)
    for j, branch in enumerate(response.branches):
        best = (
            int(np.argmax(np.where(branch.valid, branch.app_m, -np.inf)))
            if branch.valid.any()
            else None
        )
        peak = (
            f"largest valid App {branch.app_m[best]:.4g} m at {branch.frequency_hz[best]:.6g} Hz"
            if best is not None
            else "no valid point"
        )
        counts = f"{branch.frequency_hz.size} points, {int(branch.valid.sum())} valid"
        print(f"  branch {j}: {counts}, {peak}")
    if args.json:
        _write_json(args.json, response.as_json())
        _progress(args, f"wrote {args.json}")


def _order(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"`--order` must be an integer >= 0, got {text!r}."
        ) from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"`--order` must be an integer >= 0, got {text!r}.")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m perturb", description=__doc__.splitlines()[0])
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    commands = parser.add_subparsers(dest="command", required=True)

    derive_cmd = commands.add_parser("derive", help="derive and print the series of Eq. 2.6")
    derive_cmd.add_argument("--order", type=_order, required=True)
    derive_cmd.add_argument("--latex", metavar="FILE")
    derive_cmd.add_argument("--json", metavar="FILE")
    derive_cmd.add_argument("--pretty", action="store_true", help="2-d unicode formulas")
    derive_cmd.set_defaults(run=_derive)

    backbone_cmd = commands.add_parser("backbone", help="backbone series omega/omega0(alpha)")
    backbone_cmd.add_argument("--order", type=_order, required=True)
    backbone_cmd.add_argument("--json", metavar="FILE")
    backbone_cmd.set_defaults(run=_backbone)

    response_cmd = commands.add_parser("response", help="analytic frequency response")
    response_cmd.add_argument("--order", type=_order, default=6)
    response_cmd.add_argument("--pa-frac", type=float, required=True)
    response_cmd.add_argument("--fmin", type=float, default=PAPER_BAND_HZ[0])
    response_cmd.add_argument("--fmax", type=float, default=PAPER_BAND_HZ[1])
    response_cmd.add_argument("--points", type=int, default=311)
    response_cmd.add_argument("--json", metavar="FILE")
    response_cmd.set_defaults(run=_response)
    for sub in (derive_cmd, backbone_cmd, response_cmd):
        # SUPPRESS: a --quiet given before the command is not reset here.
        sub.add_argument(
            "--quiet", action="store_true", default=argparse.SUPPRESS, help="no progress on stderr"
        )
    return parser


def _check_response(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    if not math.isfinite(args.pa_frac) or args.pa_frac < 0:
        parser.error(f"`--pa-frac` must be >= 0, got {args.pa_frac!r}.")
    if not (math.isfinite(args.fmin) and args.fmin > 0):
        parser.error(f"`--fmin` must be > 0, got {args.fmin!r}.")
    if not (math.isfinite(args.fmax) and args.fmax > args.fmin):
        parser.error(f"`--fmax` must be > `--fmin` ({args.fmin!r}), got {args.fmax!r}.")
    if args.points < 1:
        parser.error(f"`--points` must be >= 1, got {args.points!r}.")


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command == "response":
        _check_response(parser, args)
    args.run(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
