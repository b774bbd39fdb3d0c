"""The exact backbone: frequency against A_pp and against a1."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from matplotlib.figure import Figure

from ._figure import finish, fixed_layout, new_figure

if TYPE_CHECKING:  # the exact backbone imports scipy.optimize: not for every figure
    from .._backbone import Backbone

__all__ = ["plot_backbone"]

#: The margins [in] (``fixed_layout``), as constrained layout placed them (2026-11-23):
#: on the right, room for the last x tick label; the title above; the labels below.
_MARGINS_IN = {"right": 0.134, "top": 0.252, "bottom": 0.501}


def plot_backbone(backbone: Backbone, path: str | Path | None = None) -> Figure:
    """Frequency of free oscillation against amplitude, A_pp and a1, log scale.

    Examples
    --------
    >>> from numerics import exact_backbone
    >>> figure = plot_backbone(exact_backbone(points=50))
    >>> figure.axes[0].get_xlabel()
    'amplitude [nm]'
    """
    figure, ax = new_figure(layout=None)
    ax.semilogx(backbone.app_m * 1e9, backbone.frequency_hz, label="peak-to-peak $A_{pp}$")
    ax.semilogx(backbone.a1_m * 1e9, backbone.frequency_hz, "--", label="fundamental $a_1$")
    ax.axhline(backbone.f_n0_hz, color="0.6", lw=0.8)
    ax.axvline(backbone.contact_loss_app_m * 1e9, color="0.3", lw=0.8, ls=":",
               label="contact lost ($A_{pp}$)")
    ax.set_xlabel("amplitude [nm]")
    ax.set_ylabel("frequency of free oscillation [Hz]")
    ax.set_title("Exact backbone of the conservative model")
    ax.legend(loc="lower left")
    fixed_layout(figure, [[ax]], **_MARGINS_IN)
    return finish(figure, path)
