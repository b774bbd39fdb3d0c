"""Attractor census: which steady states coexist at one (P_a, f_e), and their basins.

Lanes start from a grid of initial states, run together to their steady
states, and the distinct orbits are clustered (Section 3.3: bi- and
multi-stability).
"""

from __future__ import annotations

import time

import numpy as np

from common import Result, check_keys, check_positive, finite_array, result
from perturb import ContactModel, eq26_numbers

from ._orbits import Orbits
from ._simulate import check_model
from ._steady import DEFAULTS, steady_states

__all__ = ["Attractor", "Census", "attractors", "DEFAULT_GRID"]

#: Initial states, in units of the static deflection y0 (displacement, as y/y0)
#: and of omega0*y0 (velocity). They cover rest (y = y0, v = 0), small
#: oscillations about it, deep compression, and release from well above the
#: slideway (y < 0: large bouncing states), with velocities up and down.
DEFAULT_GRID = {
    "y_over_y0": (-29.0, -19.0, -11.0, -7.0, -4.0, -2.0, -1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0),
    "v_over_omega0_y0": (-8.0, -3.0, -1.0, 0.0, 1.0, 3.0, 8.0),
}
CLUSTER_TOL = 1e-3  # relative to the orbit's App: states closer than this are one orbit
#: ... but never relative to less than this fraction of y0: the settling test leaves
#: round-off of about tol x 1e-3 y0, so at rest or at tiny forces the orbits reached
#: from different states differ by far less than a picometre; they are one state.
CLUSTER_FLOOR = 1e-2
#: The most initial states of one census (its clustering compares them pairwise).
MAX_INITIAL_STATES = 10_000
#: An orbit whose App is below this fraction of y0 is rest: its harmonics are
#: round-off, and no resonance can be read from them.
REST_FRACTION = 1e-9


@result
class Attractor(Result):
    """One steady state found by the census."""

    period: int
    app_m: float
    ymin_m: float
    ymax_m: float
    basin_fraction: float
    contact_lost: bool
    dominant_harmonic: float  # strongest harmonic of the acceleration, / f_e (0: rest)
    multipliers: np.ndarray  # Floquet multipliers of the orbit (stable: inside the unit circle)
    orbit_y_m: np.ndarray  # y after every step of one orbit

    @property
    def label(self) -> str:
        """The resonance the orbit belongs to, by its strongest harmonic (Section 3.2)."""
        m = self.dominant_harmonic
        if m == 0:
            return "rest"
        if self.period != 1:
            return f"period-{self.period} ({m:g} f_e strongest)"
        return "primary" if m == 1 else f"1/{int(m)} superharmonic"

    def derived(self) -> dict:
        return {"label": self.label}

    def row(self, width: int = 24) -> str:
        """The attractor as a row of the census table."""
        return (f"{self.label:<{width}} period {self.period}  App {self.app_m * 1e9:9.2f} nm  "
                f"ymin {self.ymin_m * 1e9:9.2f} nm  basin {self.basin_fraction:6.1%}"
                f"{'  contact lost' if self.contact_lost else ''}")

    def summary(self) -> str:
        return " ".join(self.row().split())


@result
class Census(Result):
    """The attractors at one (P_a, f_e), largest basin first, and every lane's fate."""

    frequency_hz: float
    pa_frac: float
    model: dict
    settings: dict
    attractors: list[Attractor]
    lanes: Orbits
    elapsed_s: float

    @property
    def not_settled_fraction(self) -> float:
        return float(1 - self.lanes.settled.mean())

    def derived(self) -> dict:
        return {"not_settled_fraction": self.not_settled_fraction}

    def summary(self) -> str:
        return (f"{len(self.attractors)} attractors at f_e = {self.frequency_hz:g} Hz, "
                f"P_a = {self.pa_frac:g} Q ({self.elapsed_s:.2g} s)")

    def table(self) -> str:
        width = max([24] + [len(a.label) for a in self.attractors])
        lines = [f"  {a.row(width)}" for a in self.attractors]
        if self.not_settled_fraction:
            lines.append(f"  of {self.lanes.status.size} initial states: {self.lanes.fates()} "
                         "(not counted as attractors)")
        return "\n".join(lines)


