"""The analytic frequency response against the RK4 steady state of Eq. 2.6.

Two independent routes: the compiled perturbation series (roots of the
frequency equation, App of the reconstructed u(t)) and a fixed-step RK4 of the
Eq. 2.6 model (``numerics.simulate``), run to a steady state from rest. And
the compiled route against the numpy route it replaced (issue 12), kept in
``tests/_response_reference.py``.
"""

import functools
import subprocess
import sys
import warnings
from functools import partial as _partial

import numpy as np
import pytest

from numerics import simulate
from perturb import (
    EQ_2_6,
    PAPER_BAND_HZ,
    PAPER_F_N0_HZ,
    ContactModel,
    compile_series,
    eq26_numbers,
    frequency_response,
)
from perturb.response import codegen
from perturb.response.codegen import series_kernels

from ._response_reference import reference_response

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")
compile_series = _partial(compile_series, truncation="paper")

#: The compiled route, held to the numpy route (``reference_response``) below.
compiled_response = functools.partial(frequency_response, engine="compiled")

VALUES = eq26_numbers()
PA_FRAC = 0.05
# Away from the peaks; on the primary peak (1440-1480 Hz: one response; 1420 Hz:
# on the bent part, three); on the 1/2 superharmonic peak near f_n0 / 2.
AWAY = [300.0, 450.0, 600.0, 1000.0, 1200.0, 1700.0]
PRIMARY = [1420.0, 1440.0, 1460.0, 1480.0]


@pytest.fixture(scope="module")
def superharmonic_peak_hz():
    """Where the analytic App has its local maximum near f_n0 / 2."""
    f = np.linspace(0.45 * PAPER_F_N0_HZ, 0.55 * PAPER_F_N0_HZ, 401)
    (branch,) = frequency_response(f, PA_FRAC, 6).branches
    return float(f[np.argmax(branch.app_m)])


@pytest.fixture(scope="module")
def rk4(superharmonic_peak_hz):
    f = np.array(AWAY + PRIMARY + [superharmonic_peak_hz])
    res = simulate(
        f,
        PA_FRAC * VALUES.Q_n,
        periods=800,
        steps_per_period=256,
        model=ContactModel(effects=EQ_2_6),
        record=("final", "minmax"),
    )
    assert not np.any(res.failed)
    return dict(zip(f.tolist(), res.app_m.tolist()))


def closest_branch_app(response, f_hz, target):
    candidates = []
    for branch in response.branches:
        hit = np.flatnonzero(branch.frequency_hz == f_hz)
        if hit.size:
            candidates.append((branch.app_m[hit[0]], bool(branch.valid[hit[0]])))
    return min(candidates, key=lambda c: abs(c[0] - target))


def check(rk4, frequencies, order=6):
    response = frequency_response(np.array(frequencies), PA_FRAC, order)
    for f in frequencies:
        app, valid = closest_branch_app(response, f, rk4[f])
        assert valid, f
        assert abs(app / rk4[f] - 1) < 0.01, f"{f} Hz: series {app:.5e}, RK4 {rk4[f]:.5e}"


def test_away_from_peaks(rk4):
    check(rk4, AWAY)


def test_on_primary_peak(rk4):
    check(rk4, PRIMARY)


def test_on_half_superharmonic_peak(rk4, superharmonic_peak_hz):
    assert abs(superharmonic_peak_hz / (PAPER_F_N0_HZ / 2) - 1) < 0.03
    check(rk4, [superharmonic_peak_hz])


def test_error_falls_with_order_on_primary_peak(rk4):
    errors = []
    for order in (2, 4, 6):
        response = frequency_response(np.array([1440.0]), PA_FRAC, order)
        app, _ = closest_branch_app(response, 1440.0, rk4[1440.0])
        errors.append(abs(app / rk4[1440.0] - 1))
    assert errors[0] > errors[1] > errors[2], errors


def test_bent_primary_peak_has_three_responses():
    response = frequency_response(np.array([1300.0, 1420.0, 1600.0]), PA_FRAC, 6)
    assert response.roots_per_frequency().tolist() == [1, 3, 1]


def has_local_peak(order, m, pa_frac=0.5):
    """Whether branch 0 has a local maximum of App within 0.9..1.06 f_n0 / m."""
    f = np.linspace(0.9 * PAPER_F_N0_HZ / m, 1.06 * PAPER_F_N0_HZ / m, 65)
    app = frequency_response(f, pa_frac, order).branches[0].app_m
    inner = int(np.argmax(app))
    return 0 < inner < f.size - 1


