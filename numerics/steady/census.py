"""Attractor census: which steady states coexist at one (P_a, f_e), and their basins.

Lanes start from a grid of initial states, run together to their steady
states, and the distinct orbits are clustered (Section 3.3: bi- and
multi-stability).
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import (
    Result,
    Status,
    check_keys,
    check_positive,
    finite_array,
    lane_array,
    result,
)

from ..simulation.ranges import check_tested
from ..simulation.rk4 import check_model
from .lyapunov import DEFAULTS as LYAPUNOV_DEFAULTS
from .lyapunov import LyapunovExponents, check_run, largest_lyapunov
from .options import SteadyOptions, steady_options
from .orbits import Orbits
from .shooting import DEFAULTS, steady_settings, steady_states

__all__ = ["Attractor", "Census", "attractor_census", "attractors", "censuses", "DEFAULT_GRID"]

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
#: Drive periods over which the largest Lyapunov exponent of each lane that did not
#: settle is measured: its error floor, ln(K) / K per period, is 0.012 at 512, far
#: below the 0.25-0.44 of the chaos measured at 1.5 Q, 1200 Hz (tests/test_lyapunov.py).
LYAPUNOV_PERIODS = 512
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
    #: The largest Lyapunov exponent of each lane that did not settle (None: none, or
    #: not asked for), and those lanes' positions in ``lanes``.
    lyapunov: LyapunovExponents | None = None
    lyapunov_lanes: np.ndarray | None = None

    @property
    def not_settled_fraction(self) -> float:
        return float(1 - self.lanes.settled.mean())

    @property
    def chaotic_fraction(self) -> float:
        """The share of the initial states whose lane is chaotic (its largest Lyapunov
        exponent positive beyond its error): NaN if the exponents were not asked for."""
        if self.lyapunov is None:
            return 0.0 if self.settings.get("lyapunov_periods") else float("nan")
        return self.lyapunov.motion.count("chaotic") / self.lanes.status.size

    def derived(self) -> dict:
        return {"not_settled_fraction": self.not_settled_fraction,
                "chaotic_fraction": self.chaotic_fraction}

    def summary(self) -> str:
        return (f"{len(self.attractors)} attractors at f_e = {self.frequency_hz:g} Hz, "
                f"P_a = {self.pa_frac:g} Q ({self.elapsed_s:.2g} s)")

    def table(self) -> str:
        width = max([24] + [len(a.label) for a in self.attractors])
        lines = [f"  {a.row(width)}" for a in self.attractors]
        if self.not_settled_fraction:
            chaotic = ("" if self.lyapunov is None
                       else f", {self.lyapunov.motion.count('chaotic')} of them chaotic")
            lines.append(f"  of {self.lanes.status.size} initial states: {self.lanes.fates()}"
                         f"{chaotic} (not counted as attractors)")
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


def attractor_census(
    frequency_hz: float,
    pa_frac: float,
    *,
    model: ContactModel | None = None,
    grid: dict | None = None,
    steps_per_period: int | str = DEFAULTS["steps_per_period"],
    tol: float = DEFAULTS["tol"],
    max_periods: int | None = DEFAULTS["max_periods"],
    lyapunov_periods: int | None = LYAPUNOV_PERIODS,
    unchecked: bool = False,
    options: SteadyOptions | None = None,
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
    lyapunov_periods : int or None
        The largest Lyapunov exponent of each lane that does not settle is measured
        over this many periods (``largest_lyapunov``), so that chaos is told apart from
        slow transients; None: not measured.
    unchecked : bool
        Go past the ranges of f_e, P_a and the contact where the answers are measured
        to hold (``numerics.simulation.ranges.TESTED``); refused otherwise.
    options : SteadyOptions, optional
        The steady-state settings as one object, in place of ``steps_per_period``,
        ``tol`` and ``max_periods``.

    Examples
    --------
    >>> census = attractor_census(740.0, 0.15)
    >>> [(a.label, a.contact_lost) for a in census.attractors]
    [('1/2 superharmonic', False), ('primary', True)]
    """
    model = check_model(model)
    f_e = check_positive("frequency_hz", frequency_hz)
    frac = check_positive("pa_frac", pa_frac, allow_zero=True)
    check_tested(f_e, frac, model, unchecked=unchecked)
    options = steady_options(options, steps_per_period=steps_per_period, tol=tol,
                             max_periods=max_periods)
    (census,) = censuses([f_e], [frac], model=model, grid=grid, options=options,
                         lyapunov_periods=lyapunov_periods)
    return census


