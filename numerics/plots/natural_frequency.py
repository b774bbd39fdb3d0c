"""Fig. 4: natural frequency against the height of a steel body."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from ..contact.natural_frequency import HeightSweep
from .figure import finish, on_axes

__all__ = ["plot_natural_frequency"]


def plot_natural_frequency(sweep: HeightSweep, path: str | Path | None = None, *,
                           ax=None) -> Figure:
    """The model's f_n0(h_b), with the paper's 30 mm cube at its reported f_n0.

    Examples
    --------
    >>> from numerics import natural_frequency_vs_height
    >>> figure = plot_natural_frequency(natural_frequency_vs_height())
    >>> figure.axes[0].get_ylabel()
    'natural frequency $f_n$ [Hz]'
    """
    figure, ax = on_axes(ax)
    ax.plot(sweep.height_m * 1e3, sweep.f_n0_hz, label="adopted model, rigid steel body")
    ax.plot(sweep.paper_height_m * 1e3, sweep.paper_f_n0_hz, "o", color="C3",
            label=f"paper: {sweep.paper_height_m * 1e3:g} mm cube, {sweep.paper_f_n0_hz:g} Hz")
    ax.set_xlabel("height of the body $h_b$ [mm]")
    ax.set_ylabel("natural frequency $f_n$ [Hz]")
    density = f"$\\rho$ = {sweep.density_kg_m3:.0f} kg/m$^3$"
    ax.set_title(f"Fig. 4: steel bodies ({density}) on the contact")
    ax.set_xlim(0, None)
    ax.legend()
    return finish(figure, path)
