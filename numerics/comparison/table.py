"""The comparison as `python -m numerics compare` prints it."""

from __future__ import annotations

import numpy as np

from .study import Comparison

__all__ = ["format_comparison"]


def _error(value: float) -> str:
    return "-" if np.isnan(value) else f"{value:.1e}"


def _backbone_lines(c: Comparison) -> list[str]:
    b = c.backbone
    lines = [
        f"Backbone: series of order N against the exact backbone (contact lost above "
        f"A_pp = {b.contact_loss_app_m * 1e9:.1f} nm)",
        f"  limit: up to where |f_series/f_exact - 1| first exceeds {b.tolerance:g}, capped"
        " at contact loss (*);",
        "  crossing: where it first exceeds it, contact or not (past contact loss the",
        "  error of orders 4 and up changes sign: the series does not hold there)",
        f"{'order':>6}{'a1 limit [nm]':>15}{'A_pp limit [nm]':>17}{'A_pp crossing [nm]':>20}",
    ]
    for n, a1, app, cross, capped in zip(b.orders, b.limit_a1_m, b.limit_app_m,
                                          b.crossing_app_m, b.capped):
        mark = "*" if capped else " "
        lines.append(f"{n:>6}{a1 * 1e9:>15.1f}{app * 1e9:>16.1f}{mark}{cross * 1e9:>20.1f}")
    return lines


def _response_lines(c: Comparison) -> list[str]:
    head = "".join(f"{f'P_a={p:.2f}Q':>30}" for p in c.pa_frac)
    lines = [
        "Response: largest |App_series/App_RK4 - 1| where the series is valid "
        "(matched / settled states)",
        "  +N: N states with no valid series response within 10 % (the series' fold is",
        "  elsewhere, or it lacks the branch); they count in the largest error, and",
        "  [x] is the largest over the matched states alone",
        f"{'order':>6}{'RK4 model':>10}{head}",
    ]
    for n in c.orders:
        for model in ("eq26", "full"):
            cells = ""
            for p in c.pa_frac:
                r = c.response(model, p, n)
                cell = f"{_error(r.largest_error)} ({r.matched.sum()}/{r.relative_error.size}"
                if r.unmatched.any():
                    cell += f"+{r.unmatched.sum()}) [{_error(r.largest_matched_error)}]"
                else:
                    cell += ")"
                cells += f"{cell:>30}"
            lines.append(f"{n:>6}{model:>10}{cells}")
    return lines


def _peak_lines(c: Comparison) -> list[str]:
    n = max(c.orders)
    lines = [f"Peaks near f_n0/k: place [Hz] and height A_pp [nm], RK4 against order {n}"]
    lines.append(f"{'k':>3}{'P_a/Q':>7}{'RK4 Eq. 2.6':>18}{'RK4 full':>18}{'series (valid)':>18}")
    for p in c.pa_frac:
        eq26, full = c.response("eq26", p, n), c.response("full", p, n)
        for a, b in zip(eq26.peaks, full.peaks):
            cells = [(a.rk4_hz, a.rk4_app_m), (b.rk4_hz, b.rk4_app_m),
                     (a.series_hz, a.series_app_m)]
            text = "".join(
                f"{'-':>18}" if np.isnan(f) else f"{f'{f:.0f} Hz {h * 1e9:.1f}':>18}"
                for f, h in cells
            )
            lines.append(f"{a.k:>3}{p:>7.2f}{text}")
    return lines


def _parting_lines(c: Comparison) -> list[str]:
    lines = [f"RK4 full model against RK4 Eq. 2.6 (App differing by more than {c.tolerance:g})"]
    for p in c.pa_frac:
        d = c.parting(p)
        where = d["in_contact_hz"]
        span = f" ({where[0]:.0f}-{where[-1]:.0f} Hz, the damping law)" if where else ""
        lines.append(
            f"  P_a = {p:.2f} Q: {d['differ']} of {d['states']} states: "
            f"{d['differ_with_contact_loss']} with contact loss, "
            f"{d['differ_in_contact']} in contact{span}"
        )
    return lines


def format_comparison(comparison: Comparison) -> str:
    """The four tables: backbone limits, response errors, peaks, model parting.

    Examples
    --------
    >>> from numerics.comparison.study import compare
    >>> result = compare((4, 6), 0.05, frequency_hz=np.arange(700.0, 800.0, 5.0))
    >>> print(format_comparison(result).splitlines()[5])
         4          193.9           390.0*               540.1
    """
    blocks = [_backbone_lines(comparison), _response_lines(comparison),
              _peak_lines(comparison), _parting_lines(comparison)]
    notes = [f"note: {note}" for curve in comparison.curves for note in curve.notes]
    return "\n\n".join("\n".join(block) for block in blocks + ([notes] if notes else []))
