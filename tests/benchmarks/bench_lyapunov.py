"""Largest Lyapunov exponent: its cost per lane and period against the plain march.

The lanes are the 35 initial states of the chaotic census at P_a = 1.5 Q, 1200 Hz
(tests/test_hard_cases.py: 29 chaotic, 6 on period-6 and period-7 orbits), taken
to where the census left them, at its 512 steps per period. In the same run:

- the plain march of the same lanes over the same periods (``advance_periods``,
  nothing recorded): the least a run of that length can cost;
- Benettin's method through the kernel that already existed, ``shoot_periods``
  (the 2x2 monodromy matrix of one period) called once per period from Python,
  the tangent vector multiplied by it there: what ``lyapunov_periods`` replaces.
"""

from __future__ import annotations

import numpy as np

from numerics import attractor_census, largest_lyapunov
from numerics.kernels.lanes import Lanes
from numerics.steady.lyapunov import DEFAULTS
from perturb import ContactModel, eq26_numbers

from ._timing import header, interleaved_medians, row

F_E, PA_FRAC = 1200.0, 1.5
GRID = {"y_over_y0": (-22.0, -21.0, -20.0, -4.0, 0.0, 1.0, 2.0),
        "v_over_omega0_y0": (-3.0, 0.0, 3.0, 10.3, 12.5)}


def _census_lanes():
    lanes = attractor_census(F_E, PA_FRAC, grid=GRID).lanes
    return lanes.y_start_m, lanes.v_start_m_s, int(lanes.steps_used.max())


def _plain_march(lanes: Lanes, y, v, periods: int) -> None:
    lanes.advance(y.copy(), v.copy(), periods, np.full(y.size, -1, dtype=np.int64))


def _benettin_by_monodromy(lanes: Lanes, y, v, periods: int) -> np.ndarray:
    """lambda T per lane from one ``shoot_periods`` call per period (the old route)."""
    y, v = y.copy(), v.copy()
    scale = eq26_numbers(lanes.model.parameters).omega0_rad_s
    w = np.tile([1.0, scale], (y.size, 1)) / np.sqrt(2)
    monodromy = np.empty((y.size, 2, 2))
    total = np.zeros(y.size)
    for _ in range(periods):
        lanes.kernels.shoot_periods(y, v, lanes.dt, lanes.p_a, lanes.drive, 1, monodromy)
        w = np.einsum("lij,lj->li", monodromy, w)
        norm = np.hypot(w[:, 0], w[:, 1] / scale)
        total += np.log(norm)
        w /= norm[:, None]
    return total / periods


def main() -> None:
    y, v, steps = _census_lanes()
    model = ContactModel()
    q = eq26_numbers(model.parameters).Q_n
    lanes = Lanes(model, np.full(y.size, F_E), np.full(y.size, PA_FRAC * q), steps)
    periods = DEFAULTS["periods"]
    run_periods = periods + DEFAULTS["discard_periods"]
    lyapunov = lambda: largest_lyapunov(F_E, PA_FRAC, y, v, steps_per_period=steps)  # noqa: E731
    lyapunov()  # compile / load
    spent, plain = interleaved_medians(lyapunov, lambda: _plain_march(lanes, y, v, run_periods))
    lane_periods = y.size * run_periods
    header(f"Largest Lyapunov exponent: {y.size} lanes at {PA_FRAC} Q, {F_E:g} Hz, "
           f"{steps} steps/period, {periods} + {DEFAULTS['discard_periods']} periods")
    row("time per lane-period: largest_lyapunov [us]", spent / lane_periods * 1e6,
        plain / lane_periods * 1e6, "us", higher_is_better=False)
    print("  (baseline: the plain march of the same lanes; the ratio is below 1: "
          "the price of the tangent)")
    short = 256  # the Python loop over periods is slow: timed on fewer periods
    new, old = interleaved_medians(
        lambda: largest_lyapunov(F_E, PA_FRAC, y, v, steps_per_period=steps, periods=short,
                                 discard_periods=0),
        lambda: _benettin_by_monodromy(lanes, y, v, short), repeats=5)
    row(f"time per lane-period, {short} periods [us]", new / (y.size * short) * 1e6,
        old / (y.size * short) * 1e6, "us", higher_is_better=False)
    print("  (baseline: shoot_periods once per period from Python, the monodromy route)")
    result = largest_lyapunov(F_E, PA_FRAC, y, v, steps_per_period=steps)
    verdicts = result.motion
    chaotic = np.array([verdict == "chaotic" for verdict in verdicts])
    rate, error = result.exponent_per_period, result.error_per_period
    print(f"  verdicts: {chaotic.sum()} chaotic, {verdicts.count('periodic or transient')} "
          f"periodic or transient, {verdicts.count('undecided')} undecided; chaotic lambda T "
          f"{rate[chaotic].min():.3f} to {rate[chaotic].max():.3f}, median error "
          f"{np.median(error[chaotic]):.3f}, least lambda / error "
          f"{(rate[chaotic] / error[chaotic]).min():.1f}")


if __name__ == "__main__":
    main()
