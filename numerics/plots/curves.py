"""App against f_e for any list of curves (a scene's analytic response, for one)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .figure import finish, on_axes

__all__ = ["plot_curves"]


def plot_curves(curves: list[dict], path: str | Path | None = None, *, title: str = "",
                ax=None) -> Figure:
    """One line of App [nm] against f_e [Hz] per curve (dicts with ``frequency_hz``,
    ``app_m`` and ``label``); points marked invalid (``valid`` False) are drawn faint.

    Examples
    --------
    >>> curve = {"label": "a", "frequency_hz": np.array([1.0, 2.0]), "app_m": np.ones(2)}
    >>> plot_curves([curve]).axes[0].get_ylabel()
    '$A_{pp}$ [nm]'
    """
    figure, ax = on_axes(ax)
    for curve in curves:
        f, app = np.asarray(curve["frequency_hz"]), np.asarray(curve["app_m"]) * 1e9
        valid = np.asarray(curve.get("valid", np.ones(f.shape, dtype=bool)), dtype=bool)
        line, = ax.plot(f, np.where(valid, app, np.nan), ".-", ms=2, lw=0.8,
                        label=curve["label"])
        if not valid.all():
            ax.plot(f, np.where(valid, np.nan, app), ".", ms=2, color=line.get_color(),
                    alpha=0.25)
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("$A_{pp}$ [nm]")
    ax.set_yscale("log")
    if title:
        ax.set_title(title, fontsize=10)
    if 0 < len(curves) <= 12:
        ax.legend(fontsize=7)
    return finish(figure, path)
