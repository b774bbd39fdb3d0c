"""``shoot_jacobian``: the period map's exact derivatives, by the start state and by
the parameter (f_e through dt, or P_a), that continuation's Newton uses."""

import numpy as np
import pytest

from numerics.continuation.period_map import ForceMap, PeriodMap
from numerics.kernels import compiled_kernels, drive_table
from perturb import ContactModel, eq26_numbers

STEPS = 256


@pytest.fixture(scope="module")
def lanes():
    """Three orbits' starts: two in contact throughout a period (small swings: the map is
    smooth there), one bouncing (a swing of 30 y0 from rest: loss of contact)."""
    model = ContactModel()
    numbers = eq26_numbers(model.parameters)
    y0, q = numbers.y0_m, model.parameters.Q_n
    return dict(kernels=compiled_kernels(model), y=np.array([1.2 * y0, 0.9 * y0, -30 * y0]),
                v=np.array([0.0, 1e-3, 0.0]), f=np.array([900.0, 1300.0, 600.0]),
                p_a=np.array([0.02 * q, 0.05 * q, 0.3 * q]), drive=drive_table(STEPS))


def _jacobian(lanes, by_force):
    y, v = lanes["y"].copy(), lanes["v"].copy()
    jacobian = np.empty((3, 2, 3))
    lanes["kernels"].shoot_jacobian(y, v, 1 / (STEPS * lanes["f"]), lanes["p_a"],
                                    lanes["drive"], 1, by_force, jacobian)
    return y, v, jacobian


def _period_map(lanes, dt, p_a):
    y, v = lanes["y"].copy(), lanes["v"].copy()
    lanes["kernels"].advance_periods(y, v, dt, p_a, lanes["drive"], 1, np.full(3, -1),
                                     np.full(3, np.inf))
    return np.stack([y, v], axis=1)


@pytest.mark.parametrize("shape", [(3, 2, 2), (2, 2, 3), (3, 3, 3)])
def test_a_jacobian_of_the_wrong_shape_is_an_error_not_a_write_past_its_end(lanes, shape):
    # The columns are copied in a loop (numba compiles a slice assignment for seconds),
    # which, unchecked, would write out of bounds where the assignment raised.
    y, v = lanes["y"].copy(), lanes["v"].copy()
    with pytest.raises(ValueError, match="shape"):
        lanes["kernels"].shoot_jacobian(y, v, 1 / (STEPS * lanes["f"]), lanes["p_a"],
                                        lanes["drive"], 1, False, np.empty(shape))


@pytest.mark.parametrize("by_force", [False, True])
def test_its_state_and_monodromy_are_shoot_periods_to_the_last_bit(lanes, by_force):
    y, v, jacobian = _jacobian(lanes, by_force)
    y_ref, v_ref, monodromy = lanes["y"].copy(), lanes["v"].copy(), np.empty((3, 2, 2))
    lanes["kernels"].shoot_periods(y_ref, v_ref, 1 / (STEPS * lanes["f"]), lanes["p_a"],
                                   lanes["drive"], 1, monodromy)
    assert np.array_equal(y, y_ref) and np.array_equal(v, v_ref)
    assert np.array_equal(jacobian[:, :, :2], monodromy)


@pytest.mark.parametrize("count", [1, 2, 3, 8, 9, 11, 17, 20])
def test_shoot_periods_gives_each_lane_its_own_numbers_in_any_batch(lanes, count):
    # Batches run padded to whole vectors (11 and 20 lanes run as 16 and 24, 3 as 8, 2 as
    # 8; 1 and 8 as they are): each lane's state and monodromy are those of it alone.
    k = lanes["kernels"]
    pick = np.arange(count) % 3
    f, p_a = lanes["f"][pick] * (1 + 0.01 * np.arange(count)), lanes["p_a"][pick]
    y, v, monodromy = lanes["y"][pick].copy(), lanes["v"][pick].copy(), np.empty((count, 2, 2))
    k.shoot_periods(y, v, 1 / (STEPS * f), p_a, lanes["drive"], 2, monodromy)
    for i in range(count):
        y1, v1, m1 = lanes["y"][pick[[i]]].copy(), lanes["v"][pick[[i]]].copy(), np.empty((1, 2, 2))
        k.shoot_periods(y1, v1, 1 / (STEPS * f[[i]]), p_a[[i]], lanes["drive"], 2, m1)
        assert (y1[0], v1[0]) == (y[i], v[i]) and np.array_equal(m1[0], monodromy[i])
    assert k.padded_width(count) == {1: 1, 2: 8, 3: 8, 8: 8, 9: 9, 11: 16, 17: 17,
                                     20: 24}[count]
    # Its state is the plain march's too: the approach check of a sweep marches on from
    # Newton's first shot as if it had marched those periods itself.
    y2, v2 = lanes["y"][pick].copy(), lanes["v"][pick].copy()
    k.advance_periods(y2, v2, 1 / (STEPS * f), p_a, lanes["drive"], 2, np.full(count, -1),
                      np.full(count, np.inf))
    assert np.array_equal(y, y2) and np.array_equal(v, v2)


