"""Teaching animations, written as GIF: the slider riding on its contact, and a
point travelling along a swept resonance curve.

Each builds a matplotlib ``Figure`` on an Agg canvas once (no pyplot), updates its
artists in place for every frame (``set_data``, ``set_y``, ...) and writes the
frames through ``FuncAnimation`` and ``PillowWriter``. Inputs are plain numpy
arrays in SI units; nm, ms and Hz are shown.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Polygon, Rectangle

from perturb.common import check_int, check_positive, check_real, finite_array, replacing

from .observables import curve_labels, curves, increasing, is_wide, same_lengths

__all__ = ["animate_slider", "animate_sweep"]

#: resolution of the GIF frames
DPI = 80
#: a jump: neighbouring A_pp differ by more than 30 % of the smaller one ...
JUMP_RELATIVE = 0.30
#: ... and by more than 2 % of the range of the curve
JUMP_OF_RANGE = 0.02
#: a resonance curve spanning more decades than this is drawn on a log axis
LOG_DECADES = 1.0

# the slider scene, in drawing units (the slider is the paper's 30 mm cube)
SLIDER_MM = 30.0
SLIDER_SIZE = 2.0
SLIDER_HALF_WIDTH = 2.0
TIP = 0.6  # height of the asperity tips above the slideway: y = 0
TRAVEL = 0.45  # the largest |y| of the history is drawn this long
ASPERITIES = 11
CONTACT_COLOUR, LOST_COLOUR = "lightsteelblue", "tab:red"


# -- writing


def _gif_path(path) -> Path:
    try:
        path = Path(path)
    except TypeError:
        raise ValueError(f"`path` must be a file path ending in .gif, got {path!r}.") from None
    if path.suffix.lower() != ".gif":
        raise ValueError(f"`path` must end in .gif, got {str(path)!r}.")
    if not path.parent.is_dir():
        raise ValueError(f"`path` must be in an existing folder, got {str(path)!r}.")
    return path


class _FrameCanvas(FigureCanvasAgg):
    """An Agg canvas for frames written to a file: each frame is drawn once, when the
    writer grabs it, so the redraw ``FuncAnimation`` asks for after every update
    (``draw_idle``, meant for a window) is skipped."""

    def draw_idle(self, *args, **kwargs) -> None:
        pass


def _write(figure: Figure, update, frames: int, fps: float, path: Path) -> Path:
    """Draw ``update(0)`` .. ``update(frames - 1)`` into the GIF ``path``.

    ``update`` returns the artists it changes; everything else is drawn once, on the
    first frame (with its constrained layout, removed then so that frames neither
    re-run it nor shift), and shown behind the frames as one image.
    """
    _FrameCanvas(figure)
    moving = update(0)
    with mpl.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        figure.canvas.draw()  # settles the layout
        figure.set_layout_engine(None)  # no engine at all: "none" leaves a placeholder
    _freeze_background(figure, moving)
    animation = FuncAnimation(figure, update, frames=frames, init_func=lambda: (),
                              repeat=False, cache_frame_data=False)
    with replacing(path) as target:  # whole or not at all, never through a symlink
        animation.save(target, writer=PillowWriter(fps=fps), dpi=DPI)
    return path


def _freeze_background(figure: Figure, moving) -> None:
    """Render every artist but ``moving`` once into an image behind the figure, and hide
    them: a frame then draws that image and the moving artists only."""
    moving = {id(artist): artist for artist in moving}
    shown = {key: artist.get_visible() for key, artist in moving.items()}
    for artist in moving.values():
        artist.set_visible(False)
    figure.canvas.draw()
    background = np.asarray(figure.canvas.buffer_rgba()).copy()
    for key, artist in moving.items():
        artist.set_visible(shown[key])
    for ax in figure.axes:
        ax.set_axis_off()
        for artist in ax.get_children():
            if id(artist) not in moving:
                artist.set_visible(False)
    for artist in figure.get_children():
        if id(artist) not in moving and artist not in figure.axes:
            artist.set_visible(False)
    figure.figimage(background, origin="upper", zorder=-1)


def _samples(count: int, frames: int) -> np.ndarray:
    """``frames`` distinct indices into ``count`` samples, evenly spread, first and last
    included (``frames <= count``)."""
    return np.round(np.linspace(0, count - 1, frames)).astype(int)


def _counter(figure: Figure):
    """A small frame counter (it also keeps consecutive frames distinct, so that the
    GIF keeps every one of them)."""
    return figure.text(0.995, 0.005, "", ha="right", va="bottom", fontsize=6, color="0.5")


def _app_axis(ax, app_m: np.ndarray) -> None:
    """A_pp axis: logarithmic when the curve spans more than a decade."""
    if is_wide(app_m, LOG_DECADES):
        ax.set_yscale("log")
    ax.set_ylabel("$A_{pp}$ [nm]")
    ax.set_xlabel("$f_e$ [Hz]")
    ax.grid(True, which="major", alpha=0.3)


def _limits(ax, f_hz: np.ndarray, app_nm: np.ndarray) -> None:
    """Fixed limits that hold the whole curve (set_data never rescales)."""
    pad = 0.03 * np.ptp(f_hz) or 1.0
    ax.set_xlim(f_hz.min() - pad, f_hz.max() + pad)
    if ax.get_yscale() == "log":
        ax.set_ylim(app_nm.min() / 1.5, app_nm.max() * 1.5)
    else:
        pad = 0.06 * np.ptp(app_nm) or max(abs(app_nm.max()), 1.0) * 0.1
        ax.set_ylim(app_nm.min() - pad, app_nm.max() + pad)


# -- the slider on its contact


class _SliderPanel:
    """The slider (a rectangle) on the slideway (hatched) through a row of asperities.

    y points down (Eq. 2.1): the slider's bottom is drawn at ``TIP - scale * y``.
    For y > 0 it presses the asperities (drawn flattened to its bottom); for y <= 0
    it hangs above their tips with a gap ``scale * |y|``, shaded: contact lost.
    """

    def __init__(self, ax, y_m: np.ndarray, y0_m: float):
        self.ax = ax
        largest = max(float(np.abs(y_m).max()), y0_m, 1e-15)
        self.scale = TRAVEL / largest  # drawing units per metre
        self.tip = TIP
        magnification = self.scale * SLIDER_MM * 1e-3 / SLIDER_SIZE
        self._x = np.linspace(-SLIDER_HALF_WIDTH, SLIDER_HALF_WIDTH, 40 * ASPERITIES + 1)
        bumps = 0.5 * (1 - np.cos(2 * np.pi * ASPERITIES * (self._x + SLIDER_HALF_WIDTH)
                                  / (2 * SLIDER_HALF_WIDTH)))
        self._profile = TIP * np.sqrt(bumps)  # rounded asperities, tips at TIP
        ax.add_patch(Rectangle((-3.0, -0.6), 6.0, 0.6, facecolor="0.85", edgecolor="0.3",
                               hatch="///"))
        ax.text(-2.9, -0.3, "slideway", va="center", fontsize=8)
        self.asperities = ax.add_patch(Polygon(self._outline(TIP), closed=True,
                                               facecolor="0.55", edgecolor="0.25", lw=0.6))
        self.gap = ax.add_patch(Rectangle((-SLIDER_HALF_WIDTH, TIP), 2 * SLIDER_HALF_WIDTH, 0.0,
                                          facecolor=LOST_COLOUR, alpha=0.3, edgecolor="none",
                                          visible=False))
        self.slider = ax.add_patch(Rectangle((-SLIDER_HALF_WIDTH, TIP), 2 * SLIDER_HALF_WIDTH,
                                             SLIDER_SIZE, facecolor=CONTACT_COLOUR,
                                             edgecolor="0.2"))
        self.name = ax.text(0.0, TIP + SLIDER_SIZE / 2, "slider", ha="center", va="center")
        ax.axhline(TIP, color="0.3", lw=0.6, ls=":")
        ax.text(2.1, TIP, "y = 0", va="bottom", fontsize=7)
        rest = TIP - self.scale * y0_m
        ax.plot([-2.6, 2.6], [rest, rest], color="0.3", lw=0.6, ls="--")
        ax.text(2.1, rest, "rest: y0", va="top", fontsize=7)
        self.lost = ax.text(0.0, TIP + SLIDER_SIZE + TRAVEL + 0.25, "contact lost",
                            ha="center", color=LOST_COLOUR, weight="bold", visible=False)
        self.reading = ax.text(-2.95, TIP + SLIDER_SIZE + TRAVEL + 0.85, "", fontsize=8)
        ax.text(-2.95, -0.85, f"y drawn x{_rounded(magnification)} (slider {SLIDER_MM:g} mm); "
                "y points down", fontsize=7, va="top")
        ax.set_xlim(-3.0, 3.0)
        ax.set_ylim(-1.1, TIP + SLIDER_SIZE + TRAVEL + 1.1)
        ax.set_aspect("equal")
        ax.set_axis_off()

    def _outline(self, bottom: float) -> np.ndarray:
        """The asperity profile flattened where the slider's bottom presses it."""
        top = np.minimum(self._profile, bottom)
        return np.column_stack([np.r_[self._x, self._x[-1], self._x[0]],
                                np.r_[top, 0.0, 0.0]])

    def bottom(self, y_m: float) -> float:
        """Height of the slider's bottom for the displacement ``y_m``."""
        return self.tip - self.scale * y_m

    def show(self, time_s: float, y_m: float) -> tuple:
        bottom = self.bottom(y_m)
        lost = y_m <= 0
        self.slider.set_y(bottom)
        self.slider.set_facecolor(LOST_COLOUR if lost else CONTACT_COLOUR)
        self.name.set_y(bottom + SLIDER_SIZE / 2)
        self.asperities.set_xy(self._outline(bottom))
        self.gap.set_height(max(bottom - self.tip, 0.0))
        self.gap.set_visible(lost)
        self.lost.set_visible(lost)
        self.reading.set_text(f"t = {time_s * 1e3:.4f} ms   y = {y_m * 1e9:.1f} nm")
        return self.slider, self.name, self.asperities, self.gap, self.lost, self.reading


