"""Figures of what a scene records: the spectrum of one period, the phase portrait,
the time history and the fraction of a period spent out of contact.

They take plain numpy arrays in SI units (so they do not depend on the runner) and
show nm, mm/s, ms and Hz on the axes. Contact is lost where y <= 0 (Eq. 2.1).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from perturb.common import check_positive, finite_array

from .figure import finish, on_axes

__all__ = [
    "plot_contact_fraction",
    "plot_phase_portrait",
    "plot_spectrum",
    "plot_time_history",
]

#: harmonics k = 1 .. MAX_HARMONICS drawn against f_e
MAX_HARMONICS = 6
#: a linear axis spanning more decades than this becomes logarithmic
LOG_DECADES = 3.0
EDGE_STYLE = {"color": "tab:red", "lw": 0.8}
Y0_STYLE = {"color": "0.4", "lw": 0.8, "ls": "--"}


# -- checks shared with ``animation``


def finite_2d(name: str, value, *, missing: bool = False) -> np.ndarray:
    """A finite, non-empty float64 array of one or two dimensions; with ``missing``,
    NaN marks a missing value (not +-inf), and at least one value is there."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be real numbers, got {value!r}.") from None
    there = ~np.isnan(array) if missing else np.ones(array.shape, bool)
    if (array.ndim not in (1, 2) or array.size == 0 or not there.any()
            or not np.isfinite(array[there]).all()):
        what = "finite (NaN: missing)" if missing else "finite"
        raise ValueError(f"`{name}` must be a non-empty 1- or 2-dimensional array, {what}, "
                         f"got {value!r}.")
    return array


def curves(name: str, value) -> list[np.ndarray]:
    """One 1-D array, or several: a list of 1-D arrays (lengths may differ) or a 2-D
    array (one row each); every one finite and non-empty."""
    if isinstance(value, (list, tuple)) and value and all(np.ndim(v) == 1 for v in value):
        return [finite_array(f"{name}[{i}]", v) for i, v in enumerate(value)]
    if isinstance(value, np.ndarray) and value.ndim == 2:
        return [finite_array(f"{name}[{i}]", row) for i, row in enumerate(value)]
    return [finite_array(name, value)]


def same_lengths(names: tuple[str, str], first: Sequence, second: Sequence) -> None:
    """``first`` and ``second`` (lists of arrays) pair up one to one, length for length."""
    a, b = names
    if len(first) != len(second):
        raise ValueError(f"`{a}` and `{b}` must hold as many curves, got {len(first)} and "
                         f"{len(second)}.")
    for i, (x, y) in enumerate(zip(first, second)):
        if len(x) != len(y):
            where = f" (curve {i})" if len(first) > 1 else ""
            raise ValueError(f"`{a}` and `{b}` must have the same length{where}, got "
                             f"{len(x)} and {len(y)}.")


def increasing(name: str, values: np.ndarray) -> np.ndarray:
    """``values`` strictly increasing (a time axis)."""
    if np.any(np.diff(values) <= 0):
        raise ValueError(f"`{name}` must be strictly increasing.")
    return values


def curve_labels(labels, count: int, default: str = "curve {}") -> list[str | None]:
    """One label per curve: ``labels`` (checked), else none for a single curve and
    ``default.format(i)`` from 1 for several."""
    if labels is None:
        return [None] if count == 1 else [default.format(i + 1) for i in range(count)]
    if isinstance(labels, (str, bytes)) or not isinstance(labels, Sequence):
        raise ValueError(f"`labels` must be a sequence of strings, one per curve, got "
                         f"{labels!r}.")
    if len(labels) != count:
        raise ValueError(f"`labels` must have one entry per curve ({count}), got "
                         f"{len(labels)}.")
    return [str(label) for label in labels]


def is_wide(values: np.ndarray, decades: float) -> bool:
    """The positive ``values`` span more than ``decades`` decades (and none is <= 0)."""
    values = np.ravel(values)
    if values.size < 2 or values.min() <= 0:
        return False
    return bool(values.max() > values.min() * 10.0**decades)


def static_deflection(y0_m) -> float | None:
    """y0 [m] (>= 0) or None."""
    return None if y0_m is None else check_positive("y0_m", y0_m, allow_zero=True)


# -- the spectrum


