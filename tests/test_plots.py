"""The figures are drawn from result objects and saved as PNG, without pyplot; the
report's scenes draw theirs in worker processes."""

import os
import subprocess
import sys

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from numerics import exact_backbone, hysteresis_loop, natural_frequency_vs_height, sweep
from numerics.plots import figure as figure_module
from numerics.plots import (
    plot_app,
    plot_backbone,
    plot_extrema,
    plot_hysteresis,
    plot_natural_frequency,
)
from numerics.plots import sweep as sweep_module
from numerics.plots.figure import DPI
from paper_checks import scene as scene_module
from paper_checks.scene import PaperScene, worker_pool


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


# -- saving: one draw, the file savefig writes


def test_a_png_is_drawn_once_and_is_the_file_savefig_writes(tmp_path, monkeypatch):
    # Regression: savefig lays a constrained figure out in a draw of its own before
    # drawing it; finish() draws once, and must still write the same file.
    heights = natural_frequency_vs_height(points=20)  # a constrained figure
    draws = []
    original = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda self, renderer: draws.append(self)
                        or original(self, renderer))
    plot_natural_frequency(heights, tmp_path / "finish.png")
    assert len(draws) == 1
    plot_natural_frequency(heights).savefig(tmp_path / "savefig.png", dpi=DPI)
    assert len(draws) == 3  # savefig: the layout's draw, then the pixels
    assert (tmp_path / "finish.png").read_bytes() == (tmp_path / "savefig.png").read_bytes()


def test_other_formats_are_saved_by_savefig(tmp_path):
    plot_backbone(exact_backbone(points=20), tmp_path / "backbone.svg")
    assert (tmp_path / "backbone.svg").read_text().lstrip().startswith("<?xml")


def test_the_layout_shortcuts_leave_the_files_unchanged(tmp_path, monkeypatch):
    # panel_title fixes the titles at the top edge, _spines_out_of_layout leaves out of
    # the layout the spines the tick labels cover, _minor_log_ticks_in_view drops the
    # minor ticks matplotlib makes off view: all to spare it tick objects and updates of
    # every tick; _share_mathtext gives every renderer one mathtext parser, which keeps
    # what it parsed. On the Fig. 2 and 3 panels (log and linear y, shared x, x tick
    # labels hidden in all but the last row) matplotlib left to itself draws the same
    # files.
    result = sweep(np.array([700.0, 740.0, 1400.0, 1450.0]), (0.05, 0.3, 0.5))
    for plot in (plot_app, plot_extrema):
        plot(result, tmp_path / "shortcuts.png")
        with monkeypatch.context() as patch:
            patch.setattr(sweep_module, "panel_title",
                          lambda ax, text, **kw: ax.set_title(text, **kw))
            patch.setattr(figure_module, "_spines_out_of_layout", lambda figure: None)
            patch.setattr(figure_module, "_minor_log_ticks_in_view", lambda figure: None)
            patch.setattr(figure_module, "_share_mathtext", lambda renderer: None)
            plot(result, tmp_path / "plain.png")
        assert (tmp_path / "shortcuts.png").read_bytes() == (tmp_path / "plain.png").read_bytes()


def test_a_figure_drawn_again_parses_no_label_again(tmp_path, monkeypatch):
    # Regression: matplotlib keeps the mathtext it parsed ($10^{2}$ of the log axes) per
    # parser, and each renderer had one of its own, so every figure, and every axis
    # fixed_layout measured, parsed its labels again (102 parses for the report's nine
    # figures). The negative control draws with a parser per renderer, as matplotlib does.
    from matplotlib.mathtext import MathTextParser

    result = sweep(np.array([700.0, 740.0]), (0.05, 0.3))
    parses = MathTextParser._parse_cached.cache_info

    def new_parses() -> int:
        before = parses().misses
        plot_app(result, tmp_path / "fig2.png")
        return parses().misses - before

    new_parses()  # the labels this figure draws, parsed here or by an earlier test
    assert new_parses() == 0
    monkeypatch.setattr(figure_module, "_share_mathtext", lambda renderer: None)
    assert new_parses() > 0


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_a_forked_child_and_its_parent_draw_at_once(tmp_path):
    # Regression: the shared mathtext parser's FreeType fonts read their files through
    # descriptors that a forked child shares with its parent, offset and all; with both
    # drawing at once, glyphs failed ("FT_Load_Glyph ... invalid outline", "too many
    # hints": CI, make paper's forked scenes). Before the fix this drew 2-3 errors in
    # 2 rounds of 6 figures each side (3 runs); a forked child now has its own parser.
    heights = natural_frequency_vs_height(np.linspace(1e-6, 1e-4, 50))
    plot_natural_frequency(heights, tmp_path / "before.png")  # fonts and parser loaded
    failures = []
    for round_ in range(2):
        child = os.fork()
        if child == 0:  # the child draws, then leaves at once with 0 or 1
            code = 0
            try:
                for i in range(6):
                    plot_natural_frequency(heights, tmp_path / f"child{round_}{i}.png")
            except RuntimeError:
                code = 1
            os._exit(code)
        try:
            for i in range(6):
                plot_natural_frequency(heights, tmp_path / f"parent{round_}{i}.png")
        except RuntimeError as error:
            failures.append(f"parent: {error}")
        if os.waitpid(child, 0)[1]:
            failures.append("child failed")
    assert not failures