def attractors(*args, **kwargs) -> Census:
    """Deprecated: ``attractor_census``, named after the ``Census`` it returns."""
    warnings.warn("`attractors()` is deprecated: it is `attractor_census()`, named after the "
                  "Census it returns", DeprecationWarning, stacklevel=2)
    return attractor_census(*args, **kwargs)


def censuses(
    frequency_hz,
    pa_frac,
    *,
    model: ContactModel | None = None,
    grid: dict | None = None,
    options: SteadyOptions | None = None,
    lyapunov_periods: int | None = LYAPUNOV_PERIODS,
) -> list[Census]:
    """``attractor_census`` at many points (f_e, P_a) at once: every lane of every point in
    one batch of ``steady_states``, so that the compiled kernel runs many lanes per call
    (the atlas, ``numerics/steady/multistability.py``).

    Parameters
    ----------
    frequency_hz, pa_frac : array_like, shape (cells,)
        The points: f_e [Hz] (> 0) and P_a / Q (>= 0), one pair per census.
    model, grid, options, lyapunov_periods
        As in ``attractor_census`` (the default options by default).

    Returns
    -------
    list of Census
        One per point, in order; each one's ``elapsed_s`` is the batch's time over the
        number of points.
    """
    model = check_model(model)
    options = SteadyOptions() if options is None else options
    f_e = lane_array("frequency_hz", frequency_hz, positive=True)
    frac = np.broadcast_to(lane_array("pa_frac", pa_frac, f_e.size), f_e.shape)
    check_lyapunov_periods(lyapunov_periods)
    start = time.perf_counter()
    y, v = initial_grid(model, grid)
    states, cells = y.size, f_e.size
    if states * cells > MAX_BATCH_LANES:
        raise ValueError(f"{cells} points x {states} initial states are {states * cells} "
                         f"lanes, more than the limit of {MAX_BATCH_LANES} of one batch "
                         "(each lane keeps its orbit): split the points.")
    found = steady_states(np.repeat(f_e, states), np.repeat(frac * model.parameters.Q_n, states),
                          model=model, y_init_m=np.tile(y, cells), v_init_m_s=np.tile(v, cells),
                          options=options, keep_orbits=True)
    y0 = eq26_numbers(model.parameters).y0_m
    groups = _cluster(found, cells, states, y0)
    unsettled, chaos = _chaos(found, np.repeat(frac, states), model, lyapunov_periods)
    settings = census_settings(grid, states, options, lyapunov_periods)
    elapsed = (time.perf_counter() - start) / cells
    return [_census(found, cell, groups[cell], states, y0, f_e[cell], frac[cell], model,
                    settings, elapsed, unsettled, chaos) for cell in range(cells)]


def census_settings(grid: dict | None, states: int, options: SteadyOptions,
                    lyapunov_periods: int | None) -> dict:
    """The settings a census (and the atlas) records: its own, and the steady-state
    options' step, tol and cap, with any other option that differs from its default."""
    recorded = ("steps_per_period", "tol", "max_periods")
    default = SteadyOptions()
    moved = {name: value for name, value in steady_settings(options).items()
             if name not in recorded and value != getattr(default, name, None)}
    return {"initial_states": int(states), "grid": grid or DEFAULT_GRID,
            **{name: getattr(options, name) for name in recorded}, **moved,
            "lyapunov_periods": lyapunov_periods,
            "cluster_tol": CLUSTER_TOL, "cluster_floor_y0": CLUSTER_FLOOR,
            "rest_fraction_y0": REST_FRACTION}


def check_lyapunov_periods(periods: int | None) -> None:
    """A ValueError naming ``lyapunov_periods`` unless it is None or a run length that
    ``largest_lyapunov`` takes: checked before any work, not when chaos is met."""
    if periods is not None:
        try:
            check_run(periods, LYAPUNOV_DEFAULTS["discard_periods"], LYAPUNOV_DEFAULTS["blocks"])
        except ValueError as error:
            raise ValueError(str(error).replace("`periods`", "`lyapunov_periods`")) from None