def plot_spectrum(harmonic_amplitude_m, path: str | Path | None = None, *,
                  frequency_hz=None, log: bool | None = None, title: str = "",
                  periods: int = 1, ax=None) -> Figure:
    """Amplitudes of the harmonics k = 0, 1, 2, ... of one period of y, in nm.

    A spectrum of ``periods`` = p excitation periods (an orbit of period p, or a
    recorded time history) has its harmonic k at k f_e / p; the axis says so.

    A 1-D array (index = k) is drawn as bars; k = 0, the mean offset of y, is drawn
    hatched and grey, and labelled with its value. The y axis is logarithmic when
    the bars span more than three decades (``log`` forces it on or off; on a log
    axis the mean is drawn by its size).

    A 2-D array (points, harmonics) with ``frequency_hz`` (points,) is drawn as the
    amplitudes of the harmonics k = 1 .. 6 against f_e, one line each, on a log
    axis (zeros, and NaN for a point without a spectrum, are left out as gaps).

    Examples
    --------
    >>> figure = plot_spectrum([230e-9, 150e-9, 12e-9, 0.9e-9, 0.04e-9])
    >>> ax = figure.axes[0]
    >>> ax.get_yscale(), [round(float(bar.get_height()), 2) for bar in ax.patches][:3]
    ('log', [230.0, 150.0, 12.0])
    >>> over_f = plot_spectrum([[220e-9, 40e-9, 3e-9], [230e-9, 150e-9, 12e-9]],
    ...                        frequency_hz=[1000.0, 1400.0])
    >>> [line.get_label() for line in over_f.axes[0].lines]
    ['k = 1 (f_e)', 'k = 2 (2 f_e)']
    >>> plot_spectrum([230e-9, 1e-9, 150e-9], periods=2).axes[0].get_xlabel()
    'harmonic $k$ (frequency $k f_e / 2$)'
    """
    amplitude = finite_2d("harmonic_amplitude_m", harmonic_amplitude_m, missing=True)
    if amplitude.ndim == 2:
        return _spectrum_against_frequency(amplitude, frequency_hz, path, log, title, ax)
    finite_2d("harmonic_amplitude_m", amplitude)  # one spectrum: no value missing
    if frequency_hz is not None:
        raise ValueError("`frequency_hz` goes with a 2-D `harmonic_amplitude_m` (points, "
                         "harmonics); this one is 1-D, one spectrum.")
    _check_amplitudes(amplitude[1:], first_k=1)
    figure, ax = on_axes(ax)
    nm = amplitude * 1e9
    log = is_wide(np.abs(nm[np.abs(nm) > 0]), LOG_DECADES) if log is None else bool(log)
    heights = np.abs(nm) if log else nm
    ax.bar([0], heights[:1], color="0.8", edgecolor="0.3", hatch="//",
           label=f"k = 0: mean offset {nm[0]:.4g} nm")
    if nm.size > 1:
        ax.bar(np.arange(1, nm.size), heights[1:], color="tab:blue", label="harmonics k >= 1")
    if log:
        ax.set_yscale("log")
        shown = heights[heights > 0]
        if shown.size:
            ax.set_ylim(bottom=shown.min() / 3)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    if periods == 1:
        ax.set_xlabel("harmonic $k$ (frequency $k f_e$)")
    else:
        ax.set_xlabel(f"harmonic $k$ (frequency $k f_e / {periods}$)")
    ax.set_ylabel("amplitude [nm]")
    ax.set_title(title or ("Spectrum of one period of $y$" if periods == 1 else
                           f"Spectrum of {periods} excitation periods of $y$"))
    ax.legend(fontsize="small")
    return finish(figure, path)


def _check_amplitudes(amplitude: np.ndarray, first_k: int) -> None:
    """Amplitudes of the harmonics k >= 1 are >= 0."""
    negative = np.argwhere(amplitude < 0)
    if negative.size:
        k = int(negative[0][-1]) + first_k
        raise ValueError(f"`harmonic_amplitude_m` must be >= 0 for the harmonics k >= 1 "
                         f"(amplitudes), got {float(amplitude[tuple(negative[0])])!r} at k = {k}.")


