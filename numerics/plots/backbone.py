"""The exact backbone: frequency against A_pp and against a1."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from .figure import finish, fixed_layout, on_axes

if TYPE_CHECKING:  # the exact backbone imports scipy.optimize: not for every figure
    from ..backbone.exact import Backbone

__all__ = ["plot_backbone", "plot_backbone_truncations"]

#: The margins [in] (``fixed_layout``), as constrained layout placed them (2026-11-23):
#: on the right, room for the last x tick label; the title above; the labels below.
_MARGINS_IN = {"right": 0.134, "top": 0.252, "bottom": 0.501}


def plot_backbone(backbone: Backbone, path: str | Path | None = None, *, ax=None) -> Figure:
    """Frequency of free oscillation against amplitude, A_pp and a1, log scale.

    Examples
    --------
    >>> from numerics import exact_backbone
    >>> figure = plot_backbone(exact_backbone(points=50))
    >>> figure.axes[0].get_xlabel()
    'amplitude [nm]'
    """
    own = ax is None
    figure, ax = on_axes(ax, layout=None)
    ax.semilogx(backbone.app_m * 1e9, backbone.frequency_hz, label="peak-to-peak $A_{pp}$")
    ax.semilogx(backbone.a1_m * 1e9, backbone.frequency_hz, "--", label="fundamental $a_1$")
    ax.axhline(backbone.f_n0_hz, color="0.6", lw=0.8)
    ax.axvline(backbone.contact_loss_app_m * 1e9, color="0.3", lw=0.8, ls=":",
               label="contact lost ($A_{pp}$)")
    ax.set_xlabel("amplitude [nm]")
    ax.set_ylabel("frequency of free oscillation [Hz]")
    ax.set_title("Exact backbone of the conservative model")
    ax.legend(loc="lower left")
    if own:  # a caller's figure is laid out by the caller
        fixed_layout(figure, [[ax]], **_MARGINS_IN)
    return finish(figure, path)


def plot_backbone_truncations(rows, path: str | Path | None = None, *, ax=None) -> Figure:
    """The exact backbone of each contact beside its consistent and Eq. 2.6 series.

    ``rows`` holds ``(backbone, consistent, paper)`` per contact: the exact ``Backbone``
    and two ``perturb.BackboneSeries`` (``truncation`` "consistent" and "paper") of its
    model. Each series is drawn at the exact backbone's fundamental amplitudes a1,
    against its A_pp: the frequency drop f - f_n0, which the paper's truncation gets
    right only for m2 = 2.

    Examples
    --------
    >>> import numpy as np
    >>> from numerics import exact_backbone
    >>> from perturb import backbone_series
    >>> exact = exact_backbone(np.geomspace(1e-9, 1e-7, 20))
    >>> figure = plot_backbone_truncations([(exact, backbone_series(4),
    ...                                      backbone_series(4, "paper"))])
    >>> figure.axes[0].get_ylabel()
    '$f - f_{n0}$ [Hz]'
    """
    own = ax is None
    figure, ax = on_axes(ax, layout=None)
    for i, (exact, consistent, paper) in enumerate(rows):
        color = f"C{i}"
        m2 = exact.model["parameters"]["m2"]
        kept = ~np.asarray(exact.contact_lost, dtype=bool)  # the series hold in contact
        app, a1 = exact.app_m[kept] * 1e9, exact.a1_m[kept]
        ax.plot(app, exact.frequency_hz[kept] - exact.f_n0_hz, color=color,
                label=f"$m_2$ = {m2:g}: exact")
        for series, style, name in ((consistent, "--", "consistent"), (paper, ":", "Eq. 2.6")):
            ratio = series.frequency_ratio(series.alpha_per_m() * a1)
            ax.plot(app, exact.f_n0_hz * (ratio - 1), style, color=color,
                    label=f"$m_2$ = {m2:g}: {name}, order {series.order}")
    ax.set_xlabel("peak-to-peak amplitude $A_{pp}$ [nm]")
    ax.set_ylabel("$f - f_{n0}$ [Hz]")
    ax.set_title("Backbones: exact, consistent series, Eq. 2.6's series")
    ax.legend(loc="lower left", fontsize="x-small")
    if own:  # a caller's figure is laid out by the caller
        fixed_layout(figure, [[ax]], **_MARGINS_IN)
    return finish(figure, path)
