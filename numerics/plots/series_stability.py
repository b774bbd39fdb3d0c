"""The series' branches with their stability, over the continued RK4 branch of Eq. 2.6."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .figure import finish, on_axes

__all__ = ["plot_series_stability"]

_LINES = {True: "-", False: "--"}


def plot_series_stability(stability, continuation=None, path=None, *, ax=None) -> Figure:
    """App (log axis) against f_e of each branch of a ``SeriesStability``, stable parts
    solid, unstable dashed, unknown dotted and grey; with ``continuation`` (a
    ``Continuation`` of Eq. 2.6 at the same P_a), its branches beneath, thick and pale,
    styled alike.

    Branch j of the series is the root with the (j+1)-th largest omega: where the count
    of roots changes (at a fold) it passes to another orbit, and its line is broken there.
    """
    figure, ax = on_axes(ax, (7.0, 4.2))
    if continuation is not None:
        for branch in continuation.branches:
            flags = np.asarray(branch.stable, dtype=object)
            _draw(ax, branch.frequency_hz, branch.app_m, flags,
                  np.zeros(max(flags.size - 1, 0), dtype=bool), color="0.6", lw=3.5, alpha=0.6)
        ax.plot([], [], color="0.6", lw=3.5, alpha=0.6, label="RK4 of Eq. 2.6, continued")
    frequencies, counts = np.unique(np.concatenate(
        [b.frequency_hz for b in stability.branches] or [[]]), return_counts=True)
    for j, branch in enumerate(stability.branches):
        roots = counts[np.searchsorted(frequencies, branch.frequency_hz)]
        _draw(ax, branch.frequency_hz, branch.app_m, branch.stable, roots[1:] != roots[:-1],
              color=f"C{j}", lw=1.2)
        ax.plot([], [], color=f"C{j}", lw=1.2, label=f"series, branch {j}")
    ax.plot([], [], color="black", ls="-", label="stable")
    ax.plot([], [], color="black", ls="--", label="unstable")
    ax.plot([], [], color="0.4", ls=":", label="unknown")
    ax.set_xlabel("f_e [Hz]")
    ax.set_ylabel("A_pp [nm]")
    ax.set_title(f"Stability of the order-{stability.order} series' roots, P_a = "
                 f"{stability.pa_frac:g} Q", fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    return finish(figure, path)


def _draw(ax, frequency_hz, app_m, flags: np.ndarray, breaks: np.ndarray, **style) -> None:
    """One line per run of equal ``flags`` (True, False, None) between ``breaks`` (where
    points k and k + 1 are not joined); a run joins the next by one point where the flag
    changes and both are known."""
    f, app = np.asarray(frequency_hz), np.asarray(app_m) * 1e9
    if not f.size:  # an empty branch (a walk with no orbit to start from)
        return
    edges = np.flatnonzero((flags[1:] != flags[:-1]) | breaks) + 1
    bounds = np.concatenate([[0], edges, [f.size]])
    for start, stop in zip(bounds[:-1], bounds[1:]):
        flag = flags[start]
        joined = stop < f.size and not breaks[stop - 1] and flag is not None \
            and flags[stop] is not None
        span = slice(start, stop + 1 if joined else stop)
        if flag is None:
            ax.semilogy(f[span], app[span], color="0.4", ls=":", lw=1.0)
        else:
            ax.semilogy(f[span], app[span], ls=_LINES[bool(flag)], **style)
