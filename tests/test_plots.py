"""The figures are drawn from result objects and saved as PNG, without pyplot."""

import subprocess
import sys

import numpy as np

from numerics import exact_backbone, hysteresis_loop, natural_frequency_vs_height
from numerics.plots import plot_backbone, plot_hysteresis, plot_natural_frequency


def is_png(path) -> bool:
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_backbone_figure(tmp_path):
    backbone = exact_backbone(points=40)
    figure = plot_backbone(backbone, tmp_path / "backbone.png")
    assert is_png(tmp_path / "backbone.png")
    app_line = figure.axes[0].lines[0]
    assert np.array_equal(app_line.get_xdata(), backbone.app_m * 1e9)


def test_natural_frequency_figure(tmp_path):
    sweep = natural_frequency_vs_height(points=20)
    figure = plot_natural_frequency(sweep, tmp_path / "fig4.png")
    assert is_png(tmp_path / "fig4.png")
    curve, paper_point = figure.axes[0].lines
    assert np.array_equal(curve.get_ydata(), sweep.f_n0_hz)
    assert paper_point.get_xdata()[0] == 30.0 and paper_point.get_ydata()[0] == 1485.0


def test_hysteresis_figure_is_a_closed_curve(tmp_path):
    loop = hysteresis_loop(1600.0, 0.40, steps_per_period=64)
    figure = plot_hysteresis(loop, tmp_path / "fig5.png")
    assert is_png(tmp_path / "fig5.png")
    line = figure.axes[0].lines[0]
    assert line.get_xdata()[0] == line.get_xdata()[-1]
    assert line.get_ydata()[0] == line.get_ydata()[-1]


def test_plotting_does_not_touch_pyplot():
    # pyplot would pick a GUI backend and keep global figures alive.
    code = (
        "import sys, numerics, numerics.plots; "
        "numerics.plots.plot_backbone(numerics.exact_backbone(points=5)); "
        "assert 'matplotlib.pyplot' not in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_core_does_not_import_matplotlib():
    code = "import sys, numerics; assert 'matplotlib' not in sys.modules, 'core imports matplotlib'"
    subprocess.run([sys.executable, "-c", code], check=True)
