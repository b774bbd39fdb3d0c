"""The largest Lyapunov exponent of a lane: chaos told apart from slow transients.

A lane that never settles (``Status.NOT_SETTLED``) may be chaotic, quasi-periodic,
periodic with a period above those tried, or a transient slower than the cap. The
largest Lyapunov exponent tells them apart: the mean rate at which a small
perturbation of the state grows,

    lambda = lim_{K -> oo} 1 / (K T) sum_k ln( |w_k| / |w_(k-1)| ),

w_k the tangent vector after k drive periods T = 1 / f_e (Benettin et al., 1980).
The tangent is the derivative of the very RK4 map that the simulator iterates
(``rk4_step_tangents``, through loss of contact: the acceleration of Eq. 2.1-2.4 is
continuous across y = 0, so the map is piecewise smooth and needs no saltation), so
on a periodic orbit of period p lambda is ln|mu_max| / (p T), mu_max the largest
Floquet multiplier of the monodromy matrix that ``steady_states`` computes; in the
linear regime it is -c, the decay rate of Eq. 2.6's u'' + 2c u' + omega0^2 u.

The compiled kernel ``lyapunov_periods`` advances all lanes with one tangent vector
each, renormalising it once per period, and sums the log growths in blocks of
periods: the spread of the block means, with a bound on the bias of a finite run,
is the error estimate. A lane-period costs 1.3 to 1.6 times that of the plain march
of the same lanes (tests/benchmarks/bench_lyapunov.py, four runs).
"""

from __future__ import annotations

import time
from dataclasses import fields

import numpy as np

from perturb import ContactModel, eq26_numbers
from perturb.common import Result, Status, check_int, lane_array, result

from ..kernels.lanes import Lanes
from ..simulation.rk4 import check_model, initial_lanes
from .options import MAX_STEPS, check_steps
from .shooting import lane_steps

__all__ = ["LyapunovExponents", "largest_lyapunov", "classify_motion", "VERDICTS", "DEFAULTS"]

#: Periods measured, periods discarded first (while the tangent turns into the most
#: expanding direction), and blocks the measured periods are split into.
DEFAULTS = {"steps_per_period": "auto", "periods": 2048, "discard_periods": 64, "blocks": 8}
#: The tangent's first direction, an angle in the plane (y, v / v_scale): generic, so
#: that it is along no eigenvector of a simple orbit's monodromy matrix.
INITIAL_ANGLE = 1.0
#: The longest run (periods measured plus discarded): the steady-state search's own cap
#: on a transient, shooting.CAP_PERIODS, is the same.
MAX_PERIODS = 120_000
#: The most lanes of one call, refused before the lanes' arrays are made ...
MAX_LANES = 1_000_000
#: ... and the most RK4 lane-steps (lanes x periods x steps per period) of one call: at
#: some 4 ns a lane-step with the tangent (tests/benchmarks/bench_lyapunov.py: 2.1-3.5 us
#: a lane-period at 512 steps) a minute or two.
MAX_LANE_STEPS = 2 * 10**10
#: A verdict needs the exponent this many error estimates away from zero.
VERDICT_SIGMAS = 3.0
VERDICTS = ("chaotic", "periodic or transient", "undecided")


