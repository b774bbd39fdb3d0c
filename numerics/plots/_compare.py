"""The series against the exact backbone and against RK4 steady states."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .._compare import Comparison
from ._figure import finish

__all__ = ["plot_comparison"]


def _backbone_errors(ax, comparison: Comparison) -> None:
    b = comparison.backbone
    for n, error in zip(b.orders, b.error):
        ax.loglog(b.app_m * 1e9, np.maximum(error, 1e-17), label=f"order {n}")
    ax.axhline(b.tolerance, color="0.5", lw=0.8, ls="--")
    ax.axvline(b.contact_loss_app_m * 1e9, color="0.3", lw=0.8, ls=":", label="contact lost")
    ax.set_xlabel("$A_{pp}$ of the free oscillation [nm]")
    ax.set_ylabel("|f_series / f_exact - 1|")
    ax.set_title("Backbone series against the exact backbone")
    ax.legend(fontsize="small")


def _responses(ax, comparison: Comparison, pa_frac: float) -> None:
    order = max(comparison.orders)
    for model, style in (("full", dict(color="k", ms=2.5)), ("eq26", dict(color="C1", ms=1.5))):
        curve = comparison.curve(model, pa_frac)
        ax.semilogy(curve.frequency_hz, curve.app_m * 1e9, ".", label=f"RK4 {model}", **style)
    r = comparison.response("eq26", pa_frac, order)
    ax.semilogy(r.frequency_hz, r.series_app_m * 1e9, "o", mfc="none", color="C0", ms=4,
                label=f"series order {order} (valid)")
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("$A_{pp}$ [nm]")
    ax.set_title(f"$P_a$ = {pa_frac:.2f} Q")
    ax.legend(fontsize="small")


def plot_comparison(comparison: Comparison, path: str | Path | None = None) -> Figure:
    """Backbone errors by order, and App against f_e per P_a: RK4 of both models, series.

    Examples
    --------
    >>> from numerics._compare import compare
    >>> result = compare((4,), (0.05,), frequencies_hz=np.arange(700.0, 800.0, 10.0))
    >>> len(plot_comparison(result).axes)
    2
    """
    panels = 1 + len(comparison.pa_fracs)
    figure = Figure(figsize=(6.0 * min(panels, 2), 4.2 * ((panels + 1) // 2)),
                    layout="constrained")
    axes = figure.subplots((panels + 1) // 2, min(panels, 2), squeeze=False).ravel()
    _backbone_errors(axes[0], comparison)
    for ax, pa_frac in zip(axes[1:], comparison.pa_fracs):
        _responses(ax, comparison, pa_frac)
    for ax in axes[panels:]:
        ax.set_visible(False)
    return finish(figure, path)
