"""The series against the exact backbone and against RK4 steady states."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from perturb import ContactModel

from ..backbone.exact import Backbone, exact_backbone
from ..comparison.study import Comparison
from .figure import finish, fixed_layout, on_panels, panel_title

__all__ = ["plot_comparison"]

#: The panels' margins [in] (``fixed_layout``), as constrained layout placed them
#: (2026-11-23): room for the last x tick label, a title above each panel, the x tick
#: labels and label below each.
_MARGINS_IN = {"right": 0.115, "top": 0.252, "bottom": 0.473, "row_gap": 0.767}


def _backbone_errors(ax, comparison: Comparison) -> None:
    b = comparison.backbone
    for n, error in zip(b.orders, b.relative_error):
        ax.loglog(b.app_m * 1e9, np.maximum(error, 1e-17), label=f"order {n}")
    ax.axhline(b.tolerance, color="0.5", lw=0.8, ls="--")
    ax.axvline(b.contact_loss_app_m * 1e9, color="0.3", lw=0.8, ls=":", label="contact lost")
    ax.set_xlabel("$A_{pp}$ of the free oscillation [nm]")
    ax.set_ylabel("|f_series / f_exact - 1|")
    panel_title(ax, "Backbone series against the exact backbone")
    ax.legend(fontsize="small")


def _app_range(curves) -> tuple[float, float] | None:
    """(least, largest) A_pp [m] of RK4 curves (finite, > 0), or None if there is none."""
    app = np.concatenate([np.ravel(c.app_m).astype(float) for c in curves] or [np.empty(0)])
    app = app[np.isfinite(app) & (app > 0)]
    return (float(app.min()), float(app.max())) if app.size else None


def _shown_app_range(comparison: Comparison) -> tuple[float, float] | None:
    """(least, largest) A_pp [m] of the RK4 curves the response panels show."""
    return _app_range(comparison.curves)


def _within(backbone: Backbone, shown: tuple[float, float]) -> slice:
    """The levels of ``backbone`` that span ``shown`` (one more on each side)."""
    inside = np.flatnonzero((backbone.app_m >= shown[0]) & (backbone.app_m <= shown[1]))
    if inside.size == 0:
        first = int(np.searchsorted(backbone.app_m, shown[0]))
        return slice(max(first - 1, 0), first + 1)
    return slice(max(inside[0] - 1, 0), inside[-1] + 2)


def _covering_backbone(comparison: Comparison, backbone: Backbone | None) -> Backbone | None:
    """The exact backbone over the whole A_pp range of the curves shown (computed if not given)."""
    shown = _shown_app_range(comparison)
    if shown is None:
        return backbone
    if backbone is None:
        lo, hi = shown
        if hi <= lo:
            hi = lo * (1 + 1e-9)
        model = ContactModel.from_dict(comparison.backbone.model)
        return exact_backbone(app_range_m=(lo, hi), model=model, points=300)
    covered = (backbone.app_m.min() <= shown[0] * (1 + 1e-9)
               and backbone.app_m.max() >= shown[1] * (1 - 1e-9))
    if not covered:
        raise ValueError(
            f"`backbone` must cover the A_pp of the curves shown, {shown[0]:.4g}..{shown[1]:.4g} "
            f"m; it covers {backbone.app_m.min():.4g}..{backbone.app_m.max():.4g} m "
            "(use exact_backbone(app_range_m=...))."
        )
    return backbone


def _responses(ax, comparison: Comparison, pa_frac: float, backbone: Backbone | None) -> None:
    order = max(comparison.orders)
    frequencies, curves = [], []
    for model, style in (("full", dict(color="k", ms=2.5)), ("eq26", dict(color="C1", ms=1.5))):
        curve = comparison.curve(model, pa_frac)
        ax.semilogy(curve.frequency_hz, curve.app_m * 1e9, ".", label=f"RK4 {model}", **style)
        frequencies.append(np.asarray(curve.frequency_hz, dtype=float))
        curves.append(curve)
    r = comparison.response("eq26", pa_frac, order)
    ax.semilogy(r.frequency_hz, r.series_app_m * 1e9, "o", mfc="none", color="C0", ms=4,
                label=f"series order {order} (valid)")
    shown = _app_range(curves)
    if backbone is not None and shown is not None:
        # Over this panel's A_pp range: the bent peak and its bouncing branches.
        part = _within(backbone, shown)
        ax.semilogy(backbone.frequency_hz[part], backbone.app_m[part] * 1e9, "-", color="0.45",
                    lw=0.9, label="exact backbone")
        band = np.concatenate(frequencies)
        band = band[np.isfinite(band)]
        if band.size:
            pad = 0.02 * (band.max() - band.min()) or 1.0
            ax.set_xlim(band.min() - pad, band.max() + pad)
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("$A_{pp}$ [nm]")
    panel_title(ax, f"$P_a$ = {pa_frac:.2f} Q")
    ax.legend(fontsize="small")


def plot_comparison(comparison: Comparison, path: str | Path | None = None, *,
                    backbone: Backbone | None = None, ax=None) -> Figure:
    """Backbone errors by order, and A_pp against f_e per P_a: RK4 of both models, series.

    Each response panel also draws the exact backbone (free oscillation) over
    the whole A_pp range of the RK4 curves shown, bouncing branches included.

    Parameters
    ----------
    comparison : Comparison
        What ``compare`` returned (or ``common.load`` read back).
    path : str or Path, optional
        Where to save the figure.
    backbone : Backbone, optional
        The exact backbone to draw; it must cover the A_pp range of the curves
        shown. By default it is computed for that range
        (``exact_backbone(app_range_m=...)``, 300 levels, about 0.1 s).
    ax : sequence of axes, optional
        The caller's axes to draw on, laid out by the caller: the backbone errors'
        panel, then one per P_a.

    Examples
    --------
    >>> from numerics import compare
    >>> result = compare((4,), 0.05, frequency_hz=np.arange(700.0, 800.0, 10.0))
    >>> figure = plot_comparison(result)
    >>> len(figure.axes), [line.get_label() for line in figure.axes[1].lines][-1]
    (2, 'exact backbone')
    """
    panels = 1 + len(comparison.pa_frac)
    backbone = _covering_backbone(comparison, backbone)
    given = on_panels(ax, panels, "panel (the backbone errors, then each P_a)")
    if given is not None:
        figure, grid = given
    else:
        figure = Figure(figsize=(6.0 * min(panels, 2), 4.2 * ((panels + 1) // 2)))
        grid = figure.subplots((panels + 1) // 2, min(panels, 2), squeeze=False)
    axes = grid.ravel()
    _backbone_errors(axes[0], comparison)
    for ax, pa_frac in zip(axes[1:], comparison.pa_frac):
        _responses(ax, comparison, pa_frac, backbone)
    for extra in axes[panels:]:
        extra.set_visible(False)
    if given is None:
        fixed_layout(figure, grid, **_MARGINS_IN)
    return finish(figure, path)
