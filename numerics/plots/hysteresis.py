"""Fig. 5: the hysteresis loop, displacement against contact pressure."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..contact.hysteresis import HysteresisLoop
from .figure import finish, on_axes

__all__ = ["plot_hysteresis"]


def plot_hysteresis(loop: HysteresisLoop, path: str | Path | None = None, *,
                    ax=None) -> Figure:
    """y against p = -R/S over one steady period, closed, as in Fig. 5.

    Examples
    --------
    >>> from numerics import hysteresis_loop
    >>> figure = plot_hysteresis(hysteresis_loop(1600.0, 0.40, steps_per_period=128))
    >>> figure.axes[0].get_xlabel()
    'normal contact pressure $p$ [kPa]'
    """
    figure, ax = on_axes(ax)
    pressure = np.r_[loop.pressure_pa, loop.pressure_pa[:1]] / 1e3  # closed: back to the start
    ax.plot(pressure, np.r_[loop.y_m, loop.y_m[:1]] * 1e9)
    if loop.y_m.min() < 0:
        ax.axhline(0.0, color="0.6", lw=0.8, label="contact edge y = 0")
        ax.legend()
    ax.set_xlabel("normal contact pressure $p$ [kPa]")
    ax.set_ylabel("displacement $y$ [nm]")
    ax.set_title(
        f"Fig. 5: $f_e$ = {loop.frequency_hz:g} Hz, $P_a$ = {loop.pa_frac:.2f} Q; "
        f"loop area {loop.loop_area_j * 1e9:.3g} nJ"
    )
    return finish(figure, path)
