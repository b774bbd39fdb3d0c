"""The batched RK4: its tableau, its order, and its behaviour through contact loss."""

import numpy as np
import pytest

from numerics import simulate
from numerics.kernels import compiled_kernels
from perturb import LINEAR, ContactModel, eq26_numbers


def convergence_slope(steps, errors):
    """Slope of log(error) against log(step size) = -log(steps per period)."""
    return np.polyfit(-np.log(np.asarray(steps, float)), np.log(errors), 1)[0]


def test_rk4_tableau_is_consistent():
    kernels = compiled_kernels(ContactModel())
    assert sum(kernels.RK4_B) == pytest.approx(1.0, abs=1e-15)
    for c, row in zip(kernels.RK4_C, kernels.RK4_A):
        assert sum(row) == pytest.approx(c, abs=1e-15)


def test_unrolled_step_is_the_tableau(rng):
    # One step of rk4_step against the generic Butcher form on the real RHS.
    model = ContactModel()
    k = compiled_kernels(model)
    y, v, dt = eq26_numbers(model.parameters).y0_m * 1.3, 1e-3, 2e-5
    forces = (0.1, 0.2, 0.2, 0.3)
    stages = []
    for row, force in zip(k.RK4_A, forces):
        ys = y + dt * sum(a * s[0] for a, s in zip(row, stages))
        vs = v + dt * sum(a * s[1] for a, s in zip(row, stages))
        stages.append((vs, k.acceleration_batch(np.array([ys]), np.array([vs]),
                                                np.array([force]))[0]))
    expected = (y + dt * sum(b * s[0] for b, s in zip(k.RK4_B, stages)),
                v + dt * sum(b * s[1] for b, s in zip(k.RK4_B, stages)))
    got = k.rk4_step(y, v, dt, forces[0], forces[1], forces[3])
    assert got == pytest.approx(expected, rel=1e-14)


def damped_forced_exact(t, omega0, c, G, Omega, u0, v0):
    """Exact u(t) of u'' + 2c u' + omega0^2 u = G cos(Omega t)."""
    z = G / (omega0**2 - Omega**2 + 2j * c * Omega)  # steady complex amplitude
    up, vp = z.real, (1j * Omega * z).real  # particular solution at t = 0
    wd = np.sqrt(omega0**2 - c**2)
    a, b = u0 - up, (v0 - vp + c * (u0 - up)) / wd
    transient = np.exp(-c * t) * (a * np.cos(wd * t) + b * np.sin(wd * t))
    return (z * np.exp(1j * Omega * t)).real + transient


def test_rk4_is_fourth_order_on_the_linear_oscillator(weight):
    model = ContactModel(effects=LINEAR)
    k = eq26_numbers()
    f_e, periods, p_a = 700.0, 6, 0.3 * weight
    y0 = eq26_numbers(model.parameters).y0_m
    u0, v0 = 3e-8, 0.0
    exact = damped_forced_exact(periods / f_e, k.omega0_rad_s, k.c_per_s,
                                k.G_per_P_a * p_a, 2 * np.pi * f_e, u0, v0)
    steps = [32, 64, 128, 256, 512]
    errors = []
    for n in steps:
        run = simulate(f_e, p_a, periods=periods, steps_per_period=n, model=model,
                       y_init_m=y0 + u0, v_init_m_s=v0, record=("final",))
        errors.append(abs(run.y_final_m[0] - y0 - exact))
    slope = convergence_slope(steps, errors)
    assert 3.7 <= slope <= 4.3, f"measured order {slope:.3f}; errors {errors}"


