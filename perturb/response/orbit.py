"""The orbit a root of the series describes, as the simulator sees an orbit.

A root omega of the frequency equation at f_e (Eq. 2.7, 2.8) gives
u(t) = sum_k Re(H_k exp(i k Omega t)) in the frame of the excitation
P_a cos(Omega t) (Eq. 2.2). The simulator's orbits start at the drive's phase 0,
so the series' orbit starts at y = y0 + u(0) = y0 + sum_k Re H_k and
v = u'(0) = -Omega sum_k k Im H_k (Eq. 2.1: y = y0 + u): a steady state of the
full model can be sought from there. Its local extrema over a period are the
points of Fig. 3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.parameters import PAPER, ContactParameters
from ..series.formulas import compile_series
from ..series.truncation import series_values
from .frequency import Branch
from .numpy_route import harmonics_in_drive_frame, refined_at, sample_waveform

__all__ = ["SeriesOrbits", "series_orbits"]


@dataclass(frozen=True)
class SeriesOrbits:
    """Per point of a branch: the orbit's state at the drive's phase 0 and its extrema.

    Attributes
    ----------
    y_start_m, v_start_m_s : ndarray
        y = y0 + u and v = du/dt at the drive's phase 0 [m, m/s].
    maxima_m, minima_m : list of ndarray
        Every local maximum and minimum of y over a period (the largest and least
        alone where u is flat: at rest).
    """

    y_start_m: np.ndarray
    v_start_m_s: np.ndarray
    maxima_m: list[np.ndarray]
    minima_m: list[np.ndarray]


def series_orbits(branch: Branch, order: int, parameters: ContactParameters = PAPER,
                  samples: int = 256, truncation: str = "consistent") -> SeriesOrbits:
    """The orbits of ``branch``, a branch of ``frequency_response(..., order,
    parameters=..., truncation=...)``.

    Examples
    --------
    >>> import numpy as np
    >>> from perturb import frequency_response
    >>> branch = frequency_response(np.array([1000.0]), 0.05, 6, truncation="paper").branches[0]
    >>> orbit = series_orbits(branch, 6, truncation="paper")
    >>> round(float(orbit.y_start_m[0]) * 1e9, 2), round(float(orbit.v_start_m_s[0]) * 1e6, 3)
    (235.49, 2.925)
    """
    values = series_values(parameters)
    formulas = compile_series(order, truncation, parameters)
    Omega = 2 * np.pi * np.asarray(branch.frequency_hz, dtype=float)
    at_rest = np.asarray(branch.a0_m) == 0  # P_a = 0: b_n divides by A0 (Eq. 2.10)
    harmonics = np.zeros((Omega.size, 1), dtype=complex)
    if not at_rest.all():
        _check_roots(formulas, values, branch, Omega, at_rest, truncation)
        harmonics = harmonics_in_drive_frame(formulas, values, branch.a0_m,
                                             branch.omega_rad_s, Omega)
        harmonics[at_rest] = 0.0
    k = np.arange(harmonics.shape[-1])
    u = sample_waveform(harmonics, samples)
    maxima, minima = _local_extrema(u, np.greater), _local_extrema(-u, np.greater)
    return SeriesOrbits(y_start_m=values.y0_m + harmonics.real.sum(axis=-1),
                        v_start_m_s=0.0 - Omega * (k * harmonics.imag).sum(axis=-1),
                        maxima_m=[values.y0_m + m for m in maxima],
                        minima_m=[values.y0_m - m for m in minima])


def _check_roots(formulas, values, branch, Omega, at_rest, truncation) -> None:
    """Raise a ValueError naming ``truncation`` if the branch's roots are not roots of
    that series' frequency equation (Eq. 2.7): a branch of the other truncation, whose
    orbits would come out wrong by as much as the truncations differ."""
    from .numpy_route import series_arguments

    omega, a0 = branch.omega_rad_s[~at_rest], branch.a0_m[~at_rest]
    shift = formulas.frequency_shift(a0, omega, Omega[~at_rest],
                                     *series_arguments(formulas, values))
    residual = np.abs(omega**2 - values.omega0_rad_s**2 - shift) / omega**2
    if np.any(residual > 1e-8):
        raise ValueError(f"`branch` is not a branch of the {truncation!r} series of order "
                         f"{formulas.order} at these parameters (its frequency equation is "
                         f"off by {float(residual.max()):.1e} there): pass the `truncation` "
                         "and `parameters` of the response it comes from.")


def _local_extrema(u: np.ndarray, above) -> list[np.ndarray]:
    """Every local maximum of periodic samples u (lanes, samples), refined by a parabola;
    the largest sample alone where there is none (u flat)."""
    peak = above(u, np.roll(u, 1, axis=1)) & ~above(np.roll(u, -1, axis=1), u)
    flat = ~peak.any(axis=1)
    peak[flat, np.argmax(u[flat], axis=1)] = True
    rows, j = np.nonzero(peak)
    values = refined_at(u, rows, j)
    return np.split(values, np.cumsum(peak.sum(axis=1))[:-1])
