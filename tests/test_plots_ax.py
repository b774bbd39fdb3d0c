"""Every plot function takes ``ax=``: it draws on the caller's axes (one, or one per
panel), into the caller's figure, and makes no figure of its own."""

import inspect

import numpy as np
import pytest
from matplotlib.figure import Figure

import numerics.plots as plots
from numerics import simulate, sweep
from numerics.scenes import harmonic_amplitudes
from perturb import PAPER


def test_every_plot_function_takes_ax():
    functions = [name for name in plots.__all__ if name.startswith("plot_")]
    assert len(functions) == 18
    for name in functions:
        assert "ax" in inspect.signature(getattr(plots, name)).parameters, name


def test_one_axes_plots_draw_on_the_callers_axes():
    figure = Figure()
    left, right = figure.subplots(1, 2)
    run = simulate([740.0], 0.15 * PAPER.Q_n, periods=200, record="history", record_periods=1)
    y, v = run.history_y_m[0], run.history_v_m_s[0]
    drawn = plots.plot_phase_portrait(y, v, ax=left)
    assert drawn is figure and left.lines and not right.lines
    plots.plot_spectrum(harmonic_amplitudes(y), ax=right)
    assert right.patches and len(figure.axes) == 2


def test_panel_plots_draw_one_panel_per_amplitude_on_the_callers_axes(tmp_path):
    found = sweep([1300.0, 1400.0], [0.05, 0.1], direction="up")
    figure = Figure()
    axes = figure.subplots(2, 1)
    places = [ax.get_position().bounds for ax in axes]
    canvas = figure.canvas
    assert plots.plot_app(found, tmp_path / "app.png", ax=axes) is figure
    assert all(ax.lines for ax in axes) and len(figure.axes) == 2
    # The caller's layout, canvas and file: its panels stay where they were put.
    assert [ax.get_position().bounds for ax in axes] == places
    assert figure.canvas is canvas and (tmp_path / "app.png").stat().st_size > 0
    with pytest.raises(ValueError, match="`ax` must hold one axes per force amplitude"):
        plots.plot_extrema(found, ax=np.array([axes[0]]))
