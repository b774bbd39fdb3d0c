"""The coexisting orbits of an attractor census, one period each (Section 3.3)."""

from __future__ import annotations

import numpy as np

from .figure import finish, on_axes

__all__ = ["plot_census"]


def plot_census(census, path=None, *, ax=None):
    """y(t) over one orbit of every attractor found, against the phase of the drive."""
    figure, ax = on_axes(ax, (6.4, 4.2))
    for attractor in census.attractors:
        y = attractor.orbit_y_m
        phase = np.arange(1, y.size + 1) / (y.size / attractor.period)
        ax.plot(phase, y * 1e9, lw=1.2,
                label=f"{attractor.label} (basin {attractor.basin_fraction:.0%})")
    ax.axhline(0.0, color="tab:red", lw=0.7, ls=":", label="y = 0: contact lost below")
    ax.invert_yaxis()  # y points down (Fig. 1e): the slideway is below, flight above
    ax.set_xlabel("time [excitation periods]")
    ax.set_ylabel("y [nm] (down)")
    ax.set_title(f"Coexisting steady states at f_e = {census.frequency_hz:g} Hz, "
                 f"P_a = {census.pa_frac:g} Q", fontsize=10)
    ax.legend(fontsize=7)
    return finish(figure, path)
