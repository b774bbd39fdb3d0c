"""``shoot_jacobian``: the period map's exact derivatives, by the start state and by
the parameter (f_e through dt, or P_a), that continuation's Newton uses."""

import numpy as np
import pytest

from numerics import compiled_kernels, drive_table
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


@pytest.mark.parametrize("by_force", [False, True])
def test_its_state_and_monodromy_are_shoot_periods_to_the_last_bit(lanes, by_force):
    y, v, jacobian = _jacobian(lanes, by_force)
    y_ref, v_ref, monodromy = lanes["y"].copy(), lanes["v"].copy(), np.empty((3, 2, 2))
    lanes["kernels"].shoot_periods(y_ref, v_ref, 1 / (STEPS * lanes["f"]), lanes["p_a"],
                                   lanes["drive"], 1, monodromy)
    assert np.array_equal(y, y_ref) and np.array_equal(v, v_ref)
    assert np.array_equal(jacobian[:, :, :2], monodromy)


#: Measured (2026-11-23) at h = 1e-3 of dt (of P_a): the smooth lanes' differences
#: are 1.9e-5 and 4.8e-6 (6.9e-10 and 2.5e-9) off the column, a hundredth of those at
#: 1e-2; the bouncing lane's 1.5e-2 (7.6e-8): a corner of the map lies within h.
FINE_ERROR = {False: 4e-5, True: 5e-9}


@pytest.mark.parametrize("by_force", [False, True])
def test_its_parameter_column_is_the_limit_of_central_differences(lanes, by_force):
    # Route 2: central differences of the same RK4 period map in dt (or P_a). Their
    # truncation error falls as h^2 (a tenth of h, a hundredth of the error) onto the
    # column, on the lanes where the map is smooth.
    _, _, jacobian = _jacobian(lanes, by_force)
    dt, p_a = 1 / (STEPS * lanes["f"]), lanes["p_a"]
    base = p_a if by_force else dt
    errors = []
    for rel in (1e-2, 1e-3):
        h = rel * base
        ends = [(dt, p_a + s * h) if by_force else (dt + s * h, p_a) for s in (1, -1)]
        numeric = (_period_map(lanes, *ends[0]) - _period_map(lanes, *ends[1])) / (
            2 * h[:, None])
        column = jacobian[:, :, 2]
        errors.append(np.abs(numeric - column).max(axis=1) / np.abs(column).max(axis=1))
    coarse, fine = errors
    assert (fine[:2] < FINE_ERROR[by_force]).all(), errors
    assert (fine[:2] < 0.02 * coarse[:2]).all(), errors  # h^2, measured 0.0100
    assert fine[2] < 0.03, errors  # through loss of contact: the same column, to the corner