#: Measured (2026-11-23) at h = 1e-3 of dt (of P_a): the smooth lanes' differences
#: are 1.9e-5 and 4.8e-6 (6.9e-10 and 2.5e-9) off the column, a hundredth of those at
#: 1e-2; the bouncing lane's 1.5e-2 (7.6e-8): a corner of the map lies within h. The
#: two extrapolated (Richardson, h^2) lie 1.2e-8 and 3.6e-9 (2.1e-11, 3.6e-12) off.
FINE_ERROR = {False: 4e-5, True: 5e-9}
EXTRAPOLATED_ERROR = {False: 3e-8, True: 6e-11}


@pytest.mark.parametrize("by_force", [False, True])
def test_its_parameter_column_is_the_limit_of_central_differences(lanes, by_force):
    # Route 2: central differences of the same RK4 period map in dt (or P_a). Their
    # truncation error falls as h^2 (a tenth of h, a hundredth of the error) onto the
    # column, on the lanes where the map is smooth.
    _, _, jacobian = _jacobian(lanes, by_force)
    dt, p_a = 1 / (STEPS * lanes["f"]), lanes["p_a"]
    base = p_a if by_force else dt
    column = jacobian[:, :, 2]
    numerics = []
    for rel in (1e-2, 1e-3):
        h = rel * base
        ends = [(dt, p_a + s * h) if by_force else (dt + s * h, p_a) for s in (1, -1)]
        numerics.append((_period_map(lanes, *ends[0]) - _period_map(lanes, *ends[1])) / (
            2 * h[:, None]))
    numerics.append((100.0 * numerics[1] - numerics[0]) / 99.0)  # Richardson: h^2 gone
    coarse, fine, extrapolated = (np.abs(n - column).max(axis=1) / np.abs(column).max(axis=1)
                                  for n in numerics)
    errors = (coarse, fine, extrapolated)
    assert (extrapolated[:2] < EXTRAPOLATED_ERROR[by_force]).all(), errors
    assert (fine[:2] < FINE_ERROR[by_force]).all(), errors
    assert (fine[:2] < 0.02 * coarse[:2]).all(), errors  # h^2, measured 0.0100
    assert fine[2] < 0.03, errors  # through loss of contact: the same column, to the corner


@pytest.mark.parametrize("force_is_parameter", [False, True])
def test_the_scaled_jacobian_of_r_is_the_limit_of_its_central_differences(force_is_parameter):
    # R(z) and dR/dz as continuation's corrector takes them, scaled, the parameter's column
    # by f through dt = 1 / (N f) (or by P_a): against central differences of R itself in
    # each unknown, at an orbit start in contact (the map smooth there). Measured
    # (2026-11-23): at h = 1e-4 in z the differences lie 7.2e-7 (f's column) and 3.2e-8
    # (P_a's) off, relative, a hundredth of those at 1e-3. The compiled walk's period_map
    # gives the same R and monodromy to the last bit and dR/dz to 1.3e-16.
    model = ContactModel()
    y0, q = eq26_numbers(model.parameters).y0_m, model.parameters.Q_n
    if force_is_parameter:
        shoot, z, bound = ForceMap(model, 1400.0, 512, 1), np.array([1.2, 0.0, 0.05]), 1e-7
    else:
        shoot = PeriodMap(model, 0.05 * q, 512, 1)
        z, bound = shoot.scaled(1.2 * y0, 0.0, 900.0), 3e-6
    r, jacobian, monodromy = shoot.residual(z)
    errors = []
    for h in (1e-3, 1e-4):
        steps = h * np.eye(3)
        numeric = np.stack([(shoot.residual(z + e)[0] - shoot.residual(z - e)[0]) / (2 * h)
                            for e in steps], axis=1)
        errors.append(np.abs(numeric - jacobian).max(axis=0) / np.abs(jacobian).max(axis=0))
    assert (errors[1] < bound).all(), errors
    assert (errors[1] < 0.02 * errors[0]).all(), errors  # h^2
    jac, mono = np.empty((2, 3)), np.empty((2, 2))
    compiled = shoot.walker.period_map(z, shoot.scale, shoot.steps, shoot.period, shoot.drive,
                                       shoot.force_is_parameter, shoot.other, jac, mono)
    assert np.array_equal(np.array(compiled), r) and np.array_equal(mono, monodromy)
    assert np.abs(jac - jacobian).max() <= 1e-15 * np.abs(jacobian).max()