@pytest.mark.parametrize("m", [2, 3, 4, 5])
def test_superharmonic_peaks_appear_at_f_n0_over_m(m):
    # Order N carries harmonics up to N + 1, so its peaks reach f_n0 / (N + 1).
    assert has_local_peak(4, m)
    if m > 3:
        assert not has_local_peak(2, m)


def test_contact_loss_is_flagged():
    # Near the peak at 0.30 Q the slider leaves the slideway (Fig. 3): y0 + min u < 0.
    response = frequency_response(np.linspace(1100.0, 1500.0, 81), 0.30, 6)
    for branch in response.branches:
        lost = VALUES.y0_m + branch.u_min_m <= 0
        assert not np.any(branch.valid & lost)
    assert any(np.any(VALUES.y0_m + b.u_min_m <= 0) for b in response.branches)


def test_json_keeps_the_landed_keys():
    data = frequency_response(np.array([500.0, 1420.0]), PA_FRAC, 4).as_dict()
    assert {"order", "pa_frac", "branches"} <= set(data)
    assert {"kind", "model", "settings", "elapsed_s"} <= set(data)
    keys = {"frequency_hz", "app_m", "a0_m", "omega_rad_s", "valid"}
    assert all(keys <= set(branch) for branch in data["branches"])
    assert data["model"]["effects"] == {"contact_loss": False, "spring": "taylor",
                                        "taylor_degree": 2, "damping": "linear",
                                        "gravity": True}


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"frequency_hz": [100.0], "pa_frac": -0.1}, "`pa_frac`"),
        ({"frequency_hz": [100.0], "pa_frac": [0.1, 0.2]}, "`pa_frac`"),
        ({"frequency_hz": [100.0], "pa_frac": "0.1"}, "`pa_frac`"),
        ({"frequency_hz": [200.0, 100.0], "pa_frac": 0.1}, "`frequency_hz`"),
        ({"frequency_hz": [], "pa_frac": 0.1}, "`frequency_hz`"),
        ({"frequency_hz": [[100.0, 200.0]], "pa_frac": 0.1}, "`frequency_hz`"),
        ({"frequency_hz": [0.0, 100.0], "pa_frac": 0.1}, "`frequency_hz`"),
        ({"frequency_hz": ["a"], "pa_frac": 0.1}, "`frequency_hz`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "order": -2}, "`order`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "order": 2.5}, "`order`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "order": "6"}, "`order`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "omega_range": (1.2, 0.6)}, "`omega_range`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "omega_range": (0.6,)}, "`omega_range`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "omega_range": 0.6}, "`omega_range`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "omega_range": (0.0, 1.2)}, "`omega_range`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "grid_points": 1}, "`grid_points`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "samples": 2}, "`samples`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "tolerance": 0.0}, "`tolerance`"),
        ({"frequency_hz": [100.0], "pa_frac": 0.1, "parameters": {"M": 1.0}}, "`parameters`"),
    ],
)
def test_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        frequency_response(**kwargs)


def test_valid_points_are_accurate_where_the_series_converges_slowly():
    # Regression: at 0.15 Q near the 1/2 superharmonic peak the order-6 series is
    # several % off RK4 although each parity of orders still shrinks; the size of
    # the last two orders (> 1 % of App) must mark those points invalid.
    f = np.array([700.0, 715.0, 725.0, 735.0, 740.0, 750.0, 760.0, 775.0])
    res = simulate(
        f,
        0.15 * VALUES.Q_n,
        periods=800,
        steps_per_period=256,
        model=ContactModel(effects=EQ_2_6),
        record=("final", "minmax"),
    )
    target = dict(zip(f.tolist(), res.app_m.tolist()))
    response = frequency_response(f, 0.15, 6)
    flags = []
    for fi in f:
        app, valid = closest_branch_app(response, fi, target[fi])
        flags.append(valid)
        if valid:
            assert abs(app / target[fi] - 1) < 0.01, fi
    assert 2 <= sum(flags) < len(f)


def test_close_root_pair_near_a_fold_is_found():
    # Regression: at 0.05 Q, 1394-1396 Hz the upper and middle responses of the
    # bent primary peak are closer in omega than the default grid's spacing; with
    # no sign change between grid points, only one root of three was found (the
    # upper branch, 327.2 nm, matches RK4's 327.02 nm). A brute grid of 2,000
    # points sees all three.
    f = np.linspace(1394.0, 1396.0, 9)
    found = frequency_response(f, PA_FRAC, 6)
    brute = frequency_response(f, PA_FRAC, 6, grid_points=2000)
    assert brute.roots_per_frequency().tolist() == [3] * f.size
    assert found.roots_per_frequency().tolist() == [3] * f.size
    for ours, reference in zip(found.branches, brute.branches):
        np.testing.assert_allclose(ours.omega_rad_s, reference.omega_rad_s, rtol=1e-10)
        np.testing.assert_allclose(ours.app_m, reference.app_m, rtol=1e-9)


