"""The figures and GIF animations of scenes: drawn from plain arrays, checked by what
they draw (data of the artists, frames of the GIF), and strict about their inputs."""

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from numerics.plots import (
    animate_slider,
    animate_sweep,
    plot_contact_fraction,
    plot_phase_portrait,
    plot_spectrum,
    plot_time_history,
)
from numerics.plots.animation import _Run, _SliderScene, _SweepScene, jumps
from numerics.plots.observables import out_of_contact

F_E = 1500.0
Y0 = 225e-9


def history(mean=100e-9, amplitude=300e-9, periods=1.0, samples=64):
    """A cosine y(t) that leaves contact (y <= 0) near half a period when mean < amplitude."""
    t = np.linspace(0.0, periods / F_E, samples)
    return t, mean + amplitude * np.cos(2 * np.pi * F_E * t)


def lorentzian(f):
    return 40e-9 / (1 + ((f - 1450.0) / 60.0) ** 2) + 5e-9


def frames_of(path):
    """The frames of a GIF as RGB arrays."""
    with Image.open(path) as gif:
        frames = []
        for i in range(gif.n_frames):
            gif.seek(i)
            frames.append(np.asarray(gif.convert("RGB"), dtype=int))
    return frames


def legend_texts(ax):
    legend = ax.get_legend()
    return [] if legend is None else [text.get_text() for text in legend.get_texts()]


# -- static figures


def test_spectrum_bars_in_nm_with_the_mean_marked_and_a_log_axis_when_wide(tmp_path):
    amplitude = np.array([230e-9, 150e-9, 12e-9, 0.9e-9, 0.04e-9])
    figure = plot_spectrum(amplitude, tmp_path / "spectrum.png", title="one period")
    assert (tmp_path / "spectrum.png").read_bytes()[:4] == b"\x89PNG"
    ax = figure.axes[0]
    assert np.allclose([bar.get_height() for bar in ax.patches], amplitude * 1e9)
    assert ax.patches[0].get_hatch() and not ax.patches[1].get_hatch()  # k = 0 drawn apart
    assert any("mean offset 230 nm" in text for text in legend_texts(ax))
    assert ax.get_yscale() == "log"  # 230 nm .. 0.04 nm: more than three decades
    assert plot_spectrum(amplitude[:3]).axes[0].get_yscale() == "linear"
    assert plot_spectrum(amplitude, log=False).axes[0].get_yscale() == "linear"


def test_spectrum_against_frequency_draws_harmonics_one_to_six():
    f = np.linspace(1000.0, 1600.0, 7)
    amplitude = np.outer(lorentzian(f), 10.0 ** -np.arange(9))  # (points, harmonics k = 0..8)
    amplitude[2, 3] = 0.0
    figure = plot_spectrum(amplitude, frequency_hz=f)
    ax = figure.axes[0]
    assert len(ax.lines) == 6 and ax.get_yscale() == "log"
    assert ax.lines[0].get_label() == "k = 1 (f_e)" and ax.lines[5].get_label() == "k = 6 (6 f_e)"
    assert np.array_equal(ax.lines[1].get_xdata(), f)
    assert np.allclose(ax.lines[1].get_ydata(), amplitude[:, 2] * 1e9)
    assert np.isnan(ax.lines[2].get_ydata()[2])  # a zero amplitude is left out of a log axis
    amplitude[4] = np.nan  # a point without a spectrum (not period-1, say): a gap
    gap = plot_spectrum(amplitude, frequency_hz=f).axes[0]
    assert np.isnan(gap.lines[0].get_ydata()[4]) and np.isfinite(gap.lines[0].get_ydata()[3])