def _rounded(number: float) -> str:
    """Two significant digits, without an exponent for large numbers: 13,000."""
    return f"{float(f'{number:.2g}'):,.0f}" if number >= 100 else f"{number:.2g}"


class _SliderScene:
    """The figure of ``animate_slider``: the slider panel and the resonance curve."""

    def __init__(self, time_s, y_m, y0_m, curve_hz, curve_app_m, point_hz, point_app_m,
                 frames, title):
        self.time_s, self.y_m = time_s, y_m
        self.index = _samples(y_m.size, frames)
        self.figure = Figure(figsize=(9.0, 3.8), dpi=DPI, layout="constrained")
        left, right = self.figure.subplots(1, 2, width_ratios=[1.0, 1.15])
        if title:
            self.figure.suptitle(title)
        self.panel = _SliderPanel(left, y_m, y0_m)
        _app_axis(right, np.r_[curve_app_m, point_app_m])
        right.plot(curve_hz, curve_app_m * 1e9, color="0.2", lw=1, label="$A_{pp}(f_e)$")
        right.plot([point_hz], [point_app_m * 1e9], "o", color=LOST_COLOUR, ms=7,
                   label=f"now: {point_hz:.5g} Hz, {point_app_m * 1e9:.3g} nm")
        right.legend(fontsize=7, loc="best")
        right.set_title("Resonance curve", fontsize=9)
        self.counter = _counter(self.figure)
        self.frames = frames

    def update(self, frame: int) -> tuple:
        i = self.index[frame]
        self.counter.set_text(f"{frame + 1}/{self.frames}")
        return (*self.panel.show(self.time_s[i], self.y_m[i]), self.counter)