def series_states(response):
    """(f_e, y, v) at t = 0 on every root of ``response``: RK4 starting states.

    The compiled waveform has u0's phase 0; t = 0 (drive G cos(Omega t), Eq. 2.6)
    is the phase theta_1 of the fundamental's transfer.
    """
    formulas, step = compile_series(response.order), 1e-6
    states = []
    for b in response.branches:
        Omega = 2 * np.pi * b.frequency_hz
        theta_1 = -np.angle(b.omega_rad_s**2 - Omega**2 + 2j * VALUES.c_per_s * Omega)
        for f, t1, a0, w, W in zip(b.frequency_hz, theta_1, b.a0_m, b.omega_rad_s, Omega):
            u = formulas.waveform(np.array([t1, t1 + step]), a0, w, W, VALUES.c_per_s,
                                  VALUES.h_per_m_s2)
            states.append((f, VALUES.y0_m + u[0], W * (u[1] - u[0]) / step))
    return states


def rk4_attractors(pa_frac, frequencies):
    """App of the RK4 attractors of Eq. 2.6 from rest and from every order-6 root."""
    starts = [(f, VALUES.y0_m, 0.0) for f in frequencies]
    starts += series_states(frequency_response(np.array(frequencies), pa_frac, 6))
    f, y, v = map(np.array, zip(*starts))
    run = simulate(f, pa_frac * VALUES.Q_n, periods=600, steps_per_period=256, y_init_m=y,
                   v_init_m_s=v, model=ContactModel(effects=EQ_2_6), record=("final", "minmax"))
    assert not np.any(run.failed)
    return f, run.app_m


# Regression: the old flag (u_N and u_(N-1) below 1 % of App) ignored the
# left-out b_(N+1) that the resonance amplifies (zero at even N): order 3 at
# 0.05 Q was flagged valid 3.3 % off RK4 at 1420 Hz, 1-1.7 % off at 1445-1470 Hz;
# 2.1 % at 1455 Hz, 0.10 Q; 2.5 % at 1330 Hz, 0.15 Q; order 5 1.1 % at 1395 Hz,
# 0.10 Q; order 0 everything (28 % off at 1420 Hz). Order 2 was too strict.
HONESTY_CASES = {
    0.05: [300.0, 740.0, 1000.0, 1395.0, 1420.0, 1445.0, 1450.0, 1455.0, 1460.0, 1470.0, 1700.0],
    0.10: [740.0, 1395.0, 1455.0],
    0.15: [745.0, 1330.0],
}


# How many valid points (orders 0, 2, 3, 5, even branches) the test below compares
# with RK4 at least; measured: 23 at 0.05 Q (2, 5, 5, 11 by order), 3 at 0.10 Q
# (0, 0, 1, 2), 1 at 0.15 Q (0, 0, 0, 1). Without a floor the test would pass
# with no valid point at all.
VALID_FLOOR = {0.05: 22, 0.10: 3, 0.15: 1}


@pytest.mark.parametrize("pa_frac", sorted(HONESTY_CASES))
def test_valid_points_are_within_one_percent_of_rk4(pa_frac):
    frequencies = HONESTY_CASES[pa_frac]
    f, app = rk4_attractors(pa_frac, frequencies)
    compared = 0
    for order in (0, 2, 3, 5):
        response = frequency_response(np.array(frequencies), pa_frac, order)
        # Roots alternate stable, unstable along a bent peak (branch j by decreasing
        # omega): the odd branches have no attractor to compare with.
        for branch in response.branches[::2]:
            for fi, a, valid in zip(branch.frequency_hz, branch.app_m, branch.valid):
                error = np.min(np.abs(a / app[f == fi] - 1))
                assert not valid or error < 0.01, f"order {order}, {fi} Hz: {error:.2%} off"
                compared += bool(valid)
    assert compared >= VALID_FLOOR[pa_frac], compared
    if pa_frac == 0.05:
        # Order 2 is accurate (< 1 %) at five of these and must say so (old: one).
        response = frequency_response(np.array(frequencies), pa_frac, 2)
        assert response.branches[0].valid.sum() >= 5