def _spectrum_against_frequency(amplitude: np.ndarray, frequency_hz, path, log, title,
                                ax) -> Figure:
    if frequency_hz is None:
        raise ValueError("`frequency_hz` is needed with a 2-D `harmonic_amplitude_m` (points, "
                         "harmonics): the f_e of each point.")
    f = finite_array("frequency_hz", frequency_hz)
    if f.size != amplitude.shape[0]:
        raise ValueError(f"`harmonic_amplitude_m` must have one row per frequency: "
                         f"{amplitude.shape[0]} rows, `frequency_hz` has {f.size} points.")
    if amplitude.shape[1] < 2:
        raise ValueError("`harmonic_amplitude_m` must hold at least k = 0 and k = 1 (2 "
                         f"columns), got shape {amplitude.shape}.")
    _check_amplitudes(amplitude[:, 1:], first_k=1)
    figure, ax = on_axes(ax)
    log = True if log is None else bool(log)
    for k in range(1, min(amplitude.shape[1], MAX_HARMONICS + 1)):
        nm = amplitude[:, k] * 1e9
        if log:
            nm = np.where(nm > 0, nm, np.nan)
        harmonic = "f_e" if k == 1 else f"{k} f_e"
        ax.plot(f, nm, marker=".", ms=3, lw=1, label=f"k = {k} ({harmonic})")
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("amplitude of harmonic $k$ [nm]")
    ax.set_title(title or "Harmonics of $y$ against $f_e$")
    ax.legend(fontsize="small")
    return finish(figure, path)


# -- the phase portrait and the time history


def plot_phase_portrait(y_m, v_m_s, path: str | Path | None = None, *, y0_m=None,
                        labels=None, title: str = "", ax=None) -> Figure:
    """Velocity (mm/s) against displacement (nm) over one or several orbits.

    ``y_m``, ``v_m_s``: 1-D arrays, or lists of 1-D arrays (one per orbit, labelled
    from ``labels`` or "orbit 1", "orbit 2", ...). A vertical line marks the contact
    edge y = 0 when an orbit reaches it, another the static deflection ``y0_m``.

    Examples
    --------
    >>> import numpy as np
    >>> phase = np.linspace(0, 2 * np.pi, 100)
    >>> y, v = 225e-9 + 300e-9 * np.cos(phase), -2.8e-3 * np.sin(phase)
    >>> figure = plot_phase_portrait(y, v, y0_m=225e-9)
    >>> [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
    ['contact edge y = 0', 'static deflection y0 = 225 nm']
    """
    ys, vs = curves("y_m", y_m), curves("v_m_s", v_m_s)
    same_lengths(("y_m", "v_m_s"), ys, vs)
    names = curve_labels(labels, len(ys), "orbit {}")
    y0 = static_deflection(y0_m)
    figure, ax = on_axes(ax)
    for y, v, name in zip(ys, vs, names):
        ax.plot(y * 1e9, v * 1e3, lw=1, **({"label": name} if name else {}))
    if min(y.min() for y in ys) <= 0:
        ax.axvline(0.0, **EDGE_STYLE, label="contact edge y = 0")
    if y0 is not None:
        ax.axvline(y0 * 1e9, **Y0_STYLE, label=f"static deflection y0 = {y0 * 1e9:.3g} nm")
    ax.set_xlabel("displacement $y$ [nm]")
    ax.set_ylabel("velocity $\\dot{y}$ [mm/s]")
    ax.set_title(title or "Phase portrait")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small")
    return finish(figure, path)


def out_of_contact(time_s: np.ndarray, y_m: np.ndarray) -> np.ndarray:
    """(start, end) times of the intervals where y <= 0, shape (intervals, 2); the
    crossings of y = 0 between two samples are interpolated linearly."""
    out = y_m <= 0
    if not out.any():
        return np.empty((0, 2))
    change = np.diff(out.astype(np.int8))
    first = np.flatnonzero(change == 1) + 1  # first sample out of contact
    last = np.flatnonzero(change == -1)  # last sample out of contact
    if out[0]:
        first = np.r_[0, first]
    if out[-1]:
        last = np.r_[last, y_m.size - 1]
    start, end = time_s[first].astype(float), time_s[last].astype(float)
    inner = first > 0  # y[first - 1] > 0 >= y[first]
    before = first[inner] - 1
    start[inner] = _crossing(time_s, y_m, before, before + 1)
    inner = last < y_m.size - 1  # y[last] <= 0 < y[last + 1]
    end[inner] = _crossing(time_s, y_m, last[inner], last[inner] + 1)
    return np.column_stack([start, end])