@result
class LyapunovExponents(Result):
    """Per lane, the largest Lyapunov exponent and its error estimate.

    Attributes
    ----------
    frequency_hz, pa_frac : ndarray, shape (lanes,)
        Excitation frequency f_e [Hz] and force amplitude P_a / Q.
    exponent_per_s : ndarray
        The largest Lyapunov exponent lambda [1/s] (NaN where the lane failed).
    error_per_s : ndarray
        Its error estimate [1/s]: the largest of the standard error of the block means,
        half the difference between the means of the two halves of the run, and
        ln(K) / (K T) after K periods, the finite-time bias of a regular motion.
    block_exponent_per_s : ndarray, shape (lanes, blocks)
        lambda measured over each block of consecutive periods (its convergence).
    status, message :
        ``Status.SUCCESS``, or ``Status.FAILED`` with why.
    steps_used : ndarray of int
        RK4 steps per period of each lane.
    y_final_m, v_final_m_s : ndarray
        The state at the end of the run (to continue it).
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    frequency_hz: np.ndarray
    pa_frac: np.ndarray
    exponent_per_s: np.ndarray
    error_per_s: np.ndarray
    block_exponent_per_s: np.ndarray
    status: np.ndarray
    message: list[str]
    steps_used: np.ndarray
    y_final_m: np.ndarray
    v_final_m_s: np.ndarray
    model: dict
    settings: dict
    elapsed_s: float

    @property
    def exponent_per_period(self) -> np.ndarray:
        """lambda T: the mean log growth of a perturbation per drive period."""
        return self.exponent_per_s / self.frequency_hz

    @property
    def error_per_period(self) -> np.ndarray:
        return self.error_per_s / self.frequency_hz

    @property
    def motion(self) -> list[str]:
        """Per lane, ``classify_motion``'s verdict (one of VERDICTS)."""
        return classify_motion(self.exponent_per_period, self.error_per_period)

    def derived(self) -> dict:
        return {"exponent_per_period": self.exponent_per_period,
                "error_per_period": self.error_per_period, "motion": self.motion}

    def take(self, index) -> LyapunovExponents:
        """The lanes ``index`` (an integer array), as a new result (a census's share of a
        batch run over many points)."""
        index = np.asarray(index, dtype=np.int64)
        lanes = {f.name: getattr(self, f.name)[index] for f in fields(self)
                 if isinstance(getattr(self, f.name), np.ndarray)}
        return LyapunovExponents(**lanes, message=[self.message[i] for i in index],
                                 model=self.model, settings=self.settings,
                                 elapsed_s=self.elapsed_s)

    def summary(self) -> str:
        motion = self.motion
        counts = {v: motion.count(v) for v in VERDICTS if v in motion}
        return (f"LyapunovExponents: {self.status.size} lanes, {counts}, "
                f"{self.elapsed_s:.3g} s")

    def table(self) -> str:
        lines = [f"  {'f_e [Hz]':>10} {'P_a/Q':>7} {'lambda T':>10} {'+-':>8}  motion"]
        rate, error, motion = self.exponent_per_period, self.error_per_period, self.motion
        for i in range(min(self.status.size, 20)):
            lines.append(f"  {self.frequency_hz[i]:>10.6g} {self.pa_frac[i]:>7.4g} "
                         f"{rate[i]:>10.4g} {error[i]:>8.2g}  {motion[i]}")
        return "\n".join(lines)


def classify_motion(exponent_per_period, error_per_period) -> list[str]:
    """What a lane's largest Lyapunov exponent says of its motion.

    - "chaotic": lambda T > 3 error: nearby states separate, at a rate measured to be
      positive, over the periods measured (chaos that ends later, transient chaos,
      cannot be told from chaos that lasts by any finite run);
    - "periodic or transient": lambda T < -3 error: nearby states converge, so the
      lane is on (or approaching) a stable orbit, perhaps of a period above those
      ``steady_states`` tries, or a transient slower than its cap;
    - "undecided": anything else, a NaN included. A quasi-periodic motion (a torus)
      has lambda = 0 and lands here, as does a run too short for its noise, and a lane
      whose motion changes within the run (transient chaos that ends on an orbit: its
      ``block_exponent_per_s`` show where, and its final state is on the orbit).

    Three error estimates (VERDICT_SIGMAS) make a wrong sign unlikely: 0.1 % one-sided
    were the estimate normal. The error of ``largest_lyapunov`` holds the finite-time
    bias of a regular motion, ln(K) / K per period after K periods, so that lambda = 0
    is not called chaotic at any run length (tests/test_lyapunov.py: on quasi-periodic
    tori lambda T came out at 0.3 to 0.5 of it). Measured in the tests: lambda T of
    0.25 to 0.44 on the chaotic lanes at 1.5 Q, 1200 Hz; -0.022 and -0.025 on the
    period-7 and period-6 flight orbits beside them; -0.17 and -0.12 on the primary
    orbits at 0.05 Q, 1000 and 1400 Hz; 0.37, then -0.073 once landed on the period-2
    orbit, on the transiently chaotic lanes at 2 Q, 1600 Hz.

    Parameters
    ----------
    exponent_per_period, error_per_period : float or array_like
        lambda T and its error estimate (``LyapunovExponents.exponent_per_period``).

    Examples
    --------
    >>> classify_motion([0.3, -0.02, 0.001], [0.01, 1e-3, 1e-3])
    ['chaotic', 'periodic or transient', 'undecided']
    """
    rate = np.atleast_1d(np.asarray(exponent_per_period, dtype=float))
    margin = VERDICT_SIGMAS * np.broadcast_to(np.asarray(error_per_period, dtype=float),
                                              rate.shape)
    with np.errstate(invalid="ignore"):
        chaotic, regular = rate > margin, rate < -margin
    return [VERDICTS[0] if c else VERDICTS[1] if r else VERDICTS[2]
            for c, r in zip(chaotic, regular)]