def test_order_2_is_valid_somewhere_at_015q():
    # Regression: the old rule flagged no order-2 point valid at 0.15 Q over the
    # paper's band, though 256 of them are within 1 % of RK4.
    response = frequency_response(np.arange(250.0, 1801.0, 5.0), 0.15, 2)
    assert sum(int(b.valid.sum()) for b in response.branches) > 100


@pytest.mark.parametrize("order", [0, 3, 6])
def test_no_force_is_rest(order):
    # Regression: pa_frac = 0 divided by A0 = 0 in b_n (a RuntimeWarning) and gave
    # no branch at all; without force the one response is rest, exactly.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        response = frequency_response(np.array([500.0, 1485.0]), 0.0, order)
    (branch,) = response.branches
    assert branch.app_m.tolist() == [0.0, 0.0] and branch.valid.all()
    assert branch.omega_rad_s.tolist() == [VALUES.omega0_rad_s] * 2


# --- Issue 12: the compiled route against today's ---------------------------------


def assert_same_response(new, old):
    """Same branches at every frequency, same roots, validity and App (where valid)."""
    np.testing.assert_array_equal(new.roots_per_frequency(), old.roots_per_frequency())
    assert len(new.branches) == len(old.branches)
    for a, b in zip(new.branches, old.branches):
        np.testing.assert_array_equal(a.frequency_hz, b.frequency_hz)
        # Both routes stop the root search at |hi - lo| <= 1e-13 omega; measured at
        # most 1.0e-13 apart on the grids below (the bar: 1e-10).
        np.testing.assert_allclose(a.omega_rad_s, b.omega_rad_s, rtol=1e-12, atol=0)
        np.testing.assert_array_equal(a.valid, b.valid)
        np.testing.assert_array_equal(np.isnan(a.error_estimate), np.isnan(b.error_estimate))
        # Valid App: measured at most 2.5e-12 apart (the residual's operations come in
        # another order). Far from valid, where the series diverges, App moves by up
        # to 4e-9 between roots 1e-13 apart, so it is not held there.
        np.testing.assert_allclose(a.app_m[b.valid], b.app_m[b.valid], rtol=1e-11, atol=0)


#: The paper comparison's frequencies (``numerics.compare``: the band in 5 Hz steps).
PAPER_GRID_HZ = np.arange(PAPER_BAND_HZ[0], PAPER_BAND_HZ[1] + 1.0, 5.0)


@pytest.mark.parametrize("order", [2, 4, 6])
@pytest.mark.parametrize("pa_frac", [0.05, 0.2, 0.5, 1.0])
def test_the_compiled_response_is_todays(order, pa_frac):
    # Issue 12: the response moved to compiled code; today's numpy route is the
    # reference, on the grid of orders and amplitudes.
    assert_same_response(compiled_response(PAPER_GRID_HZ, pa_frac, order),
                         reference_response(PAPER_GRID_HZ, pa_frac, order))


@pytest.mark.parametrize("order", [1, 3])
def test_the_compiled_response_is_todays_at_odd_orders(order):
    # At odd N, order N+1 has a frequency equation of its own (b_(N+1) != 0), and
    # its roots are searched from order N's (the other branch of truncation_error).
    assert_same_response(compiled_response(PAPER_GRID_HZ, 0.3, order),
                         reference_response(PAPER_GRID_HZ, 0.3, order))


def test_the_compiled_response_is_todays_at_10000_frequencies():
    # The benchmark's case; its fine grid passes the close root pairs of the fold
    # at 1394-1396 Hz, which only the dips of |residual| find.
    f = np.linspace(*PAPER_BAND_HZ, 10_000)
    new, old = compiled_response(f, PA_FRAC, 6), reference_response(f, PA_FRAC, 6)
    assert_same_response(new, old)
    assert np.sum(new.roots_per_frequency() == 3) > 100


@pytest.mark.slow
@pytest.mark.parametrize("order", [2, 4, 6])
@pytest.mark.parametrize("pa_frac", [0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0])
def test_the_compiled_response_is_todays_at_10000_frequencies_everywhere(order, pa_frac):
    f = np.linspace(*PAPER_BAND_HZ, 10_000)
    assert_same_response(compiled_response(f, pa_frac, order),
                         reference_response(f, pa_frac, order))