def _crossing(t: np.ndarray, y: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Where the straight line from (t[i], y[i]) to (t[j], y[j]) crosses y = 0
    (y[i] and y[j] on either side, one of them > 0: the divisor is never 0)."""
    return t[i] + (t[j] - t[i]) * y[i] / (y[i] - y[j])


def plot_time_history(time_s, y_m, path: str | Path | None = None, *, y0_m=None,
                      title: str = "", ax=None) -> Figure:
    """y(t) in nm against t in ms; the intervals out of contact (y <= 0) shaded.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 / 1500, 200)
    >>> figure = plot_time_history(t, 100e-9 + 300e-9 * np.cos(2 * np.pi * 1500 * t),
    ...                            y0_m=225e-9)
    >>> shade = figure.axes[0].collections[0]
    >>> shade.get_label(), len(shade.get_paths())
    ('out of contact (y <= 0)', 2)
    """
    t, y = finite_array("time_s", time_s), finite_array("y_m", y_m)
    same_lengths(("time_s", "y_m"), [t], [y])
    increasing("time_s", t)
    y0 = static_deflection(y0_m)
    figure, ax = on_axes(ax, (7.0, 3.6))
    ax.plot(t * 1e3, y * 1e9, lw=1, color="tab:blue", label="$y(t)$")
    intervals = out_of_contact(t, y) * 1e3
    if intervals.size:
        boxes = [[(a, 0), (b, 0), (b, 1), (a, 1)] for a, b in intervals]
        ax.add_collection(PolyCollection(boxes, transform=ax.get_xaxis_transform(),
                                         facecolor="tab:red", alpha=0.2, edgecolor="none",
                                         label="out of contact (y <= 0)"), autolim=False)
        ax.axhline(0.0, **EDGE_STYLE, label="contact edge y = 0")
    if y0 is not None:
        ax.axhline(y0 * 1e9, **Y0_STYLE, label=f"static deflection y0 = {y0 * 1e9:.3g} nm")
    ax.set_xlabel("time $t$ [ms]")
    ax.set_ylabel("displacement $y$ [nm]")
    ax.set_title(title or "Time history")
    ax.legend(fontsize="small", loc="best")
    return finish(figure, path)


# -- the fraction of a period out of contact


def plot_contact_fraction(frequency_hz, fraction, path: str | Path | None = None, *,
                          labels=None, title: str = "", ax=None) -> Figure:
    """Share of each excitation period spent out of contact (y <= 0), in %, against f_e.

    ``fraction`` is 1-D (points,) or 2-D (curves, points), in [0, 1] (NaN: no value,
    a gap), over the common ``frequency_hz`` (points,); ``labels`` names the curves.

    Examples
    --------
    >>> figure = plot_contact_fraction([1000.0, 1200.0, 1400.0], [[0, 0.1, 0.3], [0, 0, 0.2]],
    ...                                labels=["0.30 Q", "0.20 Q"])
    >>> [line.get_ydata().tolist() for line in figure.axes[0].lines]
    [[0.0, 10.0, 30.0], [0.0, 0.0, 20.0]]
    """
    f = finite_array("frequency_hz", frequency_hz)
    share = np.atleast_2d(finite_2d("fraction", fraction, missing=True))
    if share.shape[1] != f.size:
        raise ValueError(f"`fraction` must have one value per frequency on each curve: "
                         f"{share.shape[1]} values, `frequency_hz` has {f.size}.")
    outside = (share < 0) | (share > 1)
    if outside.any():
        bad = share[outside][0]
        raise ValueError(f"`fraction` must lie in [0, 1] (a share of the period), got "
                         f"{float(bad)!r}.")
    names = curve_labels(labels, share.shape[0])
    figure, ax = on_axes(ax)
    for values, name in zip(share, names):
        ax.plot(f, values * 100, marker=".", ms=3, lw=1, **({"label": name} if name else {}))
    ax.set_ylim(-2, 102)
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("time out of contact [% of the period]")
    ax.set_title(title or "Loss of contact against $f_e$")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small")
    return finish(figure, path)
