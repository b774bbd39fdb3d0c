"""`python -m numerics info`: the numbers of Eq. 2.6 for the paper's model."""

from __future__ import annotations

import argparse

from common import output_file, write_json

__all__ = ["add_info_parser", "format_info"]

_DESCRIPTIONS = {
    "y0_m": "static contact deflection y0",
    "f_n0_hz": "natural frequency f_n0 of the linearised system",
    "omega0_rad_s": "omega0 = 2 pi f_n0",
    "Q_n": "weight of the slider Q = M g",
    "c_per_s": "c of Eq. 2.6 (2c = S h_n y0^l / M)",
    "h_per_m_s2": "eps*h of Eq. 2.6 (quadratic stiffness over M)",
    "damping_ratio": "c / omega0",
    "G_per_P_a": "G / P_a of Eq. 2.6 (1 / M)",
}


def format_info(info: dict[str, float]) -> str:
    """One aligned line per number, with what it means."""
    return "\n".join(
        f"{key:<14} {value:>14.7g}   {_DESCRIPTIONS.get(key, '')}" for key, value in info.items()
    )


def add_info_parser(sub) -> None:
    parser = sub.add_parser("info", help="print the model's static and linear figures")
    parser.add_argument("--json", metavar="FILE", type=output_file,
                        help="also write them as JSON")
    parser.set_defaults(run=_info)


def _info(args: argparse.Namespace) -> int:
    from perturb import eq26_numbers

    info = eq26_numbers().as_dict()
    print(format_info(info))
    write_json(args.json, info)
    return 0