# -- fixed layouts: the margins of constrained layout without its measuring


def _overlaps(figure) -> list[str]:
    """What of the drawn ``figure`` leaves it, or covers another axes' labels: the
    tight box (tick labels, axis labels, titles) of each visible axes, and the title."""
    renderer = FigureCanvasAgg(figure).get_renderer()
    figure.draw(renderer)
    page = figure.bbox.padded(1.0)  # a pixel of rounding
    boxes = {f"axes {i}": ax.get_tightbbox(renderer) for i, ax in enumerate(figure.axes)
             if ax.get_visible()}
    if figure._suptitle is not None:
        boxes["title"] = figure._suptitle.get_window_extent(renderer)
    found = [f"{name} leaves the figure" for name, box in boxes.items()
             if not (page.contains(box.x0, box.y0) and page.contains(box.x1, box.y1))]
    names = list(boxes)
    found += [f"{a} overlaps {b}" for i, a in enumerate(names) for b in names[i + 1:]
              if boxes[a].overlaps(boxes[b])]
    return found


@pytest.fixture(scope="module")
def bouncing_sweep():
    # Linear y tick labels from -20000 nm (bouncing at 0.5 Q, 300 Hz) beside ones of
    # three digits (0.05 Q): the widest labels the report's Fig. 3 draws.
    return sweep(np.array([300.0, 740.0, 1400.0, 1450.0]), (0.05, 0.15, 0.5))


@pytest.mark.parametrize("plot", [plot_app, plot_extrema])
def test_a_fixed_layout_keeps_every_label_in_the_figure_and_off_the_others(
        plot, bouncing_sweep):
    assert _overlaps(plot(bouncing_sweep)) == []


def test_the_fixed_layout_check_fails_where_the_labels_get_no_room(bouncing_sweep,
                                                                   monkeypatch):
    # Negative control of the test above: the y labels given a tenth of an inch.
    monkeypatch.setattr(figure_module, "Y_LABEL_ROOM_IN", 0.1)
    found = _overlaps(plot_extrema(bouncing_sweep))
    # The left column's y labels cross the figure's edge (axes 2: P_a = 0.5 Q, labels to
    # -20000), the right column's reach into the left one's panels.
    assert "axes 2 leaves the figure" in found and "axes 0 overlaps axes 1" in found


def test_a_fixed_layout_places_the_axes_as_constrained_layout_did(bouncing_sweep,
                                                                  monkeypatch):
    # The part of the margins that depends on the data: the left of each column is its
    # widest y tick label plus Y_LABEL_ROOM_IN, and the axes share the width left. Within
    # 0.02 inch (3 pixels) of where constrained layout puts them: measured 0.016 in,
    # 2026-11-23. (The heights are constants measured on the report's figures; here the
    # title, placed by hand, is out of constrained layout's reach.)
    fixed = [ax.get_position().bounds for ax in plot_extrema(bouncing_sweep).axes]
    monkeypatch.setattr(sweep_module, "fixed_layout",
                        lambda figure, grid, **margins: figure.set_layout_engine("constrained"))
    figure = plot_extrema(bouncing_sweep)
    FigureCanvasAgg(figure).draw()
    constrained = [ax.get_position().bounds for ax in figure.axes]
    left_and_width = (np.array(fixed) - constrained)[:, [0, 2]] * figure.get_figwidth()
    assert np.max(np.abs(left_and_width)) < 0.02


# -- the report's scenes and figures, in worker processes


def test_scenes_run_in_workers_give_what_they_give_here(tmp_path):
    here = PaperScene(quick=True, out=tmp_path / "here")
    there = PaperScene(quick=True, out=tmp_path / "there")
    with worker_pool(2) as pool:
        there.start(pool, ["fig5.toml", "fig4.toml"])
        assert np.array_equal(there.hysteresis.y_m, here.hysteresis.y_m)
        assert np.array_equal(there.heights.f_n0_hz, here.heights.f_n0_hz)
    assert set(there.timings) == set(here.timings) == {"hysteresis loop (Fig. 5)",
                                                       "natural frequency (Fig. 4)"}
    for figure in ("fig5-hysteresis.png", "fig4-natural-frequency.png"):
        assert (tmp_path / "there" / figure).read_bytes() == \
            (tmp_path / "here" / figure).read_bytes()


@pytest.mark.skipif(not sys.platform.startswith("linux"),
                    reason="the workers see the patched run_scene only when forked")
def test_a_scene_that_fails_in_a_worker_is_raised_where_its_result_is_asked_for(
        tmp_path, monkeypatch):
    def fail(scene, out):
        raise RuntimeError(f"cannot run {scene.title[:6]}")

    monkeypatch.setattr(scene_module, "run_scene", fail)
    scene = PaperScene(quick=True, out=tmp_path, kernel_models=())
    with pytest.raises(RuntimeError, match="cannot run Fig. 2"), worker_pool(2) as pool:
        scene.start(pool)
        scene.sweep  # noqa: B018
    assert scene.runs == {} and not list(tmp_path.iterdir())