def animate_slider(path, *, time_s, y_m, y0_m, curve_hz, curve_app_m, point_hz, point_app_m,
                   frames: int = 60, fps: float = 20, title: str = "") -> Path:
    """A GIF of the slider riding on its contact, next to its resonance curve.

    Left: the slider on the slideway through a row of asperities; its bottom follows
    ``y_m`` (exaggerated, the scale noted; y points down, so y > 0 presses the
    asperities). Where y <= 0 the slider lifts off: the gap above the asperity tips
    is shaded and "contact lost" shown. Right: the resonance curve ``curve_app_m``
    against ``curve_hz`` with the current point (``point_hz``, ``point_app_m``).
    ``frames`` samples of the history (``time_s``, ``y_m``), evenly spread, are
    drawn at ``fps`` frames per second. Returns the path written.

    Examples
    --------
    >>> import tempfile
    >>> import numpy as np
    >>> from PIL import Image
    >>> t = np.linspace(0, 1 / 1500, 40)
    >>> y = 100e-9 + 300e-9 * np.cos(2 * np.pi * 1500 * t)
    >>> f = np.linspace(1000, 1600, 30)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = animate_slider(f"{folder}/slider.gif", time_s=t, y_m=y, y0_m=225e-9,
    ...                           curve_hz=f, curve_app_m=1e-7 / (1 + ((f - 1450) / 60) ** 2),
    ...                           point_hz=1500.0, point_app_m=6e-7, frames=3)
    ...     with Image.open(path) as gif:
    ...         print(path.name, gif.n_frames)
    slider.gif 3
    """
    path = _gif_path(path)
    t, y = finite_array("time_s", time_s), finite_array("y_m", y_m)
    same_lengths(("time_s", "y_m"), [t], [y])
    increasing("time_s", t)
    f, app = finite_array("curve_hz", curve_hz), finite_array("curve_app_m", curve_app_m)
    same_lengths(("curve_hz", "curve_app_m"), [f], [app])
    frames = check_int("frames", frames, 2, y.size,
                       why=f"one frame per sample of the history ({y.size}) at most")
    fps = check_positive("fps", fps)
    scene = _SliderScene(t, y, check_positive("y0_m", y0_m, allow_zero=True), f, app,
                         check_real("point_hz", point_hz),
                         check_real("point_app_m", point_app_m), frames, str(title))
    return _write(scene.figure, scene.update, frames, fps, path)