@pytest.mark.parametrize(("args", "kwargs", "name"), [
    ([[1e-9, 2e-9], [1e-9, 2e-9]], {}, "frequency_hz"),  # 2-D needs the frequencies
    ([1e-9, 2e-9], {"frequency_hz": [1000.0]}, "frequency_hz"),  # 1-D takes none
    ([[1e-9, 2e-9], [1e-9, 2e-9]], {"frequency_hz": [1000.0]}, "harmonic_amplitude_m"),
    ([[1e-9], [2e-9]], {"frequency_hz": [1000.0, 1100.0]}, "harmonic_amplitude_m"),  # no k = 1
    ([1e-9, -2e-9], {}, "harmonic_amplitude_m"),  # a negative amplitude
    ([1e-9, np.nan], {}, "harmonic_amplitude_m"),  # one spectrum: nothing may be missing
    ([[1e-9, np.inf], [1e-9, 2e-9]], {"frequency_hz": [1e3, 2e3]}, "harmonic_amplitude_m"),
    ([[np.nan, np.nan]], {"frequency_hz": [1e3]}, "harmonic_amplitude_m"),  # all missing
    ([], {}, "harmonic_amplitude_m"),
])
def test_spectrum_rejects_bad_input(args, kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        plot_spectrum(args, **kwargs)


def test_phase_portrait_marks_the_contact_edge_only_when_an_orbit_reaches_it():
    phase = np.linspace(0.0, 2 * np.pi, 50)
    y, v = Y0 + 300e-9 * np.cos(phase), -2.8e-3 * np.sin(phase)
    figure = plot_phase_portrait(y, v, y0_m=Y0)
    ax = figure.axes[0]
    assert np.allclose(ax.lines[0].get_xdata(), y * 1e9)
    assert np.allclose(ax.lines[0].get_ydata(), v * 1e3)  # mm/s
    assert legend_texts(ax) == ["contact edge y = 0", "static deflection y0 = 225 nm"]
    assert ax.lines[1].get_xdata()[0] == 0.0
    inside = plot_phase_portrait(Y0 + 50e-9 * np.cos(phase), v).axes[0]
    assert "contact edge y = 0" not in legend_texts(inside)


def test_phase_portrait_draws_several_labelled_orbits():
    phase = np.linspace(0.0, 2 * np.pi, 40)
    ys = [Y0 + 50e-9 * np.cos(phase), Y0 + 100e-9 * np.cos(phase[:30])]
    vs = [np.sin(phase) * 1e-4, np.sin(phase[:30]) * 2e-4]
    ax = plot_phase_portrait(ys, vs).axes[0]
    assert legend_texts(ax) == ["orbit 1", "orbit 2"]
    assert len(ax.lines[1].get_xdata()) == 30
    named = plot_phase_portrait(ys, vs, labels=["primary", "1/2"]).axes[0]
    assert legend_texts(named) == ["primary", "1/2"]


@pytest.mark.parametrize(("y", "v", "kwargs", "name"), [
    ([1e-9, 2e-9], [1e-4], {}, "y_m"),  # lengths differ
    ([[1e-9], [2e-9]], [[1e-4]], {}, "y_m"),  # two orbits against one
    ([1e-9, np.inf], [1e-4, 1e-4], {}, "y_m"),
    ([1e-9, 2e-9], [1e-4, 1e-4], {"y0_m": -1e-9}, "y0_m"),
    ([1e-9, 2e-9], [1e-4, 1e-4], {"labels": ["a", "b"]}, "labels"),
])
def test_phase_portrait_rejects_bad_input(y, v, kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        plot_phase_portrait(y, v, **kwargs)


def test_out_of_contact_intervals_are_interpolated_at_the_crossings():
    t, y = history(mean=100e-9, amplitude=300e-9, periods=2.0, samples=2001)
    intervals = out_of_contact(t, y)
    # y = 0 where cos(2 pi f t) = -1/3
    half = np.arccos(-1 / 3) / (2 * np.pi * F_E)
    expected = [[half, 1 / F_E - half], [1 / F_E + half, 2 / F_E - half]]
    assert intervals.shape == (2, 2)
    assert np.allclose(intervals, expected, rtol=0, atol=1e-9)
    starts_out = out_of_contact(np.arange(4.0), np.array([-1.0, 1.0, 1.0, -1.0]))
    assert starts_out.tolist() == [[0.0, 0.5], [2.5, 3.0]]
    assert out_of_contact(t, y + 1e-6).shape == (0, 2)


def test_time_history_shades_the_intervals_out_of_contact(tmp_path):
    t, y = history(periods=2.0, samples=400)
    figure = plot_time_history(t, y, tmp_path / "history.png", y0_m=Y0)
    ax = figure.axes[0]
    assert np.allclose(ax.lines[0].get_xdata(), t * 1e3)  # ms
    assert np.allclose(ax.lines[0].get_ydata(), y * 1e9)  # nm
    (shade,) = ax.collections
    assert len(shade.get_paths()) == 2
    assert "out of contact (y <= 0)" in legend_texts(ax)
    in_contact = plot_time_history(t, y + 1e-6).axes[0]
    assert not in_contact.collections
    assert "out of contact (y <= 0)" not in legend_texts(in_contact)


@pytest.mark.parametrize(("t", "y", "name"), [
    ([0.0, 1.0, 1.0], [1e-9, 2e-9, 3e-9], "time_s"),  # not increasing
    ([0.0, 1.0], [1e-9, 2e-9, 3e-9], "time_s"),  # lengths differ
    ([], [], "time_s"),
    ([0.0, 1.0], [1e-9, np.nan], "y_m"),
])
def test_time_history_rejects_bad_input(t, y, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        plot_time_history(t, y)


def test_contact_fraction_in_percent_one_line_per_curve():
    f = np.array([1000.0, 1200.0, 1400.0])
    fraction = np.array([[0.0, 0.1, 0.3], [0.0, 0.0, 0.2]])
    ax = plot_contact_fraction(f, fraction, labels=["0.30 Q", "0.20 Q"], title="t").axes[0]
    assert [line.get_ydata().tolist() for line in ax.lines] == [[0, 10, 30], [0, 0, 20]]
    assert legend_texts(ax) == ["0.30 Q", "0.20 Q"]
    single = plot_contact_fraction(f, fraction[0]).axes[0]
    assert len(single.lines) == 1 and single.get_legend() is None
    gap = plot_contact_fraction(f, [0.0, np.nan, 0.2]).axes[0]  # NaN: no value there
    assert np.isnan(gap.lines[0].get_ydata()[1])


@pytest.mark.parametrize(("fraction", "kwargs", "name"), [
    ([0.0, 0.5], {}, "fraction"),  # two points for three frequencies
    ([0.0, 0.5, 1.5], {}, "fraction"),  # not a share of the period
    ([0.0, 0.5, np.inf], {}, "fraction"),
    ([[0.0, 0.1, 0.2], [0.0, 0.1, 0.2]], {"labels": ["one"]}, "labels"),
    ([[0.0, 0.1, 0.2], [0.0, 0.1, 0.2]], {"labels": "ab"}, "labels"),
])
def test_contact_fraction_rejects_bad_input(fraction, kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        plot_contact_fraction([1000.0, 1200.0, 1400.0], fraction, **kwargs)


# -- the slider animation


def slider_arguments(**changes):
    t, y = history()
    f = np.linspace(1000.0, 1700.0, 40)
    arguments = {"time_s": t, "y_m": y, "y0_m": Y0, "curve_hz": f, "curve_app_m": lorentzian(f),
                 "point_hz": F_E, "point_app_m": float(lorentzian(F_E)), "frames": 8}
    arguments.update(changes)
    return arguments


def test_slider_gif_has_the_frames_asked_for(tmp_path):
    path = animate_slider(tmp_path / "slider.gif", **slider_arguments(), fps=10, title="demo")
    assert path == tmp_path / "slider.gif"
    with Image.open(path) as gif:
        assert gif.format == "GIF" and gif.n_frames == 8
        assert gif.info["duration"] == 100  # ms per frame at 10 fps
    frames = frames_of(path)
    left = slice(0, frames[0].shape[1] // 2)
    assert not np.array_equal(frames[0][:, left], frames[4][:, left])  # the slider moves


def test_slider_lifts_off_the_asperities_only_when_y_is_negative():
    arguments = slider_arguments()
    scene = _SliderScene(arguments["time_s"], arguments["y_m"], Y0, arguments["curve_hz"],
                         arguments["curve_app_m"], F_E, 1e-8, 8, "")
    panel = scene.panel
    seen = set()
    for frame in range(8):
        y = arguments["y_m"][scene.index[frame]]
        scene.update(frame)
        bottom = panel.slider.get_y()
        tips = panel.asperities.get_xy()[:, 1].max()
        if y < 0:
            assert bottom > panel.tip and tips == pytest.approx(panel.tip)
            assert panel.gap.get_visible() and panel.lost.get_visible()
            assert panel.gap.get_height() == pytest.approx(bottom - panel.tip)
            assert panel.gap.get_height() == pytest.approx(-y * panel.scale)  # proportional
        else:
            assert bottom <= panel.tip and tips == pytest.approx(bottom)  # pressed flat
            assert not panel.gap.get_visible() and not panel.lost.get_visible()
        seen.add(y < 0)
    assert seen == {True, False}


def test_slider_gif_shows_contact_lost_in_red(tmp_path):
    arguments = slider_arguments()
    path = animate_slider(tmp_path / "slider.gif", **arguments)
    index = np.round(np.linspace(0, arguments["y_m"].size - 1, 8)).astype(int)
    lost = arguments["y_m"][index] <= 0
    assert lost.any() and not lost.all()

    def red_pixels(frame):
        left = frame[:, : frame.shape[1] // 2]
        return int(np.sum((left[..., 0] > 180) & (left[..., 1] < 90) & (left[..., 2] < 90)))

    reds = np.array([red_pixels(frame) for frame in frames_of(path)])
    assert reds[lost].min() > 1000 and reds[~lost].max() < 100


@pytest.mark.parametrize(("changes", "name"), [
    ({"y_m": np.zeros(10)}, "time_s"),  # lengths differ
    ({"time_s": np.zeros(64)}, "time_s"),  # not increasing
    ({"y_m": np.r_[np.zeros(63), np.nan]}, "y_m"),
    ({"time_s": [], "y_m": []}, "time_s"),
    ({"frames": 1}, "frames"),
    ({"frames": 65}, "frames"),  # more frames than samples
    ({"frames": 2.5}, "frames"),
    ({"fps": 0}, "fps"),
    ({"fps": -5.0}, "fps"),
    ({"y0_m": np.nan}, "y0_m"),
    ({"curve_app_m": np.ones(3)}, "curve_hz"),
    ({"point_hz": np.inf}, "point_hz"),
])
def test_slider_rejects_bad_input(tmp_path, changes, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        animate_slider(tmp_path / "slider.gif", **slider_arguments(**changes))
    assert not (tmp_path / "slider.gif").exists()


@pytest.mark.parametrize("path", ["slider.png", "no/such/folder/slider.gif"])
def test_slider_wants_a_gif_in_an_existing_folder(tmp_path, path):
    with pytest.raises(ValueError, match="`path`"):
        animate_slider(tmp_path / path, **slider_arguments())


# -- the sweep animation


def jumping_curve():
    """A bent peak swept up: A_pp grows, then drops from 80 nm to 20 nm."""
    f = np.linspace(1300.0, 1600.0, 31)
    return f, np.where(f <= 1480.0, 30e-9 + (f - 1300.0) * 0.28e-9, 20e-9 - (f - 1480.0) * 0.05e-9)


def test_jumps_are_found_in_a_jumping_curve_and_not_in_a_smooth_one():
    f, app = jumping_curve()
    assert jumps(app).tolist() == [18]  # between 1480 and 1490 Hz
    assert jumps(app[::-1]).tolist() == [11]  # the same step, swept down
    smooth = lorentzian(np.linspace(1000.0, 1700.0, 141))
    assert jumps(smooth).size == 0
    flat = np.full(20, 50e-9)
    flat[10] += 1e-12  # tiny against 30 %: no jump
    assert jumps(flat).size == 0
    noisy_low = np.r_[np.full(10, 1e-12), 2e-12, np.full(10, 1e-12), 100e-9]
    assert 9 not in jumps(noisy_low) and 10 not in jumps(noisy_low)  # < 2 % of the range


def test_sweep_draws_the_jump_as_a_vertical_dashed_segment():
    f, app = jumping_curve()
    scene = _SweepScene([_Run(f, app * 1e9)], [None], 8, "")
    (jump,) = scene.jump_lines
    scene.update(0)
    assert len(jump.get_xdata()) == 0  # not reached yet
    scene.update(7)
    x, y = np.asarray(jump.get_xdata()), np.asarray(jump.get_ydata())
    assert x[0] == x[1] == pytest.approx(1485.0)  # vertical, half-way between the points
    assert sorted(y[:2]) == pytest.approx([19.5, 80.4])  # A_pp at 1490 and 1480 Hz
    assert jump.get_linestyle() == "--"
    curve = scene.curves[0]
    assert np.isnan(curve.get_ydata()).sum() == 1  # the solid curve is broken at the jump
    assert scene.point.get_xdata()[0] == f[-1]

    smooth_f = np.linspace(1000.0, 1700.0, 41)
    smooth = _SweepScene([_Run(smooth_f, lorentzian(smooth_f) * 1e9)], [None], 8, "")
    smooth.update(7)
    assert len(smooth.jump_lines[0].get_xdata()) == 0
    assert np.array_equal(smooth.curves[0].get_xdata(), smooth_f)


def test_sweep_gif_of_two_labelled_runs(tmp_path):
    f, app = jumping_curve()
    path = animate_sweep(tmp_path / "sweep.gif", frequency_hz=[f, f[::-1]],
                         app_m=[app, app[::-1]], labels=["up", "down"], frames=8, fps=5)
    with Image.open(path) as gif:
        assert gif.n_frames == 8 and gif.info["duration"] == 200
    frames = frames_of(path)
    assert not np.array_equal(frames[0], frames[-1])
    scene = _SweepScene([_Run(f, app), _Run(f[::-1], app[::-1])], ["up", "down"], 8, "")
    scene.update(3)  # point 17 of 62: in the first run
    assert len(scene.curves[1].get_xdata()) == 0
    scene.update(7)
    assert len(scene.curves[0].get_xdata()) == len(scene.curves[1].get_xdata())
    assert [text.get_text() for text in scene.figure.axes[0].get_legend().get_texts()] == [
        "up", "down"]


def test_sweep_of_a_smooth_curve_concatenated_up_and_down(tmp_path):
    f = np.linspace(1000.0, 1700.0, 30)
    path = animate_sweep(tmp_path / "smooth.gif", frequency_hz=np.r_[f, f[::-1]],
                         app_m=np.r_[lorentzian(f), lorentzian(f[::-1])], frames=8)
    with Image.open(path) as gif:
        assert gif.n_frames == 8


@pytest.mark.parametrize(("changes", "name"), [
    ({"app_m": np.ones(5)}, "frequency_hz"),  # lengths differ
    ({"app_m": [np.ones(31), np.ones(31)]}, "frequency_hz"),  # two runs against one
    ({"frequency_hz": np.r_[np.zeros(30), np.nan]}, "frequency_hz"),
    ({"frequency_hz": [], "app_m": []}, "frequency_hz"),
    ({"frames": 1}, "frames"),
    ({"frames": 32}, "frames"),  # more frames than points
    ({"fps": 0.0}, "fps"),
    ({"labels": ["up", "down"]}, "labels"),
])
def test_sweep_rejects_bad_input(tmp_path, changes, name):
    f, app = jumping_curve()
    arguments = {"frequency_hz": f, "app_m": app, "frames": 8, **changes}
    with pytest.raises(ValueError, match=f"`{name}`"):
        animate_sweep(tmp_path / "sweep.gif", **arguments)
    assert not (tmp_path / "sweep.gif").exists()


def test_animations_do_not_touch_pyplot(tmp_path):
    code = (
        "import sys, numpy as np; from numerics.plots import animate_sweep; "
        f"animate_sweep(r'{tmp_path / 'a.gif'}', frequency_hz=np.arange(3.0), "
        "app_m=np.ones(3), frames=2); "
        "assert 'matplotlib.pyplot' not in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
