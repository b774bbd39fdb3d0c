"""Continued branches drawn from a ``Continuation`` (App against f_e) or a
``ForceContinuation`` (App against P_a / Q), stability shown."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from .figure import finish, on_axes, on_panels

__all__ = ["plot_continuation", "plot_continued_app", "plot_force_continuation"]

_MARKS = {"fold": {"marker": "o", "color": "tab:red", "label": "fold"},
          "period-doubling": {"marker": "s", "color": "tab:blue", "label": "period doubling"}}


def plot_continuation(continuation, path=None, *, sweep=None, ax=None) -> Figure:
    """App (log axis) against f_e: stable parts solid, unstable parts dashed, folds and
    period doublings marked; with ``sweep`` (a ``Sweep`` at the same P_a), its points too."""
    figure, ax = on_axes(ax, (7.0, 4.2))
    _draw_branches(ax, continuation)
    _mark_bifurcations(ax, continuation.bifurcations)
    if sweep is not None:
        for run in (r for r in sweep.runs if np.isclose(r.pa_frac, continuation.pa_frac)):
            ax.semilogy(run.frequency_hz, run.app_m * 1e9, "+" if run.direction == "down"
                        else ".", ms=3, color="tab:orange", label=f"sweep {run.direction}")
    ax.set_xlabel("f_e [Hz]")
    ax.set_title(f"Continued periodic orbits, P_a = {continuation.pa_frac:g} Q", fontsize=10)
    return _finish_one(figure, ax, path)


def plot_force_continuation(continuation, path=None, *, ax=None) -> Figure:
    """App (log axis) against P_a / Q at one f_e, from a ``ForceContinuation``
    (``numerics.continue_in_force``): stable parts solid, unstable parts dashed, folds
    and period doublings marked."""
    figure, ax = on_axes(ax, (7.0, 4.2))
    _draw_branches(ax, continuation, along="pa_frac")
    _mark_bifurcations(ax, continuation.bifurcations, along="pa_frac")
    ax.set_xlabel("P_a / Q")
    ax.set_title("Periodic orbits continued in the force amplitude, "
                 f"f_e = {continuation.frequency_hz:g} Hz", fontsize=10)
    return _finish_one(figure, ax, path)


#: The tolerance of each bifurcation's place, by the parameter continued.
_TOLERANCES = {"frequency_hz": "frequency_tol_hz", "pa_frac": "pa_frac_tol"}


def _mark_bifurcations(ax, bifurcations, along: str = "frequency_hz") -> None:
    """A marker at each fold and period doubling, at its ``along`` (the parameter that
    was continued) and App, with its tolerance as an error bar (seen where it is wide:
    a zigzag's spread, a step's reach); one legend entry per kind. One that was not
    located (only marked within a step), or read from a file that did not say, is drawn
    hollow."""
    seen = set()
    for mark in bifurcations:
        style = dict(_MARKS[mark.kind])
        label = style.pop("label") + _HOW_LOCATED[mark.located]
        key = (mark.kind, mark.located)
        label = None if key in seen else label
        seen.add(key)
        tolerance = getattr(mark, _TOLERANCES[along])
        style |= {"xerr": tolerance if np.isfinite(tolerance) else None, "capsize": 2}
        if mark.located is not True:
            style["mfc"] = "none"
        ax.errorbar([getattr(mark, along)], [mark.app_m * 1e9], ls="none", ms=5, label=label,
                    **style)


#: The legend's words for ``Bifurcation.located``.
_HOW_LOCATED = {True: "", False: " (not located)", None: " (precision unknown)"}


def _finish_one(figure: Figure, ax, path) -> Figure:
    """The App axis, the stability's legend entries and the grid of a one-panel figure."""
    ax.plot([], [], color="black", ls="-", label="stable")
    ax.plot([], [], color="black", ls="--", label="unstable")
    ax.set_ylabel("A_pp [nm]")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    return finish(figure, path)


def plot_continued_app(continuations, path=None, *, sweep=None, ax=None) -> Figure:
    """Fig. 2 redrawn from continued branches: one panel per force amplitude (one
    ``Continuation`` each), App (log axis) against f_e, stable parts solid and unstable
    dashed; with ``sweep`` (a ``Sweep`` at the same amplitudes), its points beside;
    ``ax``: the caller's axes, one per amplitude (increasing), to draw on."""
    from .sweep import f_n0_hz, fraction_title, resonance_marks

    runs = sorted(continuations, key=lambda c: c.pa_frac)
    given = on_panels(ax, len(runs), "force amplitude")
    if given is not None:
        figure, axes = given[0], given[1].ravel()
        cols = len(runs)  # x labels on every panel: the caller's layout is unknown
    else:
        cols = min(len(runs), 2)
        rows = -(-len(runs) // cols)
        figure = Figure(figsize=(6.0 * cols, 2.6 * rows), layout="constrained")
        axes = figure.subplots(rows, cols, squeeze=False, sharex=True).ravel()
        figure.suptitle("Contact resonances, continued: A_pp against f_e (Fig. 2; stable "
                        "solid, unstable dashed)")
    for ax in axes[len(runs):]:
        ax.set_visible(False)
    for i, (ax, run) in enumerate(zip(axes, runs)):
        _draw_branches(ax, run)
        if sweep is not None:
            for part in (r for r in sweep.runs if np.isclose(r.pa_frac, run.pa_frac)):
                ax.semilogy(part.frequency_hz, part.app_m * 1e9, "." if part.direction == "up"
                            else "+", ms=2, color="tab:orange")
        band = run.settings["fmin_hz"], run.settings["fmax_hz"]
        resonance_marks(ax, f_n0_hz(run.model), *band)
        fraction_title(ax, i, run.pa_frac)
        ax.set_ylabel("A_pp [nm]")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes[len(runs) - min(cols, len(runs)):len(runs)]:
        ax.set_xlabel("f_e [Hz]")
    return finish(figure, path)


def _draw_branches(ax, continuation, along: str = "frequency_hz") -> None:
    """Each branch of ``continuation``, App against its ``along`` (the parameter that was
    continued: "frequency_hz" or "pa_frac"): stable parts solid, unstable parts dashed."""
    for branch in continuation.branches:
        f, app = np.asarray(getattr(branch, along)), np.asarray(branch.app_m) * 1e9
        for part in _runs(np.asarray(branch.stable, dtype=bool)):
            stable = bool(branch.stable[part.start])
            # One point either side joins the parts where the stability changes.
            span = slice(part.start, min(part.stop + 1, f.size))
            ax.semilogy(f[span], app[span], color="black", lw=1.0,
                        ls="-" if stable else "--")


def _runs(flags: np.ndarray) -> list[slice]:
    """The slices of consecutive equal ``flags``."""
    if not flags.size:
        return []
    edges = np.flatnonzero(flags[1:] != flags[:-1]) + 1
    bounds = np.concatenate([[0], edges, [flags.size]])
    return [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:])]