# -- a sweep along a resonance curve


def jumps(app_m: np.ndarray) -> np.ndarray:
    """Indices i where A_pp jumps between the swept points i and i + 1: it changes by
    more than ``JUMP_RELATIVE`` of the smaller of the two, and by more than
    ``JUMP_OF_RANGE`` of the range of the curve.

    >>> jumps(np.array([10.0, 12.0, 15.0, 60.0, 55.0, 50.0])).tolist()
    [2]
    """
    step = np.abs(np.diff(app_m))
    smaller = np.minimum(np.abs(app_m[:-1]), np.abs(app_m[1:]))
    return np.flatnonzero((step > JUMP_RELATIVE * smaller)
                          & (step > JUMP_OF_RANGE * np.ptp(app_m)))


class _Run:
    """One swept curve laid out for drawing: the solid curve broken at each jump, where
    it steps half a frequency step sideways to a dashed vertical segment."""

    def __init__(self, f_hz: np.ndarray, app_nm: np.ndarray):
        self.f, self.app = f_hz, app_nm
        self.jumps = jumps(app_nm)
        after_jump = set((self.jumps + 1).tolist())
        x, y, self.shown = [f_hz[0]], [app_nm[0]], [1]  # shown[k]: length drawn at point k
        jx, jy, self.jumps_shown = [], [], [0]
        for k in range(1, f_hz.size):
            if k in after_jump:
                mid = 0.5 * (f_hz[k - 1] + f_hz[k])
                x += [mid, np.nan, mid]
                y += [app_nm[k - 1], np.nan, app_nm[k]]
                jx += [mid, mid, np.nan]
                jy += [app_nm[k - 1], app_nm[k], np.nan]
            x.append(f_hz[k])
            y.append(app_nm[k])
            self.shown.append(len(x))
            self.jumps_shown.append(len(jx))
        self.x, self.y = np.array(x), np.array(y)
        self.jx, self.jy = np.array(jx, dtype=float), np.array(jy, dtype=float)