def _chaos(found, pa_frac: np.ndarray, model, periods: int | None):
    """The lanes that did not settle, and their largest Lyapunov exponents (None when
    there are none or ``periods`` is None), measured from where each lane stopped, at
    the steps it ran with (the exponent is that of the RK4 map at those steps)."""
    unsettled = np.flatnonzero(found.status == Status.NOT_SETTLED)
    if periods is None or not unsettled.size:
        return unsettled, None
    chaos = largest_lyapunov(found.frequency_hz[unsettled], pa_frac[unsettled],
                             found.y_start_m[unsettled], found.v_start_m_s[unsettled],
                             model=model, steps_per_period=found.steps_used[unsettled],
                             periods=periods)
    for i, lane in enumerate(unsettled):
        if chaos.status[i] == Status.FAILED:
            found.message[lane] += f"; its Lyapunov run failed: {chaos.message[i]}"
            continue
        found.message[lane] += (f"; largest Lyapunov exponent {chaos.exponent_per_period[i]:.3g}"
                                f" +- {chaos.error_per_period[i]:.2g} per period: "
                                f"{chaos.motion[i]}")
    return unsettled, chaos


#: The most lanes (points x initial states) of one ``censuses`` batch: each keeps its
#: orbit (y at every step of a period, a kilobyte or more), and its clustering is done
#: in memory.
MAX_BATCH_LANES = 1_000_000


def _census(found, cell: int, groups: list[np.ndarray], states: int, y0: float, f_e: float,
            frac: float, model: ContactModel, settings: dict, elapsed_s: float,
            unsettled: np.ndarray, chaos: LyapunovExponents | None) -> Census:
    """The census of one point, from its lanes cell * states ... (cell + 1) * states - 1."""
    first = cell * states
    mine = (unsettled >= first) & (unsettled < first + states)
    lyapunov = None if chaos is None or not mine.any() else chaos.take(np.flatnonzero(mine))
    census = [_describe(found, first + members, states, y0) for members in groups]
    census.sort(key=lambda a: -a.basin_fraction)
    lanes = found.take(np.arange(first, first + states))
    lanes.orbit_y_m = None  # each attractor keeps its own orbit
    return Census(frequency_hz=float(f_e), pa_frac=float(frac), model=model.as_dict(),
                  settings=settings, attractors=census, lanes=lanes, elapsed_s=elapsed_s,
                  lyapunov=lyapunov,
                  lyapunov_lanes=None if lyapunov is None else unsettled[mine] - first)


def _cluster(found, cells: int, states: int, y0: float) -> list[list[np.ndarray]]:
    """Per point, the lanes (numbered within the point) of each distinct orbit.

    Settled lanes are one orbit when their period matches and their ymin, ymax agree
    within CLUSTER_TOL of the orbit's App (or of CLUSTER_FLOOR y0, if that is larger),
    the App being that of the orbit's first lane: each pass takes, at every point at
    once, the first lane not yet placed and every later one that matches it. (The
    passes are as many as the most orbits at one point, not as many as lanes.)
    """
    shape = (cells, states)
    period = found.period.reshape(shape)
    ymin, ymax = found.ymin_m.reshape(shape), found.ymax_m.reshape(shape)
    left = found.settled.reshape(shape).copy()  # settled lanes not yet in an orbit
    orbit = np.full(shape, -1)
    rank = 0
    while left.any():
        rows = np.flatnonzero(left.any(axis=1))
        lead = np.argmax(left[rows], axis=1)  # the first lane left at each point
        at = (rows, lead)
        scale = np.maximum(ymax[at] - ymin[at], CLUSTER_FLOOR * y0)[:, None]
        same = (left[rows] & (period[rows] == period[at][:, None])
                & (np.abs(ymin[rows] - ymin[at][:, None]) < CLUSTER_TOL * scale)
                & (np.abs(ymax[rows] - ymax[at][:, None]) < CLUSTER_TOL * scale))
        same[np.arange(rows.size), lead] = True  # an orbit holds its first lane, NaN or not
        orbit[rows] = np.where(same, rank, orbit[rows])
        left[rows] &= ~same
        rank += 1
    return [[np.flatnonzero(row == k) for k in range(row.max() + 1)] for row in orbit]


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
