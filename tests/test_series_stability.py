"""The stability of the series' roots (issue 13, item 3): numerics.series_stability.

Two routes to the same multipliers: Newton from each series root's state, and the
continued branch of Eq. 2.6 (``continue_orbits``), which reaches the same orbits from
the orbit time marching finds at the band's end. A third check needs neither: for
Eq. 2.6 the trace of the Jacobian is -2c everywhere, so (Liouville) the multipliers'
product is exp(-2c T) on every orbit.
"""

from functools import partial as _partial

import numpy as np
import pytest

from numerics import continue_orbits, series_stability
from numerics.plots import plot_series_stability
from perturb import EQ_2_6, PAPER, ContactModel, eq26_numbers, frequency_response

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")

EQ26 = ContactModel(PAPER, EQ_2_6)
NUMBERS = eq26_numbers(PAPER)
#: Order 6 at 0.05 Q has three roots from 1395 to 1420 Hz (the continued branch of
#: Eq. 2.6 folds at 1394.0 and 1420.8 Hz); one root at 800 and 1300 Hz, and at 1000 Hz
#: one valid root and two invalid ones with no error estimate.
BENT = [1400.0, 1405.0, 1410.0, 1415.0, 1420.0]
OFF = [800.0, 1000.0, 1300.0]


@pytest.fixture(scope="module")
def peak_005():
    response = frequency_response(np.array(OFF + BENT), 0.05, 6)
    return response, series_stability(response)


def test_on_the_bent_peak_the_middle_root_is_unstable(peak_005):
    response, stability = peak_005
    assert response.roots_per_frequency().tolist() == [1, 3, 1, 3, 3, 3, 3, 3]
    flags = {j: dict(zip(b.frequency_hz, b.stable)) for j, b in enumerate(stability.branches)}
    for f in BENT:
        assert [flags[j][f] for j in range(3)] == [True, False, True], f
    for f in OFF:
        assert flags[0][f] is True, f
    # The middle root is a saddle: real multipliers, one outside the unit circle. Measured
    # 1.037 (1420 Hz, next to the fold) to 1.082 (1410 Hz); the inner one 0.73-0.76.
    middle = stability.branches[1].multipliers[1:]
    assert np.all(middle.imag == 0)
    assert np.abs(middle).max(axis=1).min() > 1.03
    assert np.abs(middle).min(axis=1).max() < 0.77


def test_the_multipliers_multiply_to_liouvilles_determinant(peak_005):
    # Eq. 2.6 damps linearly: det M = exp(-2c T) on every orbit, stable or not. RK4's
    # monodromy at N = 512 gives it to 0.014 (omega0 dt)^4 (measured: 3.7e-9 at 800 Hz,
    # 2.3e-10 at 1420 Hz), its fourth order.
    _, stability = peak_005
    for b in stability.branches:
        f = b.frequency_hz[b.known]
        product = np.prod(b.multipliers[b.known], axis=1)
        error = np.abs(product / np.exp(-2 * NUMBERS.c_per_s / f) - 1)
        assert np.max(error / (NUMBERS.omega0_rad_s / (512 * f)) ** 4) < 0.02


def _compared(pa_frac, fmin_hz, fmax_hz):
    """Each point of the continued branch beside the series' root at its f_e with the
    nearest App: (the root's flag, the point's, multiplier gap, App gap, the root's
    error estimate, valid), one row per point."""
    branch = continue_orbits(pa_frac, fmin_hz, fmax_hz, model=EQ26).branches[0]
    response = frequency_response(np.unique(branch.frequency_hz), pa_frac, 6)
    stability = series_stability(response)
    rows = []
    for f, app, stable, theirs in zip(branch.frequency_hz, branch.app_m, branch.stable,
                                      branch.multipliers):
        gap, j, k = min((abs(b.app_m[k] - app) / app, j, k)
                        for j, b in enumerate(response.branches)
                        for k in np.flatnonzero(b.frequency_hz == f))
        ours, series = stability.branches[j], response.branches[j]
        mu = ours.multipliers[k]
        mu_gap = min(np.abs(mu - theirs).max(), np.abs(mu[::-1] - theirs).max())
        rows.append((ours.stable[k], bool(stable), mu_gap, gap, series.error_estimate[k],
                     series.valid[k]))
    return rows