def largest_lyapunov(
    frequency_hz,
    pa_frac,
    y_init_m,
    v_init_m_s,
    *,
    model: ContactModel | None = None,
    steps_per_period=DEFAULTS["steps_per_period"],
    periods: int = DEFAULTS["periods"],
    discard_periods: int = DEFAULTS["discard_periods"],
    blocks: int = DEFAULTS["blocks"],
) -> LyapunovExponents:
    """The largest Lyapunov exponent of each lane, by Benettin's method.

    Parameters
    ----------
    frequency_hz, pa_frac : float or array_like, shape (lanes,)
        Excitation frequency f_e [Hz] and force amplitude P_a as a fraction of Q.
    y_init_m, v_init_m_s : float or array_like, shape (lanes,)
        The states to start from [m, m/s]; for a lane that did not settle, the state
        where it stopped (``Orbits.y_start_m``, ``v_start_m_s``), on its attractor.
    model : ContactModel, optional
    steps_per_period : int, "auto" or array_like of int
        RK4 steps per period, per lane where an array (a census's ``steps_used``);
        "auto" as in ``steady_states``. The exponent is that of the RK4 map at
        these steps: use the steps the lane's state was found with.
    periods : int
        Drive periods measured (a multiple of ``blocks``).
    discard_periods : int
        Periods run first and not measured, while the tangent turns into the most
        expanding direction (and the state onto its attractor).
    blocks : int
        The measured periods are split into this many blocks (even, >= 4); the
        spread of their means gives the error estimate.

    Returns
    -------
    LyapunovExponents

    Examples
    --------
    From rest at P_a = 1.5 Q, 1200 Hz the slider bounces chaotically; at 1e-6 Q it
    stays on the linearised contact, whose perturbations decay at the rate c of Eq. 2.6:

    >>> from perturb import eq26_numbers
    >>> numbers = eq26_numbers()
    >>> run = largest_lyapunov([1200.0, 1000.0], [1.5, 1e-6], numbers.y0_m, 0.0)
    >>> run.motion
    ['chaotic', 'periodic or transient']
    >>> round(float(run.exponent_per_s[1]), 2), round(-numbers.c_per_s, 2)
    (-168.41, -168.41)
    """
    model = check_model(model)
    periods, discard, blocks = check_run(periods, discard_periods, blocks)
    lanes = np.broadcast_shapes(*(np.shape(a) for a in (frequency_hz, pa_frac, y_init_m,
                                                        v_init_m_s)))
    if int(np.prod(lanes)) > MAX_LANES:
        raise ValueError(f"{int(np.prod(lanes))} lanes are more than the limit of {MAX_LANES} "
                         "of one call (a bound on memory and work): split them.")
    f_e, pa, y, v = initial_lanes(frequency_hz, lane_array("pa_frac", pa_frac), y_init_m,
                                  v_init_m_s, model)
    numbers = eq26_numbers(model.parameters)
    steps = _lane_steps(steps_per_period, f_e, numbers.fastest_rate_per_s)
    work = int(steps.sum()) * (periods + discard)
    if work > MAX_LANE_STEPS:
        raise ValueError(f"the lanes' steps per period x (`periods` + `discard_periods`) "
                         f"ask for {work:.3g} RK4 lane-steps, more than the limit of "
                         f"{MAX_LANE_STEPS:.0e} of one call (a minute or two): take fewer "
                         "periods or lanes.")
    start = time.perf_counter()
    n = f_e.size
    growth = np.full((n, blocks), np.nan)
    status = np.full(n, Status.SUCCESS, dtype=np.int64)
    message = [""] * n
    for count in np.unique(steps):
        group = np.flatnonzero(steps == count)
        lanes = Lanes(model, f_e[group], pa[group] * numbers.Q_n, int(count))
        yg, vg, sums, failed = _benettin(lanes, y[group], v[group], _velocity_scale(numbers),
                                         periods, discard, blocks)
        y[group], v[group], growth[group] = yg, vg, sums
        status[group[failed >= 0]] = Status.FAILED
        for lane, why in zip(group, lanes.failure_messages(failed)):
            message[lane] = why
    block_rate = growth * (blocks / periods) * f_e[:, None]  # ln growth per second
    block_rate[status == Status.FAILED] = np.nan
    exponent, error = _mean_and_error(block_rate, f_e, periods)
    settings = {"steps_per_period": _jsonable_steps(steps_per_period), "periods": periods,
                "discard_periods": discard, "blocks": blocks}
    return LyapunovExponents(
        frequency_hz=f_e, pa_frac=pa, exponent_per_s=exponent, error_per_s=error,
        block_exponent_per_s=block_rate, status=status, message=message, steps_used=steps,
        y_final_m=y, v_final_m_s=v, model=model.as_dict(), settings=settings,
        elapsed_s=time.perf_counter() - start)


