"""Fig. 2 and Fig. 3 drawn from a ``Sweep``: one panel per force amplitude."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .figure import EDGE_PAD_IN, finish, fixed_layout, on_panels, panel_title

__all__ = ["plot_app", "plot_extrema"]

_STYLE = {"up": {"color": "black", "ls": "-", "marker": "."},
          "down": {"color": "tab:orange", "ls": "--", "marker": "+"}}
_PANELS = "abcdefghij"


#: The panels' margins [in] (``fixed_layout``), as constrained layout placed them on
#: Fig. 2 and 3 (2026-11-23): the title and panel title above, the x tick labels and
#: label below, a panel title between rows (the x tick labels hidden but in the last).
_MARGINS_IN = {"right": 0.042, "top": 0.470, "bottom": 0.473, "row_gap": 0.34}


def _panels(sweep, title: str, ax=None):
    fracs = sorted({r.pa_frac for r in sweep.runs})
    given = on_panels(ax, len(fracs), "force amplitude")
    if given is not None:  # the caller's panels, laid out by the caller
        return given[0], fracs, given[1]
    cols = min(len(fracs), 2)
    rows = -(-len(fracs) // cols)
    figure = Figure(figsize=(6.0 * cols, 2.6 * rows))
    axes = figure.subplots(rows, cols, squeeze=False, sharex=True)
    figure.suptitle(title, y=1 - EDGE_PAD_IN / figure.get_figheight())
    for ax in axes.ravel()[len(fracs):]:
        ax.set_visible(False)
    return figure, fracs, axes


def _finish(figure, axes, path, own: bool = True) -> Figure:
    if own:
        fixed_layout(figure, axes, **_MARGINS_IN)
    return finish(figure, path)


def fraction_title(ax, i: int, frac: float) -> None:
    panel_title(ax, f"({_PANELS[i % 10]}) P_a = {frac:.2f} Q", fontsize=9, loc="left")


def resonance_marks(ax, f_n0: float, fmin: float, fmax: float) -> None:
    """Plus signs at f_n0 / m (Eq. 3.1), at the bottom of the panel."""
    m = np.arange(1, 40)
    marks = f_n0 / m
    marks = marks[(marks >= fmin) & (marks <= fmax)]
    ax.plot(marks, np.full(marks.size, 0.04), "+", color="tab:red", ms=8,
            transform=ax.get_xaxis_transform(), label="f_n0/m")


def plot_app(sweep, path=None, *, ax=None) -> Figure:
    """Fig. 2: peak-to-peak amplitude App (log axis) against f_e, sweeps up and down;
    ``ax``: the caller's axes, one per force amplitude (increasing), to draw on."""
    own = ax is None  # (the loop below names each panel ax)
    figure, fracs, grid = _panels(sweep, "Contact resonances: A_pp against f_e (Fig. 2)", ax)
    axes = grid.ravel()
    for i, (ax, frac) in enumerate(zip(axes, fracs)):
        for run in (r for r in sweep.runs if r.pa_frac == frac):
            f, app = np.asarray(run.frequency_hz), np.asarray(run.app_m)
            style = _STYLE[run.direction]
            ax.semilogy(f, app * 1e9, ls=style["ls"], color=style["color"], lw=1,
                        label=f"sweep {run.direction}")
            lost = run.contact_lost
            ax.semilogy(f[lost], app[lost] * 1e9, ".", color=style["color"], ms=2)
        f_all = np.concatenate([r.frequency_hz for r in sweep.runs])
        resonance_marks(ax, f_n0_hz(sweep.model), f_all.min(), f_all.max())
        fraction_title(ax, i, frac)
        ax.set_ylabel("A_pp [nm]")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper left")
    for ax in axes[-2:]:
        ax.set_xlabel("f_e [Hz]")
    return _finish(figure, grid, path, own=own)


def plot_extrema(sweep, path=None, *, ax=None) -> Figure:
    """Fig. 3: every local extremum of y over one period against f_e
    (minima light grey, maxima dark grey; down sweeps with + marks); ``ax``: the
    caller's axes, one per force amplitude (increasing), to draw on."""
    own = ax is None  # (the loop below names each panel ax)
    figure, fracs, grid = _panels(sweep, "Local extrema of y against f_e (Fig. 3)", ax)
    axes = grid.ravel()
    for i, (ax, frac) in enumerate(zip(axes, fracs)):
        for run in (r for r in sweep.runs if r.pa_frac == frac):
            marker = "." if run.direction == "up" else "+"
            for values, color in ((run.minima_m, "0.7"), (run.maxima_m, "0.25")):
                f = np.repeat(run.frequency_hz, [len(v) for v in values])
                y = np.concatenate([np.asarray(v, float) for v in values]) * 1e9
                ax.plot(f, y, marker, color=color, ms=2, ls="none")
        ax.axhline(0.0, color="tab:red", lw=0.6, alpha=0.6)  # below: loss of contact
        fraction_title(ax, i, frac)
        ax.set_ylabel("y extrema [nm]")
    for ax in axes[-2:]:
        ax.set_xlabel("f_e [Hz]")
    return _finish(figure, grid, path, own=own)


def f_n0_hz(model: dict) -> float:
    """f_n0 of the model a result carries (Eq. 2.6)."""
    from perturb import ContactModel, eq26_numbers

    return eq26_numbers(ContactModel.from_dict(model).parameters).f_n0_hz