class _SweepScene:
    """The figure of ``animate_sweep``: the curves drawn up to the current point."""

    def __init__(self, runs: list[_Run], names: list[str | None], frames: int, title: str):
        self.runs, self.names, self.frames = runs, names, frames
        sizes = [run.f.size for run in runs]
        self.starts = np.cumsum([0, *sizes])
        self.index = _samples(int(self.starts[-1]), frames)
        self.figure = Figure(figsize=(6.4, 4.2), dpi=DPI, layout="constrained")
        ax = self.figure.add_subplot()
        all_app = np.concatenate([run.app for run in runs])
        _app_axis(ax, all_app)
        _limits(ax, np.concatenate([run.f for run in runs]), all_app)
        self.curves, self.jump_lines = [], []
        for name in names:
            (curve,) = ax.plot([], [], lw=1.2, **({"label": name} if name else {}))
            (jump,) = ax.plot([], [], ls="--", lw=1.0, color=curve.get_color())
            self.curves.append(curve)
            self.jump_lines.append(jump)
        (self.point,) = ax.plot([], [], "o", ms=7, mec="black")
        self.reading = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8)
        self.jump_note = ax.text(0.02, 0.90, "", transform=ax.transAxes, va="top", fontsize=8,
                                 color="tab:red")
        if any(names):
            ax.legend(fontsize=8, loc="upper right")
        ax.set_title(title or "Sweep along the resonance curve", fontsize=10)
        self.counter = _counter(self.figure)

    def update(self, frame: int) -> tuple:
        point = self.index[frame]
        current = int(np.searchsorted(self.starts, point, side="right")) - 1
        jumped = 0
        for r, (run, curve, jump) in enumerate(zip(self.runs, self.curves, self.jump_lines)):
            k = -1 if r > current else (run.f.size - 1 if r < current
                                        else point - self.starts[r])
            n, m = (0, 0) if k < 0 else (run.shown[k], run.jumps_shown[k])
            curve.set_data(run.x[:n], run.y[:n])
            jump.set_data(run.jx[:m], run.jy[:m])
            jumped += m // 3
        run, k = self.runs[current], point - self.starts[current]
        self.point.set_data([run.f[k]], [run.app[k]])
        self.point.set_color(self.curves[current].get_color())
        name = self.names[current]
        self.reading.set_text(f"{name + ': ' if name else ''}f_e = {run.f[k]:.1f} Hz, "
                              f"A_pp = {run.app[k]:.3g} nm")
        self.jump_note.set_text(f"jumps so far: {jumped}" if jumped else "")
        self.counter.set_text(f"{frame + 1}/{self.frames}")
        return (*self.curves, *self.jump_lines, self.point, self.reading, self.jump_note,
                self.counter)


def animate_sweep(path, *, frequency_hz, app_m, frames: int = 60, fps: float = 20,
                  title: str = "", labels=None) -> Path:
    """A GIF of a point travelling along a swept resonance curve, drawing it behind.

    ``frequency_hz`` and ``app_m`` are 1-D, in the order swept (up then down:
    concatenated), or lists of 1-D arrays, one per run, animated one after the other
    and labelled from ``labels``. A jump of A_pp between neighbouring points (by
    more than 30 % of the smaller value and more than 2 % of the curve's range,
    ``jumps``) is drawn as a vertical dashed segment half-way between them.
    ``frames`` points, evenly spread over all of them, are drawn at ``fps`` frames
    per second. Returns the path written.

    Examples
    --------
    >>> import tempfile
    >>> import numpy as np
    >>> f = np.linspace(1300, 1600, 12)
    >>> app = np.where(f < 1480, 80e-9 + (f - 1300) * 2e-9, 60e-9)  # jumps down
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = animate_sweep(f"{folder}/sweep.gif", frequency_hz=f, app_m=app, frames=3)
    ...     print(path.name, path.stat().st_size > 0)
    sweep.gif True
    """
    path = _gif_path(path)
    fs, apps = curves("frequency_hz", frequency_hz), curves("app_m", app_m)
    same_lengths(("frequency_hz", "app_m"), fs, apps)
    names = curve_labels(labels, len(fs), "run {}")
    total = sum(f.size for f in fs)
    frames = check_int("frames", frames, 2, total,
                       why=f"one frame per swept point ({total}) at most")
    fps = check_positive("fps", fps)
    runs = [_Run(f, app * 1e9) for f, app in zip(fs, apps)]
    scene = _SweepScene(runs, names, frames, str(title))
    return _write(scene.figure, scene.update, frames, fps, path)