@pytest.mark.parametrize("pa_frac, fmin_hz, fmax_hz, min_known, min_unstable, worst_mu", [
    # Measured (points of the continued branch matched by a flagged root, of them
    # unstable, worst multiplier gap): 107 of 111, 32, 2.7e-11 at 0.05 Q (near the folds
    # M - I is nearly singular); 52 of 59, 27, 3.4e-13 at 0.15 Q; 62 of 83, 34, 3.3e-13
    # at 0.1 Q; 41 of 44, 19, 2.6e-13 at 0.3 Q; on the 1/2 superharmonic, all stable,
    # 92 of 92, 1.3e-13 at 0.15 Q and 44 of 98, 6.3e-13 at 0.3 Q (where the series has no
    # root of its many crossings; 49 before the distance allowed was capped at half the
    # amplitude: five invalid roots lost their flags). The gaps are round-off since the
    # continued points' multipliers are computed at the points themselves (before, at
    # the walk's last Newton iterate: up to 5.7e-9); the bounds allow about 4x.
    (0.05, 1300.0, 1600.0, 0.95, 30, 1e-10),
    (0.15, 1150.0, 1600.0, 0.85, 25, 1.5e-12),
    (0.1, 1100.0, 1600.0, 0.7, 30, 1.5e-12),
    (0.3, 1100.0, 1600.0, 0.9, 17, 1e-12),
    (0.15, 650.0, 850.0, 0.95, 0, 5e-13),
    (0.3, 650.0, 850.0, 0.44, 0, 2.5e-12),
])
def test_flags_and_multipliers_are_those_of_the_continued_branch(pa_frac, fmin_hz, fmax_hz,
                                                                 min_known, min_unstable,
                                                                 worst_mu):
    rows = _compared(pa_frac, fmin_hz, fmax_hz)
    # A root describes the point's orbit when their App agree within the series' reach
    # (4 x its estimate, + RK4's error); elsewhere the series has no root for this
    # crossing of f_e (next to a fold) and the nearest App is another orbit's.
    same = [r for r in rows if r[3] <= 4 * r[4] + 1e-7]
    known = [r for r in same if r[0] is not None]
    assert len(known) >= min_known * len(rows)
    assert sum(r[0] is False for r in known) >= min_unstable
    for ours, theirs, mu_gap, *_ in known:
        assert ours == theirs
        assert mu_gap < worst_mu
    # Wherever the series is valid its root has a flag (measured: every one).
    assert all(r[0] is not None for r in same if r[5])


def test_a_root_it_cannot_back_gets_no_flag(peak_005):
    # 0.05 Q, 1000 Hz: the two lesser roots are invalid (no root of orders 7 and 8
    # nearby); Newton from their states diverges.
    _, stability = peak_005
    for j in (1, 2):
        b = stability.branches[j]
        k = int(np.flatnonzero(b.frequency_hz == 1000.0)[0])
        assert b.stable[k] is None and "did not converge" in b.message[k]
        assert np.isnan(b.multipliers[k]).all() and np.isnan(b.y_start_m[k])
    # 0.1 Q, 1000 Hz: the middle root is past loss of contact (y0 + min u = -110 nm) with
    # no error estimate; Newton from it converges, 1.2 App/2 away, on the stable orbit
    # of the upper root (|mu| 0.845): not the root's orbit, so no flag.
    response = frequency_response(np.array([1000.0]), 0.1, 6)
    middle = response.branches[1]
    assert NUMBERS.y0_m + middle.u_min_m[0] < 0 and np.isnan(middle.error_estimate[0])
    ours = series_stability(response).branches[1]
    assert ours.stable[0] is None and "no error estimate" in ours.message[0]
    assert 1.0 < ours.orbit_distance[0] < 1.5
    # 0.3 Q, 745 Hz (the 1/2 superharmonic, six roots): the second root's error estimate
    # is 311 %, so its reach would take any orbit; the orbit Newton finds from it (2.47
    # App/2 away) lies beyond the cap of half the amplitude (and nearer another root's
    # state than its own): no flag.
    response = frequency_response(np.array([745.0]), 0.3, 6)
    assert response.branches[1].error_estimate[0] > 3.0
    ours = series_stability(response).branches[1]
    assert ours.orbit_distance[0] < 4 * response.branches[1].error_estimate[0]
    assert ours.stable[0] is None and "at most 0.5" in ours.message[0]