def test_the_comparison_can_fail():
    # Negative control: a tighter tolerance changes validity flags, and order 8's
    # roots lie some 1e-5 from order 6's; the comparison must see both.
    f = np.linspace(1440.0, 1480.0, 41)  # one root each, at both orders
    old = reference_response(f, PA_FRAC, 6)
    with pytest.raises(AssertionError, match="Arrays are not equal"):
        assert_same_response(compiled_response(f, PA_FRAC, 6, tolerance=1e-4), old)
    with pytest.raises(AssertionError, match="Not equal to tolerance"):
        assert_same_response(compiled_response(f, PA_FRAC, 8), old)


@pytest.mark.parametrize("order", [0, 3, 6])
def test_the_generated_code_is_the_lambdified_series(order):
    # Two routes from one chain (complex_chain): the generated straight-line code and
    # sympy's lambdify, at random points of the band at 0.2 Q.
    rng = np.random.default_rng(12)
    omega = rng.uniform(0.6, 1.2, 2000) * VALUES.omega0_rad_s
    Omega = 2 * np.pi * rng.uniform(*PAPER_BAND_HZ, 2000)
    G, c, h = 0.2 * VALUES.Q_n * VALUES.G_per_P_a, VALUES.c_per_s, VALUES.h_per_m_s2
    kernels = series_kernels(order)
    residual = np.empty(omega.size)
    kernels.residual_lanes(G, omega, Omega, c, np.array([h]), VALUES.omega0_rad_s, residual)
    a0 = G / np.hypot(omega**2 - Omega**2, 2 * c * Omega)
    shift = compile_series(order).frequency_shift(a0, omega, Omega, c, h)
    # Measured: at most 2.6e-13 relative (orders 0-8).
    np.testing.assert_allclose(residual, omega**2 - VALUES.omega0_rad_s**2 - shift, rtol=2e-12)
    shape = (3, kernels.TOP_HARMONIC + 1, omega.size)
    real, imag = np.empty(shape), np.empty(shape)
    kernels.harmonics_lanes(a0, omega, Omega, c, np.array([h]), real, imag)
    for m in range(3):  # orders N, N+1, N+2
        series = compile_series(order + m)
        expected = series.harmonics(series.amplitudes(a0, omega, Omega, c, h))
        got = (real[m] + 1j * imag[m]).T
        # Measured: at most 1e-13 of the largest harmonic; higher harmonics are zero.
        scale = np.abs(expected).max()
        np.testing.assert_allclose(got[:, :expected.shape[1]], expected, rtol=0, atol=1e-12 * scale)
        assert not got[:, expected.shape[1]:].any()


def test_a_response_with_its_kernels_cached_needs_no_sympy():
    # Issue 12: the compiled response reads its kernels (and the numbers of Eq. 2.6)
    # from the cache; a new process does not derive them again.
    compiled_response(np.array([800.0, 1420.0]), PA_FRAC, 6)  # builds the kernels
    code = ("import sys, numpy as np; from perturb import frequency_response;"
            "frequency_response(np.array([800.0, 1420.0]), 0.05, 6);"
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "False"


@pytest.fixture
def empty_series_cache(tmp_path, monkeypatch):
    """An empty cache folder, and no series kernels loaded by this process."""
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    monkeypatch.setattr(codegen, "_LOADED", {})
    return tmp_path / "kernels"


@pytest.mark.slow
def test_a_damaged_series_cache_is_rebuilt(empty_series_cache):
    # Compiles order 0 three times (some 10 s each on the shared machine).
    cache = empty_series_cache
    reference = series_kernels(0)
    (source,) = cache.glob("series_*.py")
    source.write_text(source.read_text()[:500])  # cut short
    codegen._LOADED.clear()
    assert series_kernels(0) is not reference
    numba_files = list(cache.glob("__pycache__/series_*.nb*"))
    assert numba_files
    for path in numba_files:
        path.write_bytes(b"garbage")
    codegen._LOADED.clear()
    rebuilt = series_kernels(0)
    assert all(p.read_bytes() != b"garbage" for p in cache.glob("__pycache__/series_*.nb*"))
    f = np.array([800.0, 1420.0])
    assert_same_response(compiled_response(f, PA_FRAC, 0), reference_response(f, PA_FRAC, 0))
    assert callable(rebuilt.find_roots)


def test_auto_answers_from_numpy_until_the_kernels_are_built(empty_series_cache):
    # Building an order's kernels takes 10-20 s: "auto" does not pay it for a call.
    f = np.array([800.0, 1420.0])
    assert_same_response(frequency_response(f, PA_FRAC, 3), reference_response(f, PA_FRAC, 3))
    assert not list(empty_series_cache.glob("series_*.py"))