def test_self_convergence_through_loss_of_contact(weight):
    # P_a = 0.5Q at 490 Hz, released from +-3 y0 and similar: the slider bounces
    # (ymin < 0), where the law is not smooth (y = 0). The jump in d(acceleration)/dt
    # there makes RK4 second order; the error of one crossing depends erratically on
    # where in its step the crossing falls, so the error is the largest over four
    # lanes and all 20 period ends, which follows the envelope.
    steps = [100, 200, 400, 800]
    periods = 20
    y_init = np.array([3.0, -3.0, 2.5, -2.0]) * eq26_numbers().y0_m
    ends = []
    for n in steps + [6400]:
        run = simulate(490.0, 0.5 * weight, periods=periods, steps_per_period=n, y_init_m=y_init,
                       record=("history", "minmax"), record_periods=periods)
        ends.append(run.history_y_m[:, n - 1 :: n])
    assert (run.ymin_m < 0).all(), "every reference lane must lose contact"
    errors = [np.abs(e - ends[-1]).max() for e in ends[:-1]]
    slope = convergence_slope(steps, errors)
    assert slope >= 2.0, f"measured order {slope:.3f}; errors {errors}"
    # Over the whole range 100 -> 800 the error falls at least like step^2 (8^2 = 64);
    # single doublings vary with where the crossings fall (measured 7.5, 3.0, 14.8).
    assert errors[0] / errors[-1] >= 64, f"error ratio {errors[0] / errors[-1]:.3g}; {errors}"


@pytest.mark.parametrize("count", [1, 3, 8, 20])
def test_recording_gives_each_lane_the_numbers_of_its_steps(count):
    # record_periods runs the steps of all lanes (padded to whole vectors) in blocks of
    # RECORD_BLOCK, then reads each lane's steps: 600 steps are three blocks, the last
    # short. Every lane's numbers are those of it alone, its final state that of the plain
    # march, its extrema the sign changes of v in its history, min and max over them.
    from numerics.kernels import drive_table

    model = ContactModel()
    k, y0, q = compiled_kernels(model), eq26_numbers().y0_m, model.parameters.Q_n
    steps, periods = 600, 2
    assert steps > 2 * k.RECORD_BLOCK
    drive = drive_table(steps)
    f = np.linspace(300.0, 1500.0, count)
    p_a = np.linspace(0.05, 0.5, count) * q
    y, v = np.linspace(-20.0, 2.0, count) * y0, np.zeros(count)

    def record(lanes):
        n = lanes.size
        out = dict(y=y[lanes].copy(), v=v[lanes].copy(), ymin=np.empty(n), ymax=np.empty(n),
                   value=np.empty((n, 64)), phase=np.empty((n, 64)),
                   kind=np.empty((n, 64), dtype=np.int8), count=np.zeros(n, dtype=np.int64),
                   hy=np.empty((n, periods * steps)), hv=np.empty((n, periods * steps)))
        k.record_periods(out["y"], out["v"], 1 / (steps * f[lanes]), p_a[lanes], drive,
                         periods, np.full(n, -1), 0, out["ymin"], out["ymax"], out["value"],
                         out["phase"], out["kind"], out["count"], out["hy"], out["hv"],
                         np.full(n, np.inf))
        return out

    every = record(np.arange(count))
    marched_y, marched_v = y.copy(), v.copy()
    k.advance_periods(marched_y, marched_v, 1 / (steps * f), p_a, drive, periods,
                      np.full(count, -1), np.full(count, np.inf))
    assert np.array_equal(every["y"], marched_y) and np.array_equal(every["v"], marched_v)
    for i in range(count):
        alone = record(np.array([i]))
        n = every["count"][i]
        for name, value in alone.items():
            mine, theirs = value[0], every[name][i]
            if name in ("value", "phase", "kind"):  # the first n are written
                mine, theirs = mine[:n], theirs[:n]
            assert np.array_equal(mine, theirs), name
        hv = np.concatenate([[v[i]], every["hv"][i]])
        turns = np.flatnonzero(((hv[:-1] > 0) & (hv[1:] <= 0)) | ((hv[:-1] < 0) & (hv[1:] >= 0)))
        assert n == turns.size
        assert np.array_equal(every["kind"][i, :n], np.where(hv[turns] > 0, 1, -1))
        values = every["value"][i, :n]
        assert every["ymax"][i] == max(y[i], every["hy"][i].max(), values.max(initial=-np.inf))
        assert every["ymin"][i] == min(y[i], every["hy"][i].min(), values.min(initial=np.inf))
