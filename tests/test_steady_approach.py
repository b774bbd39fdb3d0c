"""The approach check of continuation (``Batch.follows``): decided after ``verify_first``
periods where the march follows the orbit's linearisation, after ``verify_periods``
otherwise; its verdicts are those of the one-stage check of ``verify_periods`` it
replaced (``SteadyOptions(verify_first=verify_periods)`` is that check)."""

import numpy as np
import pytest

from numerics import SteadyOptions, steady_states, sweep
from numerics.steady import shooting
from numerics.steady.shooting import Batch
from perturb import PAPER, PAPER_BAND_HZ, PAPER_PANEL_FRACTIONS, ContactModel

DEFAULT = SteadyOptions()
#: The check as it was: every lane marches verify_periods, one verdict.
ONE_STAGE = SteadyOptions(verify_first=DEFAULT.verify_periods)

#: Columns that must not move when only the cost of the check changes.
SAME = ("status", "period", "app_m", "ymin_m", "ymax_m", "y_start_m", "v_start_m_s",
        "steps_used", "method", "error_estimate")


def assert_same_points(staged, single):
    for a, b in zip(staged.runs, single.runs, strict=True):
        assert a.jumps() == b.jumps(), (a.pa_frac, a.direction)
        for name in SAME:
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        for name in ("maxima_m", "minima_m"):
            for x, y in zip(getattr(a, name), getattr(b, name), strict=True):
                np.testing.assert_array_equal(x, y)


def periods_run(result):
    return sum(int(run.periods_run.sum()) for run in result.runs)


def staged_against_one_stage(points, most):
    """The ten panels on ``points`` frequencies of the band, Python route: the same points
    with both checks, and at most ``most`` times the periods with the staged one."""
    grid = np.linspace(*PAPER_BAND_HZ, points)
    staged = sweep(grid, PAPER_PANEL_FRACTIONS, engine="python")
    single = sweep(grid, PAPER_PANEL_FRACTIONS, engine="python", options=ONE_STAGE)
    assert single.settings["steady_options"] == {"verify_first": DEFAULT.verify_periods}
    assert_same_points(staged, single)
    assert periods_run(staged) <= most * periods_run(single)


def test_a_lane_that_approaches_then_departs_is_not_accepted_early():
    # Regression for the staged check's hazard: on the 25 Hz grid the down sweep at
    # 0.05 Q continues the 334 nm orbit of 1400 Hz to 1375 Hz, where Newton finds it
    # stable, but the previous state lies beyond its basin: the march comes within 0.31
    # of its first distance after 4 periods (a "shrank by half" rule would accept it),
    # then leaves for the 80 nm orbit (the paper's jump).
    grid = np.linspace(*PAPER_BAND_HZ, 63)
    run = sweep(grid[grid >= 1375.0], [0.05], direction="down", engine="python").runs[0]
    seed, jumped = -2, -1
    assert run.frequency_hz[jumped] == 1375.0 and run.method[jumped] == "march+newton"
    assert run.app_m[jumped] < 0.3 * run.app_m[seed]
    model = ContactModel()
    batch = Batch(model, np.array([1375.0]), np.array([0.05 * PAPER.Q_n]), 128, DEFAULT)
    y, v = run.y_start_m[[seed]], run.v_start_m_s[[seed]]
    span = run.app_m[[seed]]
    monodromy = np.empty((1, 2, 2))
    ok, y_orbit, v_orbit, _, shot = batch.newton([0], y, v, 1, span,
                                                 DEFAULT.reach_continuation, monodromy)
    assert ok[0]  # Newton continued the big orbit, stable by its multipliers
    scale = batch.scale(span)
    before = batch.distance([0], y - y_orbit, v - v_orbit, scale)
    ym, vm = y.copy(), v.copy()
    batch.advance(ym, vm, DEFAULT.verify_first, np.full(1, -1))
    after = batch.distance([0], ym - y_orbit, vm - v_orbit, scale)
    assert after[0] < DEFAULT.verify_shrink * before[0]  # measured 0.31 of it
    # ... but it left the orbit's linearisation (by 0.36 of the first distance, 18 times
    # `verify_linear`), so the check marches on, and rejects it.
    ly, lv = shooting._propagate(monodromy, y - y_orbit, v - v_orbit, DEFAULT.verify_first)
    deviation = batch.distance([0], ym - y_orbit - ly, vm - v_orbit - lv, scale)
    assert deviation[0] > 10 * DEFAULT.verify_linear * before[0]
    assert not batch.follows(np.array([0]), y, v, y_orbit, v_orbit, 1, span, monodromy,
                             shot)[0]


def test_the_staged_check_gives_the_verdicts_of_one_stage():
    # The 25 Hz grid, all ten panels: large steps make large first distances, 15 lanes
    # rejected (4 of them jumps). Measured: every point the same; 19,162 periods run
    # against 30,118 with one stage (0.64; 2026-11-23, with the Newton try after a march).
    # The saving exists: at most 0.7 of the periods.
    staged_against_one_stage(63, 0.7)


def test_a_period_two_orbit_is_checked_in_stages_of_whole_orbits():
    # The period-2 bouncing orbit at 490 Hz, 0.5 Q (tests/test_steady.py; found at 512
    # steps), continued: the first stage is 4 periods, two orbits, and the prediction
    # applies the 2-period monodromy. At 490 Hz the check accepts it (at 512 steps), a
    # little further it rejects it at every step count (a march then finds the orbit
    # nearby: |mu| = 0.87, the distance oscillates). The verdicts are those of one stage.
    from numerics import attractor_census

    lanes = attractor_census(490.0, 0.5).lanes
    two = np.flatnonzero(lanes.period == 2)[0]
    f = np.array([490.0, 490.5, 492.0])

    def continued(options):
        return steady_states(f, 0.5 * PAPER.Q_n, y_init_m=lanes.y_start_m[two],
                             v_init_m_s=lanes.v_start_m_s[two], period_guess=2,
                             app_guess_m=lanes.app_m[two], options=options)

    staged = continued(DEFAULT)
    single = continued(ONE_STAGE)
    assert (staged.period == 2).all()
    assert staged.method.tolist() == ["newton", "march+newton", "march+newton"]
    for name in SAME:
        np.testing.assert_array_equal(getattr(staged, name), getattr(single, name))
    assert staged.periods_run.sum() <= single.periods_run.sum()


@pytest.mark.slow
def test_the_fig2_fig3_job_gives_the_verdicts_of_one_stage():
    # Measured: all 6,220 points the same, 76,939 periods run against 139,003 (0.55;
    # 2026-11-23, with the Newton try after a march).
    staged_against_one_stage(311, 0.6)