def _benettin(lanes: Lanes, y, v, v_scale: float, periods: int, discard: int, blocks: int):
    """Run ``discard`` periods, then ``periods`` in ``blocks`` blocks, one compiled call
    each; returns the final states, the log growth summed per block, and the period
    in which each lane failed (-1: none)."""
    n = y.size
    dy = np.full(n, np.cos(INITIAL_ANGLE))
    dv = np.full(n, np.sin(INITIAL_ANGLE) * v_scale)
    failed = np.full(n, -1, dtype=np.int64)
    args = (lanes.dt, lanes.p_a, lanes.drive, v_scale)
    if discard:
        lanes.kernels.lyapunov_periods(y, v, dy, dv, *args, np.empty((n, 1)), discard, failed,
                                       0, lanes.limit)
    sums = np.empty((n, blocks))
    lanes.kernels.lyapunov_periods(y, v, dy, dv, *args, sums, periods // blocks, failed,
                                   discard, lanes.limit)
    return y, v, sums, failed


def _mean_and_error(block_rate: np.ndarray, frequency_hz: np.ndarray, periods: int
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The mean of the block exponents [1/s] and its error estimate: the largest of

    - their standard error (blocks taken as independent: each spans many correlation
      times of a chaotic lane's growth);
    - half the gap between the two halves' means (a drift: a transient, or a slowly
      turning tangent);
    - ln(K) / (K T) for K periods: the finite-time exponent of a tangent that grows
      linearly in time, as it does on a quasi-periodic torus with twist, whose
      lambda is 0 (a regular motion's tangent grows no faster than a power of t).
    """
    blocks = block_rate.shape[1]
    with np.errstate(invalid="ignore"):
        mean = block_rate.mean(axis=1)
        standard_error = block_rate.std(axis=1, ddof=1) / np.sqrt(blocks)
        halves = block_rate.reshape(-1, 2, blocks // 2).mean(axis=2)
        drift = np.abs(halves[:, 0] - halves[:, 1]) / 2
    regular_bias = np.log(periods) / periods * frequency_hz
    return mean, np.maximum.reduce([standard_error, drift, regular_bias])


def _velocity_scale(numbers) -> float:
    """The velocity that weighs a tangent's v against its y: omega0 (the norm is then
    nearly constant over an oscillation of the linearised contact). It is the same for
    every lane, so that a lane's exponent does not depend on the lanes beside it;
    omega0 > 0 for every model, since ``ContactParameters`` asks g > 0."""
    return numbers.omega0_rad_s


def _lane_steps(steps_per_period, frequency_hz: np.ndarray, rate_per_s: float) -> np.ndarray:
    """Steps per period of each lane: "auto" or one integer as ``steady_states`` takes
    them, or one integer per lane."""
    if isinstance(steps_per_period, str) or np.ndim(steps_per_period) == 0:
        check_steps(steps_per_period)
        return lane_steps(steps_per_period, frequency_hz, rate_per_s)
    steps = np.asarray(steps_per_period)
    if steps.shape != frequency_hz.shape:
        raise ValueError(f"`steps_per_period` has shape {steps.shape}, expected one integer "
                         f"or one per lane {frequency_hz.shape}.")
    for count in np.unique(steps):
        check_int("steps_per_period", count, minimum=4, maximum=MAX_STEPS)
    return steps.astype(np.int64)


def _jsonable_steps(steps_per_period):
    if isinstance(steps_per_period, str) or np.ndim(steps_per_period) == 0:
        return steps_per_period if isinstance(steps_per_period, str) else int(steps_per_period)
    return "per lane (steps_used)"


def check_run(periods, discard_periods, blocks) -> tuple[int, int, int]:
    blocks = check_int("blocks", blocks, minimum=4)
    if blocks % 2:
        raise ValueError(f"`blocks` must be even (the error compares the two halves), got "
                         f"{blocks!r}.")
    periods = check_int("periods", periods, minimum=blocks, maximum=MAX_PERIODS)
    if periods % blocks:
        raise ValueError(f"`periods` must be a multiple of `blocks` ({blocks}), got "
                         f"{periods!r}.")
    discard = check_int("discard_periods", discard_periods, minimum=0, maximum=MAX_PERIODS)
    if periods + discard > MAX_PERIODS:
        raise ValueError(f"`periods` + `discard_periods` must be at most {MAX_PERIODS} (a "
                         f"bound on the work), got {periods} + {discard}.")
    return periods, discard, blocks