def test_the_reach_check_can_fail(peak_005):
    # Negative control: the middle root's orbit lies 1.06-1.35 times the series' error
    # estimate from its state (measured); a reach of 0.5 estimates refuses every flag.
    response, _ = peak_005
    strict = series_stability(response, reach=0.5).branches[1]
    assert all(flag is None for flag in strict.stable)
    assert all("(0.5 x its error estimate" in m for m in strict.message[1:])


def test_rk4_error_is_within_its_bound():
    # The reach adds RK4's own error, bounded by (omega0 dt)^4: measured against
    # N = 4096 at most 0.28 of it (0.15 Q, 742 Hz, the 1/2 superharmonic peak).
    f = np.array([250.0, 495.0, 742.0, 1400.0])
    response = frequency_response(f, 0.15, 6)
    coarse, fine = (series_stability(response, steps_per_period=n).branches[0]
                    for n in (512, 4096))
    half, omega = response.branches[0].app_m / 2, 2 * np.pi * f
    error = (np.abs(coarse.y_start_m - fine.y_start_m) / half
             + np.abs(coarse.v_start_m_s - fine.v_start_m_s) / (omega * half))
    assert np.max(error / (NUMBERS.omega0_rad_s / (512 * f)) ** 4) < 0.4


def test_the_figure_draws_both_routes_alike(peak_005, tmp_path):
    response, stability = peak_005
    continuation = continue_orbits(0.05, 1300.0, 1600.0, model=EQ26)
    path = tmp_path / "series_stability.png"
    figure = plot_series_stability(stability, continuation, path)
    assert path.stat().st_size > 10_000
    styles = {(line.get_color(), line.get_linestyle()) for line in figure.axes[0].lines
              if line.get_xydata().size}
    # The series' middle branch dashed, its other branches solid; the continued branch
    # (grey) both; the invalid roots at 1000 Hz dotted.
    assert {("C1", "--"), ("C0", "-"), ("C2", "-"), ("0.6", "-"), ("0.6", "--"),
            ("0.4", ":")} <= styles


def test_bad_input_is_named(peak_005):
    response, _ = peak_005
    with pytest.raises(ValueError, match="`response`"):
        series_stability("1400 Hz")
    with pytest.raises(ValueError, match="steps_per_period"):
        series_stability(response, steps_per_period=2)
    with pytest.raises(ValueError, match="reach"):
        series_stability(response, reach=-1.0)


def test_a_root_whose_orbit_was_not_found_gets_no_flag():
    # Regression (review): the distance allowed grew with the series' error estimate
    # without bound, so at 0.3 Q, 690 Hz an invalid root (App 205.8 nm, estimate 1.61)
    # was flagged stable on a 98 nm orbit 1.35 App/2 away. It is at most half the
    # amplitude now: unknown, with the reason.
    stability = series_stability(frequency_response(np.array([690.0]), 0.3, 6))
    branch = stability.branches[0]
    assert branch.stable.tolist() == [None]
    assert "1.35 App/2" in branch.message[0] and "at most 0.5" in branch.message[0]


def test_an_orbit_nearer_another_roots_state_gives_no_flag():
    # 0.2 Q, 762.5 Hz (past the 1/2 superharmonic peak): Newton from root 0 (App 89.3 nm,
    # estimate 0.30) converges 0.36 App/2 away, within its reach and the cap, but on the
    # orbit of root 2 (68.3 nm), whose state lies nearer: root 0 gets no flag, root 2
    # keeps its own (measured). Without the check both would say "stable".
    stability = series_stability(frequency_response(np.array([762.5]), 0.2, 6))
    first, third = stability.branches[0], stability.branches[2]
    assert first.stable.tolist() == [None] and 0.3 < first.orbit_distance[0] < 0.5
    assert "nearer the state of another root" in first.message[0]
    assert third.stable.tolist() == [True]