def initial_grid(model: ContactModel, grid: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The census's initial states [m, m/s] from a grid in units of y0 and omega0 y0."""
    grid = DEFAULT_GRID if grid is None else check_keys("grid", grid, tuple(DEFAULT_GRID))
    axes = {key: finite_array(f"grid[{key!r}]", grid[key]) for key in DEFAULT_GRID}
    numbers = eq26_numbers(model.parameters)
    y0, omega0 = numbers.y0_m, numbers.omega0_rad_s
    states = axes["y_over_y0"].size * axes["v_over_omega0_y0"].size
    if states > MAX_INITIAL_STATES:
        raise ValueError(f"`grid` has {states} initial states, more than the limit of "
                         f"{MAX_INITIAL_STATES}: the census clusters its states pairwise.")
    y, v = np.meshgrid(y0 * axes["y_over_y0"], omega0 * y0 * axes["v_over_omega0_y0"])
    return y.ravel(), v.ravel()


def attractors(
    frequency_hz: float,
    pa_frac: float,
    *,
    model: ContactModel | None = None,
    grid: dict | None = None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int | None = DEFAULTS["max_periods"],
) -> Census:
    """Find and cluster the steady states reached from a grid of initial states.

    Parameters
    ----------
    frequency_hz : float
        Excitation frequency f_e [Hz].
    pa_frac : float
        Force amplitude P_a as a fraction of the weight Q.
    model : ContactModel, optional
    grid : dict, optional
        Initial states: ``{"y_over_y0": [...], "v_over_omega0_y0": [...]}``
        (``DEFAULT_GRID`` by default).
    steps_per_period, tol, max_periods
        As in ``steady_states``.

    Examples
    --------
    >>> census = attractors(740.0, 0.15)
    >>> [(a.label, a.contact_lost) for a in census.attractors]
    [('1/2 superharmonic', False), ('primary', True)]
    """
    model = check_model(model)
    f_e = check_positive("frequency_hz", frequency_hz)
    frac = check_positive("pa_frac", pa_frac, allow_zero=True)
    start = time.perf_counter()
    y, v = initial_grid(model, grid)
    found = steady_states(np.full(y.size, f_e), frac * model.parameters.Q_n, model=model,
                          y_init_m=y, v_init_m_s=v, steps_per_period=steps_per_period, tol=tol,
                          max_periods=max_periods, keep_orbits=True)
    y0 = eq26_numbers(model.parameters).y0_m
    census = [_describe(found, members, y.size, y0) for members in _cluster(found, y0)]
    census.sort(key=lambda a: -a.basin_fraction)
    lanes = found.take(np.arange(y.size))
    lanes.orbit_y_m = None  # each attractor keeps its own orbit
    settings = {"initial_states": int(y.size), "grid": grid or DEFAULT_GRID,
                "steps_per_period": steps_per_period, "tol": tol, "max_periods": max_periods,
                "cluster_tol": CLUSTER_TOL, "cluster_floor_y0": CLUSTER_FLOOR,
                "rest_fraction_y0": REST_FRACTION}
    return Census(frequency_hz=f_e, pa_frac=frac, model=model.as_dict(), settings=settings,
                  attractors=census, lanes=lanes, elapsed_s=time.perf_counter() - start)


def _cluster(found, y0: float) -> list[np.ndarray]:
    """Group settled lanes whose period matches and whose ymin, ymax agree within
    CLUSTER_TOL of the orbit's App (or of CLUSTER_FLOOR y0, if that is larger)."""
    groups: list[list[int]] = []
    app = found.app_m
    for lane in np.flatnonzero(found.settled):
        for group in groups:
            first = group[0]
            scale = max(app[first], CLUSTER_FLOOR * y0)
            same = (found.period[first] == found.period[lane]
                    and abs(found.ymin_m[first] - found.ymin_m[lane]) < CLUSTER_TOL * scale
                    and abs(found.ymax_m[first] - found.ymax_m[lane]) < CLUSTER_TOL * scale)
            if same:
                group.append(lane)
                break
        else:
            groups.append([lane])
    return [np.array(g) for g in groups]


def _describe(found, members, total, y0: float) -> Attractor:
    lane = members[0]
    p = int(found.period[lane])
    orbit = found.orbit_y_m[lane]
    resting = found.app_m[lane] < REST_FRACTION * y0
    return Attractor(
        period=p, app_m=float(found.app_m[lane]), ymin_m=float(found.ymin_m[lane]),
        ymax_m=float(found.ymax_m[lane]), basin_fraction=members.size / total,
        contact_lost=bool(found.ymin_m[lane] < 0),
        dominant_harmonic=0.0 if resting else _dominant_harmonic(orbit, p),
        multipliers=found.multipliers[lane],
        orbit_y_m=orbit,
    )


def _dominant_harmonic(orbit: np.ndarray, period: int) -> float:
    """Frequency, over f_e, of the strongest harmonic of the acceleration over one orbit.

    A superharmonic resonance m amplifies the m-th harmonic, whose frequency is
    near f_n0 (Section 3.2); weighting the displacement harmonics c_k by k^2
    (acceleration) lets it stand out above the directly forced first harmonic.
    """
    spectrum = np.abs(np.fft.rfft(orbit))
    k = np.arange(spectrum.size)
    return (1 + int(np.argmax((k**2 * spectrum)[1:]))) / period
