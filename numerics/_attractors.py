"""Attractor census: which steady states coexist at one (P_a, f_e), and their basins.

Lanes start from a grid of initial states, run together to their steady
states, and the distinct orbits are clustered (Section 3.3: bi- and
multi-stability).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import numpy as np

from perturb import ContactModel

from ._info import model_info
from ._simulate import simulate, static_deflection
from ._steady import DEFAULTS, steady_states
from ._validate import lane_array

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


@dataclass
class Attractor:
    """One steady state found by the census."""

    period: int
    app_m: float
    ymin_m: float
    ymax_m: float
    basin_fraction: float
    contact_lost: bool
    dominant_harmonic: float  # frequency of the strongest harmonic of the acceleration, / f_e
    orbit_y_m: np.ndarray = field(default=None, repr=False)  # y over one orbit, per step

    def label(self) -> str:
        """The resonance the orbit belongs to, by its strongest harmonic (Section 3.2)."""
        m = self.dominant_harmonic
        if self.period != 1:
            return f"period-{self.period} ({m:g} f_e strongest)"
        return "primary" if m == 1 else f"1/{int(m)} superharmonic"


@dataclass
class Census:
    """The attractors at one (P_a, f_e), largest basin first."""

    f_e_hz: float
    pa_frac: float
    attractors: list[Attractor]
    not_settled_fraction: float
    settings: dict
    elapsed_s: float

    def as_dict(self) -> dict:
        return {"attractors": [_attractor_dict(a) for a in self.attractors],
                "not_settled_fraction": self.not_settled_fraction,
                "settings": self.settings, "elapsed_s": self.elapsed_s}

    def __str__(self) -> str:
        lines = [f"{len(self.attractors)} attractors at f_e = {self.f_e_hz:g} Hz, "
                 f"P_a = {self.pa_frac:g} Q ({self.elapsed_s:.2g} s)"]
        width = max([24] + [len(a.label()) for a in self.attractors])
        lines += [f"  {a.label():<{width}} period {a.period}  App {a.app_m * 1e9:9.2f} nm  "
                  f"ymin {a.ymin_m * 1e9:9.2f} nm  basin {a.basin_fraction:6.1%}"
                  f"{'  contact lost' if a.contact_lost else ''}" for a in self.attractors]
        if self.not_settled_fraction:
            lines.append(f"  not settled: {self.not_settled_fraction:.1%} of initial states")
        return "\n".join(lines)


def _attractor_dict(attractor: Attractor) -> dict:
    out = asdict(attractor) | {"label": attractor.label()}
    out.pop("orbit_y_m")
    return out


def initial_grid(model: ContactModel, grid: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The census's initial states [m, m/s] from a grid in units of y0 and omega0 y0."""
    grid = DEFAULT_GRID if grid is None else grid
    y0 = static_deflection(model)
    omega0 = model_info(model)["omega0_rad_s"]
    y, v = np.meshgrid(y0 * np.asarray(grid["y_over_y0"], float),
                       omega0 * y0 * np.asarray(grid["v_over_omega0_y0"], float))
    return y.ravel(), v.ravel()


def attractors(
    f_e_hz: float,
    pa_frac: float,
    *,
    model: ContactModel | None = None,
    grid: dict | None = None,
    steps_per_period: int = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int = DEFAULTS["max_periods"],
) -> Census:
    """Find and cluster the steady states reached from a grid of initial states.

    Examples
    --------
    >>> census = attractors(740.0, 0.15)
    >>> [(a.label(), a.contact_lost) for a in census.attractors]
    [('1/2 superharmonic', False), ('primary', True)]
    """
    model = ContactModel() if model is None else model
    f_e = float(lane_array("f_e_hz", f_e_hz, positive=True)[0])
    frac = float(lane_array("pa_frac", pa_frac)[0])
    start = time.perf_counter()
    y, v = initial_grid(model, grid)
    found = steady_states(np.full(y.size, f_e), frac * model.parameters.weight_n, model=model,
                          y_init=y, v_init=v, steps_per_period=steps_per_period, tol=tol,
                          max_periods=max_periods)
    groups = _cluster(found)
    census = [
        _describe(found, members, y.size, model, f_e, frac, steps_per_period)
        for members in groups
    ]
    census.sort(key=lambda a: -a.basin_fraction)
    settings = {"f_e_hz": f_e, "pa_frac": frac, "initial_states": int(y.size),
                "grid": grid or DEFAULT_GRID, "steps_per_period": steps_per_period, "tol": tol,
                "max_periods": max_periods, "cluster_tol": CLUSTER_TOL}
    return Census(f_e_hz=f_e, pa_frac=frac, attractors=census,
                  not_settled_fraction=float(1 - found.settled.mean()), settings=settings,
                  elapsed_s=time.perf_counter() - start)


def _cluster(found) -> list[np.ndarray]:
    """Group settled lanes whose period matches and whose ymin, ymax agree within tol."""
    groups: list[list[int]] = []
    for lane in np.flatnonzero(found.settled):
        for group in groups:
            first = group[0]
            scale = max(found.app[first], 1e-30)
            same = (found.period[first] == found.period[lane]
                    and abs(found.ymin[first] - found.ymin[lane]) < CLUSTER_TOL * scale
                    and abs(found.ymax[first] - found.ymax[lane]) < CLUSTER_TOL * scale)
            if same:
                group.append(lane)
                break
        else:
            groups.append([lane])
    return [np.array(g) for g in groups]


def _describe(found, members, total, model, f_e, frac, steps) -> Attractor:
    lane = members[0]
    p = int(found.period[lane])
    orbit = _orbit(found, lane, model, f_e, frac, int(found.steps_used[lane]))
    return Attractor(
        period=p, app_m=float(found.app[lane]), ymin_m=float(found.ymin[lane]),
        ymax_m=float(found.ymax[lane]), basin_fraction=members.size / total,
        contact_lost=bool(found.ymin[lane] < 0),
        dominant_harmonic=_dominant_harmonic(orbit, p), orbit_y_m=orbit,
    )


def _orbit(found, lane, model, f_e, frac, steps) -> np.ndarray:
    """y after every step of one orbit (p periods) from the lane's orbit start."""
    p = int(found.period[lane])
    run = simulate(f_e, frac * model.parameters.weight_n, periods=p, steps_per_period=steps,
                   model=model, y_init=found.y_start[lane], v_init=found.v_start[lane],
                   record=("history",), record_periods=p)
    return run.history_y[0]


def _dominant_harmonic(orbit: np.ndarray, period: int) -> float:
    """Frequency, over f_e, of the strongest harmonic of the acceleration over one orbit.

    A superharmonic resonance m amplifies the m-th harmonic, whose frequency is
    near f_n0 (Section 3.2); weighting the displacement harmonics c_k by k^2
    (acceleration) lets it stand out above the directly forced first harmonic.
    """
    spectrum = np.abs(np.fft.rfft(orbit))
    k = np.arange(spectrum.size)
    return (1 + int(np.argmax((k**2 * spectrum)[1:]))) / period
