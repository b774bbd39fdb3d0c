"""The batched RK4 kernels, as a template.

``numerics.kernels.codegen`` appends this file's text to a generated
``acceleration(y, v, force)`` (Eq. 2.4 for the chosen effects, lambdified
from ``perturb``) and compiles the result with numba; so this file is never
imported on its own, and ``acceleration`` is defined by the generated part.

Integration is in phase: a lane with excitation frequency f_e takes N steps
of dt = 1 / (N f_e) per period, so that every lane sits at the same phase of
the drive after every step, and the drive cos(2 pi k / 2N) is read from one
table shared by all lanes. The lane loop is innermost, with no branch on the
hot path, so that the compiler can run several lanes per SIMD instruction.
"""

import math

import numba
import numpy as np

# fmt: off
# The classical RK4 tableau (Kutta 1901), stated as data; `rk4_step` below is
# its unrolled form and tests/test_rk4.py checks the two agree.
RK4_C = (0.0, 0.5, 0.5, 1.0)
RK4_A = ((), (0.5,), (0.0, 0.5), (0.0, 0.0, 1.0))
RK4_B = (1 / 6, 1 / 3, 1 / 3, 1 / 6)
# fmt: on


@numba.njit(cache=True, inline="always")
def rk4_step(y, v, dt, force_start, force_mid, force_end):
    """One classical RK4 step of y' = v, v' = acceleration(y, v, force)."""
    a1 = acceleration(y, v, force_start)  # noqa: F821 (generated)
    v2 = v + 0.5 * dt * a1
    a2 = acceleration(y + 0.5 * dt * v, v2, force_mid)  # noqa: F821
    v3 = v + 0.5 * dt * a2
    a3 = acceleration(y + 0.5 * dt * v2, v3, force_mid)  # noqa: F821
    v4 = v + dt * a3
    a4 = acceleration(y + dt * v3, v4, force_end)  # noqa: F821
    y_next = y + dt / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
    v_next = v + dt / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
    return y_next, v_next


@numba.njit(cache=True, inline="always")
def drive_at_step(drive, k):
    """The drive cos(2 pi t f_e) at the start, middle and end of step k (RK4's stages)."""
    return drive[2 * k], drive[2 * k + 1], drive[2 * k + 2]


@numba.njit(cache=True)
def advance_step(y, v, dt, p_a, drive, k, y_start, v_start):
    """Advance every lane by step k of the period (drive: cos table, 2N + 1 long); the
    state before it is left in (y_start, v_start). The lanes go straight, in one vector
    loop, which counts those near y = 0; the caller then splits them at their switches
    (``settle_switches``), out of this loop's way. Returns that count."""
    c0, ch, c1 = drive_at_step(drive, k)
    near = 0
    for lane in range(y.shape[0]):
        ys, vs = y[lane], v[lane]
        y1, v1 = rk4_step(ys, vs, dt[lane], p_a[lane] * c0, p_a[lane] * ch, p_a[lane] * c1)
        y[lane], v[lane] = y1, v1
        if SWITCHES:  # noqa: F821 (a count, branch-free: the loop stays a vector loop)
            y_start[lane], v_start[lane] = ys, vs
            near += near_switch(ys, vs, y1, v1, dt[lane])
    return near


@numba.njit(cache=True)
def settle_switches(y, v, dt, p_a, drive, k, y_start, v_start):
    """Step k of every lane whose straight step may cross y = 0, split at its switches."""
    for lane in range(y.shape[0]):
        if near_switch(y_start[lane], v_start[lane], y[lane], v[lane], dt[lane]):
            y[lane], v[lane], _ = switched(y_start[lane], v_start[lane], dt[lane], p_a[lane],
                                           k, drive, y[lane], v[lane])


@numba.njit(cache=True)
def mark_failed(y, v, failed_period, period, limit):
    """Record the first period in which a lane's state became non-finite or left
    |y| <= limit[lane] (an unstable step, or a model with no floor)."""
    for lane in range(y.shape[0]):
        sane = math.isfinite(v[lane]) and abs(y[lane]) <= limit[lane]  # NaN fails too
        if failed_period[lane] < 0 and not sane:
            failed_period[lane] = period


@numba.njit(cache=True)
def advance_periods(y, v, dt, p_a, drive, periods, failed_period, limit):
    """Advance every lane by whole periods, recording nothing (the hot path)."""
    steps = (drive.shape[0] - 1) // 2
    y_start, v_start = np.empty(y.shape[0]), np.empty(y.shape[0])
    for period in range(periods):
        for k in range(steps):
            if advance_step(y, v, dt, p_a, drive, k, y_start, v_start):
                settle_switches(y, v, dt, p_a, drive, k, y_start, v_start)
        mark_failed(y, v, failed_period, period, limit)


@numba.njit(cache=True, inline="always")
def hermite_extremum(y0, v0, y1, v1, dt):
    """The extremum of the cubic Hermite interpolant on a step where v changes sign.

    y(s) on s in [0, 1] matches y and dt*v at both ends; its derivative is a
    quadratic whose root in [0, 1] is the extremum. Returns (fraction, value).
    """
    d0 = dt * v0
    d1 = dt * v1
    # y'(s) = d0 + 2 p s + 3 q s^2 with the Hermite coefficients below.
    p = 3.0 * (y1 - y0) - 2.0 * d0 - d1
    q = -2.0 * (y1 - y0) + d0 + d1
    a = 3.0 * q
    b = 2.0 * p
    s = 0.5
    if a == 0.0:
        s = -d0 / b if b != 0.0 else 0.5
    else:
        disc = max(b * b - 4.0 * a * d0, 0.0)
        root = math.sqrt(disc)
        # The numerically stable pair of roots; keep the one inside [0, 1].
        qq = -0.5 * (b + math.copysign(root, b))
        s1 = qq / a
        s2 = d0 / qq if qq != 0.0 else s1
        s = s1 if 0.0 <= s1 <= 1.0 else s2
    s = min(max(s, 0.0), 1.0)
    value = y0 + s * (d0 + s * (p + s * q))
    return s, value


#: The vector loops over lanes take this many lanes at a time (LLVM's code for the
#: kernels: 4 doubles a vector, two vectors an iteration); the lanes left over run one
#: by one, several times dearer each (bench_kernel's "batches and whole vectors").
VECTOR_LANES = 8


@numba.njit(cache=True, inline="always")
def padded_width(lanes):
    """The lanes a batch runs as: whole vectors, where two or more lanes are left over
    (one lane left over costs about what a vector of copies would)."""
    rest = lanes % VECTOR_LANES
    return lanes if rest < 2 else lanes + VECTOR_LANES - rest


@numba.njit(cache=True, inline="always")
def padded(a, width):
    """A copy of the lanes ``a``, padded with copies of its first lane to ``width``."""
    out = np.empty(width)
    for lane in range(width):  # a loop: see ``copy_into``
        out[lane] = a[lane] if lane < a.shape[0] else a[0]
    return out


@numba.njit(cache=True)
def copy_into(target, source):
    """target[:] = source[:target.shape[0]] (the first lanes of a padded batch too).

    The kernels, and the sweep's driver, copy arrays in loops: numba compiles an
    assignment of one array to a slice of another (``a[:] = b``) through its
    broadcasting machinery, for seconds (bench_kernel: the first simulate() with an
    empty cache against the route that had five such assignments)."""
    for k in range(target.shape[0]):
        target[k] = source[k]


#: record_periods runs this many steps of every lane into a buffer, then reads each
#: lane's extrema from it: the buffer stays small (2 x 257 x lanes numbers) at any step.
RECORD_BLOCK = 256


@numba.njit(cache=True)
def record_periods(
    y, v, dt, p_a, drive, periods, failed_period, first_period,
    ymin, ymax, ext_value, ext_phase, ext_kind, ext_count, history_y, history_v, limit,
):
    """Advance by whole periods while recording the observables asked for.

    ymin, ymax : min and max of y over these periods (extrema refined by Hermite).
    ext_value, ext_phase, ext_kind, ext_count : every local extremum: its value
        [m], its phase in periods since the recording began, +1 for a maximum
        and -1 for a minimum, and the count per lane; width 0 when not asked for.
    history_y, history_v : y and v after every step; width 0 when not asked for.

    The steps run lanes innermost (padded to whole vectors, as ``shoot_periods``) into
    a buffer of RECORD_BLOCK steps; each lane's steps are then read in order: the
    numbers are those of finding the extrema step by step, which did not vectorise.
    """
    steps = (drive.shape[0] - 1) // 2
    lanes = y.shape[0]
    width = padded_width(lanes)
    ys, vs, dts, pas = padded(y, width), padded(v, width), padded(dt, width), padded(p_a, width)
    block_y = np.empty((RECORD_BLOCK + 1, width))  # row 0: the state before the block
    block_v = np.empty((RECORD_BLOCK + 1, width))
    for lane in range(lanes):
        ymin[lane] = y[lane]
        ymax[lane] = y[lane]
        ext_count[lane] = 0
    for period in range(periods):
        for start in range(0, steps, RECORD_BLOCK):
            count = min(RECORD_BLOCK, steps - start)
            copy_into(block_y[0], ys)
            copy_into(block_v[0], vs)
            for j in range(count):
                c0, ch, c1 = drive_at_step(drive, start + j)
                for lane in range(width):
                    pa = pas[lane]
                    ys[lane], vs[lane] = rk4_step(ys[lane], vs[lane], dts[lane], pa * c0,
                                                  pa * ch, pa * c1)
                if SWITCHES:  # noqa: F821 (row j holds the state before the step)
                    settle_switches(ys, vs, dts, pas, drive, start + j, block_y[j], block_v[j])
                for lane in range(width):
                    block_y[j + 1, lane] = ys[lane]
                    block_v[j + 1, lane] = vs[lane]
            for lane in range(lanes):
                read_steps(block_y, block_v, lane, count, period, start, steps, dts[lane],
                           ymin, ymax, ext_value, ext_phase, ext_kind, ext_count, history_y,
                           history_v)
        copy_into(y, ys)
        copy_into(v, vs)
        mark_failed(y, v, failed_period, first_period + period, limit)


@numba.njit(cache=True, inline="always")
def read_steps(block_y, block_v, lane, count, period, start, steps, dt, ymin, ymax, ext_value,
               ext_phase, ext_kind, ext_count, history_y, history_v):
    """record_periods' reading of one lane's ``count`` steps from the buffer, in order."""
    capacity = ext_value.shape[1]
    keep_history = history_y.shape[1] > 0
    for j in range(count):
        k = start + j
        y0, v0 = block_y[j, lane], block_v[j, lane]
        y1, v1 = block_y[j + 1, lane], block_v[j + 1, lane]
        ymin[lane] = min(ymin[lane], y1)
        ymax[lane] = max(ymax[lane], y1)
        if keep_history:
            history_y[lane, period * steps + k] = y1
            history_v[lane, period * steps + k] = v1
        # A local extremum lies where v changes sign within the step.
        if (v0 > 0.0 and v1 <= 0.0) or (v0 < 0.0 and v1 >= 0.0):
            s, value = hermite_extremum(y0, v0, y1, v1, dt)
            ymin[lane] = min(ymin[lane], value)
            ymax[lane] = max(ymax[lane], value)
            n = ext_count[lane]
            if n < capacity:
                ext_value[lane, n] = value
                ext_phase[lane, n] = period + (k + s) / steps
                ext_kind[lane, n] = 1 if v0 > 0.0 else -1
            ext_count[lane] = n + 1


@numba.njit(cache=True)
def acceleration_batch(y, v, force):
    """The generated acceleration at many states (for tests and plots)."""
    out = np.empty(y.shape[0])
    for i in range(y.shape[0]):
        out[i] = acceleration(y[i], v[i], force[i])  # noqa: F821
    return out


@numba.njit(cache=True, inline="always")
def stage_tangents(y, v, force, dy, dv, ey, ev):
    """The acceleration at one RK4 stage and its directional derivatives along (dy, dv)
    and (ey, ev), from one evaluation of its partials."""
    a = acceleration(y, v, force)  # noqa: F821
    a_y, a_v, _ = acceleration_partials(y, v, force)  # noqa: F821
    return a, a_y * dy + a_v * dv, a_y * ey + a_v * ev


@numba.njit(cache=True, inline="always")
def rk4_step_tangents(y, v, dy, dv, ey, ev, dt, force_start, force_mid, force_end):
    """One RK4 step and its derivatives along (dy, dv) and (ey, ev): the derivative of
    the discrete step itself, so that the monodromy matrix is exact for the map that the
    simulator iterates. The stages' partials serve both directions (a caller that needs
    one passes zeros for the other; the compiler drops its arithmetic)."""
    a1, da1, ea1 = stage_tangents(y, v, force_start, dy, dv, ey, ev)
    v2, dv2, ev2 = v + 0.5 * dt * a1, dv + 0.5 * dt * da1, ev + 0.5 * dt * ea1
    a2, da2, ea2 = stage_tangents(y + 0.5 * dt * v, v2, force_mid,
                                  dy + 0.5 * dt * dv, dv2, ey + 0.5 * dt * ev, ev2)
    v3, dv3, ev3 = v + 0.5 * dt * a2, dv + 0.5 * dt * da2, ev + 0.5 * dt * ea2
    a3, da3, ea3 = stage_tangents(y + 0.5 * dt * v2, v3, force_mid,
                                  dy + 0.5 * dt * dv2, dv3, ey + 0.5 * dt * ev2, ev3)
    v4, dv4, ev4 = v + dt * a3, dv + dt * da3, ev + dt * ea3
    a4, da4, ea4 = stage_tangents(y + dt * v3, v4, force_end,
                                  dy + dt * dv3, dv4, ey + dt * ev3, ev4)
    y_next = y + dt / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
    v_next = v + dt / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
    dy_next = dy + dt / 6.0 * (dv + 2.0 * dv2 + 2.0 * dv3 + dv4)
    dv_next = dv + dt / 6.0 * (da1 + 2.0 * da2 + 2.0 * da3 + da4)
    ey_next = ey + dt / 6.0 * (ev + 2.0 * ev2 + 2.0 * ev3 + ev4)
    ev_next = ev + dt / 6.0 * (ea1 + 2.0 * ea2 + 2.0 * ea3 + ea4)
    return y_next, v_next, dy_next, dv_next, ey_next, ev_next


@numba.njit(cache=True, inline="always")
def stage_partials(y, v, force):
    """a and its partials by y, v and the force at one stage: (a, a_y, a_v, a_force)."""
    a_y, a_v, a_force = acceleration_partials(y, v, force)  # noqa: F821
    return acceleration(y, v, force), a_y, a_v, a_force  # noqa: F821


@numba.njit(cache=True, inline="always")
def rk4_step_columns(y, v, dt, p_a, c0, ch, c1, dy, dv, dt_seed, p_a_seed):
    """One RK4 step of one lane and its derivative along each column of (dy, dv) (in
    place): the derivative of the discrete step by the start state, and, for a column
    with ``dt_seed`` or ``p_a_seed`` 1, by dt or by P_a (the drive is P_a (c0, ch, c1)
    at the step's stages). The stages' partials are computed once for all columns.
    With both seeds 0 a column's arithmetic is that of ``rk4_step_tangents``, term for
    term: the same numbers, to the last bit."""
    a1, y1_y, y1_v, y1_f = stage_partials(y, v, p_a * c0)
    y2, v2 = y + 0.5 * dt * v, v + 0.5 * dt * a1
    a2, y2_y, y2_v, y2_f = stage_partials(y2, v2, p_a * ch)
    y3, v3 = y + 0.5 * dt * v2, v + 0.5 * dt * a2
    a3, y3_y, y3_v, y3_f = stage_partials(y3, v3, p_a * ch)
    y4, v4 = y + dt * v3, v + dt * a3
    a4, y4_y, y4_v, y4_f = stage_partials(y4, v4, p_a * c1)
    sum_v = v + 2.0 * v2 + 2.0 * v3 + v4
    sum_a = a1 + 2.0 * a2 + 2.0 * a3 + a4
    for col in range(dy.shape[0]):
        e1, g1, t, q = dy[col], dv[col], dt_seed[col], p_a_seed[col]
        da1 = y1_y * e1 + y1_v * g1 + y1_f * q * c0
        e2, g2 = e1 + 0.5 * dt * g1 + 0.5 * t * v, g1 + 0.5 * dt * da1 + 0.5 * t * a1
        da2 = y2_y * e2 + y2_v * g2 + y2_f * q * ch
        e3, g3 = e1 + 0.5 * dt * g2 + 0.5 * t * v2, g1 + 0.5 * dt * da2 + 0.5 * t * a2
        da3 = y3_y * e3 + y3_v * g3 + y3_f * q * ch
        e4, g4 = e1 + dt * g3 + t * v3, g1 + dt * da3 + t * a3
        da4 = y4_y * e4 + y4_v * g4 + y4_f * q * c1
        dy[col] = e1 + dt / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4) + t / 6.0 * sum_v
        dv[col] = g1 + dt / 6.0 * (da1 + 2.0 * da2 + 2.0 * da3 + da4) + t / 6.0 * sum_a
    return y + dt / 6.0 * sum_v, v + dt / 6.0 * sum_a


# --- contact switches located within the step --------------------------------------------
# A step across y = 0 integrates straight over the switch of the laws, and RK4 falls to
# about second order there (first where a law jumps, as the damping of l = 0 does). Such
# a step is split at the switch: the crossing is bracketed on the step's cubic Hermite
# interpolant, located by Newton's method (the Illinois method where it would leave the
# bracket) on RK4 sub-steps of the side it starts on
# (its own law, extended past y = 0), and the step goes on from it with the other side's
# law. The step grid per period stays (the phase lock): the drive at a fraction s of step
# k is cos(pi (2k + 2s) / N), the table's own formula. The derivative of the step (the
# columns) is that of the split step itself: each switch time moves with the columns
# (it keeps y = 0 at the switch), and each sub-step's ends move with it
# (``moving_ends_step``). In the limit of small steps this is the saltation matrix,
# S = I + (f_after - f_before) e_y^T / v* with f = (v, a) and v* the velocity at the
# switch; here it is exact for the map the kernels iterate.

#: The two sides of y = 0, each with its own law, that the pieces of a split step take.
CONTACT, FLIGHT = 1, 2
#: Switches one step may hold; more is chattering (ever shorter flights): the lane fails.
MAX_SWITCHES = 16
#: Illinois iterations that locate a switch (each one RK4 sub-step); it stops earlier
#: once the bracket is below EVENT_RESOLUTION of the step.
EVENT_ITERATIONS = 60
EVENT_RESOLUTION = 1e-14
#: A step is looked at for a switch when an end lies within this many times
#: dt (|v_start| + |v_end|) of y = 0 on its side: the cubic Hermite interpolant dips at
#: most 4/27 of that below its lower end (0.2 leaves a margin), or y changes sign.
NEAR_SWITCH = 0.2


@numba.njit(cache=True, inline="always")
def side_acceleration(y, v, force, law):
    """The acceleration by one side's law: CONTACT's (extended past y = 0) or FLIGHT's."""
    if law == CONTACT:
        return acceleration_contact(y, v, force)  # noqa: F821
    return acceleration_flight(y, v, force)  # noqa: F821


@numba.njit(cache=True, inline="always")
def side_partials(y, v, force, law):
    """``stage_partials`` by one side's law (CONTACT, FLIGHT)."""
    if law == CONTACT:
        a_y, a_v, a_force = acceleration_partials_contact(y, v, force)  # noqa: F821
        return acceleration_contact(y, v, force), a_y, a_v, a_force  # noqa: F821
    a_y, a_v, a_force = acceleration_partials_flight(y, v, force)  # noqa: F821
    return acceleration_flight(y, v, force), a_y, a_v, a_force  # noqa: F821


@numba.njit(cache=True, inline="always")
def near_switch(y0, v0, y1, v1, dt):
    """Whether a step from (y0, v0) to (y1, v1) may cross y = 0 (a cheap, sure test)."""
    # Where y changes sign, the nearer end is within half the step's travel of y = 0:
    # one comparison, cheap in the vector loop.
    reach = NEAR_SWITCH * dt * (abs(v0) + abs(v1)) + 0.5 * abs(y1 - y0)
    return min(abs(y0), abs(y1)) <= reach


@numba.njit(cache=True, inline="always")
def drive_at(k, fraction, steps):
    """cos of the drive's phase at ``fraction`` of step k of N: the table's formula."""
    return math.cos(math.pi * (2.0 * k + 2.0 * fraction) / steps)


@numba.njit(cache=True)
def side_step(y, v, dt, p_a, k, steps, start, end, law):
    """The state after RK4 from fraction ``start`` to ``end`` of step k by one side's law
    (no partials: they are infinite at y = 0 where l < 1)."""
    h = dt * (end - start)
    f0, fh, f1 = p_a * drive_at(k, start, steps), \
        p_a * drive_at(k, 0.5 * (start + end), steps), p_a * drive_at(k, end, steps)
    a1 = side_acceleration(y, v, f0, law)
    v2 = v + 0.5 * h * a1
    a2 = side_acceleration(y + 0.5 * h * v, v2, fh, law)
    v3 = v + 0.5 * h * a2
    a3 = side_acceleration(y + 0.5 * h * v2, v3, fh, law)
    v4 = v + h * a3
    a4 = side_acceleration(y + h * v3, v4, f1, law)
    return (y + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4),
            v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4))


@numba.njit(cache=True)
def forced_columns_step(y, v, h, f0, fh, f1, law, dy, dv, h_seed, q0, qh, q1):
    """One RK4 step by ``law`` and its derivative along each column (in place), a column
    seeded by the derivative of h (``h_seed``) and of the force at each stage (q0, qh,
    q1): ``rk4_step_columns`` with stage-wise force seeds, for the sub-steps of a split
    step, whose ends move with the switch."""
    a1, y1_y, y1_v, y1_f = side_partials(y, v, f0, law)
    y2, v2 = y + 0.5 * h * v, v + 0.5 * h * a1
    a2, y2_y, y2_v, y2_f = side_partials(y2, v2, fh, law)
    y3, v3 = y + 0.5 * h * v2, v + 0.5 * h * a2
    a3, y3_y, y3_v, y3_f = side_partials(y3, v3, fh, law)
    y4, v4 = y + h * v3, v + h * a3
    a4, y4_y, y4_v, y4_f = side_partials(y4, v4, f1, law)
    sum_v = v + 2.0 * v2 + 2.0 * v3 + v4
    sum_a = a1 + 2.0 * a2 + 2.0 * a3 + a4
    for col in range(dy.shape[0]):
        e1, g1, t = dy[col], dv[col], h_seed[col]
        da1 = y1_y * e1 + y1_v * g1 + y1_f * q0[col]
        e2, g2 = e1 + 0.5 * h * g1 + 0.5 * t * v, g1 + 0.5 * h * da1 + 0.5 * t * a1
        da2 = y2_y * e2 + y2_v * g2 + y2_f * qh[col]
        e3, g3 = e1 + 0.5 * h * g2 + 0.5 * t * v2, g1 + 0.5 * h * da2 + 0.5 * t * a2
        da3 = y3_y * e3 + y3_v * g3 + y3_f * qh[col]
        e4, g4 = e1 + h * g3 + t * v3, g1 + h * da3 + t * a3
        da4 = y4_y * e4 + y4_v * g4 + y4_f * q1[col]
        dy[col] = e1 + h / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4) + t / 6.0 * sum_v
        dv[col] = g1 + h / 6.0 * (da1 + 2.0 * da2 + 2.0 * da3 + da4) + t / 6.0 * sum_a
    return y + h / 6.0 * sum_v, v + h / 6.0 * sum_a


@numba.njit(cache=True)
def moving_ends_step(y, v, dt, p_a, k, steps, start, end, law, dy, dv, dt_seed, p_a_seed,
                     moved, end_moves):
    """RK4 from fraction ``start`` to ``end`` of step k by ``law`` with the columns' exact
    derivative where the sub-step's ends are switches, which move with the columns: its
    start by ``moved`` (per column, d start; zeros at the step's start), and, with
    ``end_moves``, its end as far as keeps y = 0 there (``moved`` is then overwritten
    with d end). The columns of the switch times: their h and force seeds."""
    n = dy.shape[0]
    share, mid = end - start, 0.5 * (start + end)
    c0, ch, c1 = drive_at(k, start, steps), drive_at(k, mid, steps), drive_at(k, end, steps)
    turn = -2.0 * math.pi / steps * p_a  # d force / d fraction = turn sin(phase)
    s0 = math.sin(math.pi * (2.0 * k + 2.0 * start) / steps)
    sh = math.sin(math.pi * (2.0 * k + 2.0 * mid) / steps)
    s1 = math.sin(math.pi * (2.0 * k + 2.0 * end) / steps)
    ey, ev, h_seed = np.zeros(n + 2), np.zeros(n + 2), np.empty(n + 2)
    q0, qh, q1 = np.empty(n + 2), np.empty(n + 2), np.empty(n + 2)
    for col in range(n):
        ey[col], ev[col], h_seed[col] = dy[col], dv[col], dt_seed[col] * share
        q0[col], qh[col], q1[col] = p_a_seed[col] * c0, \
            p_a_seed[col] * ch, p_a_seed[col] * c1
    # column n: by the start fraction; column n + 1: by the end fraction
    h_seed[n], q0[n], qh[n], q1[n] = -dt, turn * s0, 0.5 * turn * sh, 0.0
    h_seed[n + 1], q0[n + 1], qh[n + 1], q1[n + 1] = dt, 0.0, 0.5 * turn * sh, turn * s1
    y1, v1 = forced_columns_step(y, v, dt * share, p_a * c0, p_a * ch, p_a * c1, law, ey, ev,
                                 h_seed, q0, qh, q1)
    for col in range(n):
        dy[col] = ey[col] + ey[n] * moved[col]
        dv[col] = ev[col] + ev[n] * moved[col]
    if end_moves:
        for col in range(n):
            moved[col] = -dy[col] / ey[n + 1] if ey[n + 1] != 0.0 else 0.0
            dy[col] += ey[n + 1] * moved[col]
            dv[col] += ev[n + 1] * moved[col]
    return y1, v1


@numba.njit(cache=True)
def first_crossing(y0, v0, y1, v1, h, contact):
    """The first fraction in (0, 1] of a step of length h where its cubic Hermite
    interpolant leaves the side it starts on (y > 0 in contact), or -1: the end if it
    is across, else the interpolant's first extremum across (a grazing touch)."""
    side = 1.0 if contact else -1.0
    c2 = -3.0 * y0 - 2.0 * h * v0 + 3.0 * y1 - h * v1
    c3 = 2.0 * y0 + h * v0 - 2.0 * y1 + h * v1
    best = 1.0 if side * y1 <= 0.0 else 2.0
    # The extrema: roots of p'(s) = h v0 + 2 c2 s + 3 c3 s^2.
    a, b, c = 3.0 * c3, 2.0 * c2, h * v0
    first, second = -1.0, -1.0  # no allocation: this runs on every step near y = 0
    if a != 0.0:
        disc = b * b - 4.0 * a * c
        if disc >= 0.0:
            root = math.sqrt(disc)
            first, second = (-b - root) / (2.0 * a), (-b + root) / (2.0 * a)
    elif b != 0.0:
        first = -c / b
    for s in (first, second):
        if 0.0 < s < best and side * (y0 + s * (h * v0 + s * (c2 + s * c3))) <= 0.0:
            best = s
    return best if best <= 1.0 else -1.0


@numba.njit(cache=True)
def locate_switch(y, v, dt, p_a, k, steps, start, end, law, y_hi):
    """The fraction in (start, end] where RK4 by ``law`` from (y, v) at ``start`` reaches
    y = 0 (y_hi, the sub-step's y at ``end``, is across): Newton's method on the
    sub-step's end (dy/ds = dt v there), kept inside the bracket, with the Illinois
    method where Newton would leave it. Some three sub-steps."""
    side = 1.0 if law == CONTACT else -1.0
    lo, hi = start, end
    g_lo = side * y if y != 0.0 else 1e-300  # just past a switch: on its new side
    g_hi = side * y_hi
    kept = 0
    mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)  # the secant through the bracket's ends
    for _ in range(EVENT_ITERATIONS):
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        y_mid, v_mid = side_step(y, v, dt, p_a, k, steps, start, mid, law)
        g_mid = side * y_mid
        if g_mid > 0.0:
            lo, g_lo = mid, g_mid
            if kept == 1:
                g_hi *= 0.5
            kept = 1
        else:
            hi, g_hi = mid, g_mid
            if kept == -1:
                g_lo *= 0.5
            kept = -1
        if g_mid == 0.0 or hi - lo < EVENT_RESOLUTION:
            break
        slope = dt * v_mid
        newton = mid - y_mid / slope if slope != 0.0 else -1.0
        if abs(newton - mid) < EVENT_RESOLUTION and lo <= newton <= hi:
            return newton
        mid = newton if lo < newton < hi else (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
    return mid


@numba.njit(cache=True)
def next_switch(y, v, dt, p_a, k, steps, start, contact):
    """The next switch of a step taken on from fraction ``start`` on the side ``contact``
    (y > 0): (its fraction, or -1 where there is none left, and then the step's end by
    that side's law)."""
    law = CONTACT if contact else FLIGHT
    y1, v1 = side_step(y, v, dt, p_a, k, steps, start, 1.0, law)
    if not (math.isfinite(y1) and math.isfinite(v1)):  # no switch to look for: it fails
        return -1.0, math.nan, math.nan
    across = first_crossing(y, v, y1, v1, dt * (1.0 - start), contact)
    end = start + across * (1.0 - start)
    y_at = y1
    if across > 0.0 and across < 1.0:  # an extremum across: is it, by the step itself?
        y_at, _v = side_step(y, v, dt, p_a, k, steps, start, end, law)
        if (y_at > 0.0) == contact:
            across = 1.0 if (y1 > 0.0) != contact else -1.0
            end, y_at = 1.0, y1
    if across < 0.0:
        return -1.0, y1, v1
    return locate_switch(y, v, dt, p_a, k, steps, start, end, law, y_at), y1, v1


@numba.njit(cache=True)
def split_step(y, v, dt, p_a, k, steps):
    """Step k of a state split at every switch of the laws within it: (y, v, switches),
    switches -1 where more than MAX_SWITCHES were met: (NaN, NaN), the lane fails."""
    contact = y > 0.0
    start = 0.0
    for event in range(MAX_SWITCHES + 1):
        at, y1, v1 = next_switch(y, v, dt, p_a, k, steps, start, contact)
        if at < 0.0:
            return y1, v1, event
        if event == MAX_SWITCHES:
            break
        _y, v_at = side_step(y, v, dt, p_a, k, steps, start, at, CONTACT if contact else FLIGHT)
        if not math.isfinite(v_at):
            break
        y, v, start, contact = 0.0, v_at, at, not contact
    return math.nan, math.nan, -1


@numba.njit(cache=True)
def event_step(y, v, dt, p_a, k, steps, y_end, v_end, dy, dv, dt_seed, p_a_seed, dy_start,
               dv_start):
    """``split_step`` with the derivative of the split step along each column (dy, dv).

    (y_end, v_end) and the columns (dy, dv) hold the straight step's result: kept, to the
    last bit, unless its interpolant crosses y = 0. Otherwise the step is taken again
    from (y, v) and the columns (dy_start, dv_start), side by side, each switch located
    and its saltation applied. Returns as ``split_step``."""
    contact = y > 0.0
    if first_crossing(y, v, y_end, v_end, dt, contact) < 0.0:
        return y_end, v_end, 0
    copy_into(dy, dy_start)
    copy_into(dv, dv_start)
    moved = np.zeros(dy.shape[0])  # d(the sub-step's start) by each column
    start = 0.0
    for event in range(MAX_SWITCHES + 1):
        law = CONTACT if contact else FLIGHT
        at, y1, v1 = next_switch(y, v, dt, p_a, k, steps, start, contact)
        if at < 0.0:  # no switch left in the step
            y1, v1 = moving_ends_step(y, v, dt, p_a, k, steps, start, 1.0, law, dy, dv,
                                      dt_seed, p_a_seed, moved, False)
            return y1, v1, event
        if event == MAX_SWITCHES:
            break
        # The columns through the switch, whose time moves with them: at the switch, y's
        # derivative is 0 and the rest is the saltation matrix's, to the step's last bit.
        _y, v_at = moving_ends_step(y, v, dt, p_a, k, steps, start, at, law, dy, dv, dt_seed,
                                    p_a_seed, moved, True)
        if not math.isfinite(v_at):
            break
        y, v, start, contact = 0.0, v_at, at, not contact
    return math.nan, math.nan, -1


@numba.njit(cache=True)
def switched(y, v, dt, p_a, k, drive, y_end, v_end):
    """Step k of a state near y = 0 (the drive table gives N), (y_end, v_end) the
    straight step's result: kept, to the last bit, unless its interpolant crosses y = 0,
    else ``split_step``'s. Returns (y, v, switches)."""
    if first_crossing(y, v, y_end, v_end, dt, y > 0.0) < 0.0:  # the straight step holds
        return y_end, v_end, 0
    return split_step(y, v, dt, p_a, k, (drive.shape[0] - 1) // 2)


@numba.njit(cache=True)
def switched_tangents(y, v, dt, p_a, k, drive, y_end, v_end, dy1, dv1, ey1, ev1, dy0, dv0,
                      ey0, ev0):
    """``event_step`` of a state and two tangent directions (as ``rk4_step_tangents``):
    (dy1, dv1), (ey1, ev1) after the straight step, (dy0, dv0), (ey0, ev0) before it."""
    if first_crossing(y, v, y_end, v_end, dt, y > 0.0) < 0.0:  # the straight step holds
        return y_end, v_end, dy1, dv1, ey1, ev1
    steps = (drive.shape[0] - 1) // 2
    dy, dv = np.array([dy1, ey1]), np.array([dv1, ev1])
    seeds = np.zeros(2)
    y1, v1, _ = event_step(y, v, dt, p_a, k, steps, y_end, v_end, dy, dv, seeds, seeds,
                           np.array([dy0, ey0]), np.array([dv0, ev0]))
    return y1, v1, dy[0], dv[0], dy[1], dv[1]


@numba.njit(cache=True)
def shoot_periods(y, v, dt, p_a, drive, periods, monodromy):
    """Advance every lane by ``periods`` periods with the derivative of the map.

    On return ``monodromy[lane]`` is the 2x2 matrix d(y, v)_end / d(y, v)_start
    (columns: derivative by y and by v); its eigenvalues are the Floquet
    multipliers of the orbit when the start is a fixed point. The batch runs padded
    to whole vectors (``padded_width``); every lane's numbers are its own.
    """
    steps = (drive.shape[0] - 1) // 2
    lanes = y.shape[0]
    width = padded_width(lanes)
    ys, vs, dts, pas = padded(y, width), padded(v, width), padded(dt, width), padded(p_a, width)
    m = np.empty((4, width))  # m00, m10, m01, m11, lane innermost for SIMD
    m[0, :] = 1.0
    m[1, :] = 0.0
    m[2, :] = 0.0
    m[3, :] = 1.0
    # The state and the columns before each step, for the lanes split at a switch.
    before = np.empty((6, width))
    for _ in range(periods):
        for k in range(steps):
            c0, ch, c1 = drive_at_step(drive, k)
            if SWITCHES:  # noqa: F821 (copied apart, as in advance_step)
                copy_into(before[0], ys)
                copy_into(before[1], vs)
                for row in range(4):
                    copy_into(before[2 + row], m[row])
            near = 0
            for lane in range(width):
                pa = pas[lane]
                yy, vv = ys[lane], vs[lane]
                f0, fh, f1 = pa * c0, pa * ch, pa * c1
                ys[lane], vs[lane], m[0, lane], m[1, lane], m[2, lane], m[3, lane] = (
                    rk4_step_tangents(yy, vv, m[0, lane], m[1, lane], m[2, lane], m[3, lane],
                                      dts[lane], f0, fh, f1))
                if SWITCHES:  # noqa: F821
                    near += near_switch(yy, vv, ys[lane], vs[lane], dts[lane])
            if near:
                for lane in range(width):
                    b = before[:, lane]
                    if near_switch(b[0], b[1], ys[lane], vs[lane], dts[lane]):
                        (ys[lane], vs[lane], m[0, lane], m[1, lane], m[2, lane],
                         m[3, lane]) = switched_tangents(
                            b[0], b[1], dts[lane], pas[lane], k, drive, ys[lane], vs[lane],
                            m[0, lane], m[1, lane], m[2, lane], m[3, lane], b[2], b[3], b[4],
                            b[5])
    copy_into(y, ys)
    copy_into(v, vs)
    for lane in range(lanes):
        monodromy[lane, 0, 0] = m[0, lane]
        monodromy[lane, 1, 0] = m[1, lane]
        monodromy[lane, 0, 1] = m[2, lane]
        monodromy[lane, 1, 1] = m[3, lane]


@numba.njit(cache=True)
def shoot_jacobian(y, v, dt, p_a, drive, periods, by_force, jacobian):
    """``shoot_periods`` with a third column: ``jacobian[lane]`` is d(y, v)_end by
    (y, v)_start and by dt (``by_force`` False) or by P_a (True), of the discrete map
    itself (the residual's exact derivative in the parameter, for continuation).

    One lane at a time, for continuation's one orbit: the stages' partials are shared by
    the three columns. (``shoot_periods`` keeps the lanes innermost, which many lanes
    need to run fast; this loop, lane by lane, would not.)
    """
    if jacobian.shape[0] != y.shape[0] or jacobian.shape[1] != 2 or jacobian.shape[2] != 3:
        raise ValueError("shoot_jacobian: jacobian must have the shape (lanes, 2, 3)")
    steps = (drive.shape[0] - 1) // 2
    # The columns' seeds: d/dy and d/dv at the start, then the parameter's.
    dt_seed = np.array([0.0, 0.0, 0.0 if by_force else 1.0])
    p_a_seed = np.array([0.0, 0.0, 1.0 if by_force else 0.0])
    dy_start, dv_start = np.empty(3), np.empty(3)
    for lane in range(y.shape[0]):
        dy, dv = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
        yy, vv, h, pa = y[lane], v[lane], dt[lane], p_a[lane]
        for _ in range(periods):
            for k in range(steps):
                c0, ch, c1 = drive_at_step(drive, k)
                y_start, v_start = yy, vv
                if SWITCHES:  # noqa: F821
                    copy_into(dy_start, dy)
                    copy_into(dv_start, dv)
                yy, vv = rk4_step_columns(yy, vv, h, pa, c0, ch, c1, dy, dv, dt_seed, p_a_seed)
                if SWITCHES and near_switch(y_start, v_start, yy, vv, h):  # noqa: F821
                    yy, vv, _ = event_step(y_start, v_start, h, pa, k, steps, yy, vv, dy, dv,
                                           dt_seed, p_a_seed, dy_start, dv_start)
        y[lane], v[lane] = yy, vv
        copy_into(jacobian[lane, 0], dy)
        copy_into(jacobian[lane, 1], dv)


@numba.njit(cache=True)
def lyapunov_periods(y, v, dy, dv, dt, p_a, drive, v_scale, log_growth, periods_per_block,
                     failed_period, first, limit):
    """Benettin's method: advance every lane and one tangent vector (dy, dv) of it by
    whole periods, the tangent by the derivative of the RK4 step (``rk4_step_tangents``).

    After each period the tangent is scaled back to unit length in the norm
    sqrt(dy^2 + (dv / v_scale)^2), and the log of its growth over the period is added
    to log_growth[lane, period // periods_per_block]; the periods run are
    log_growth.shape[1] * periods_per_block. A tangent that vanished or became
    non-finite makes its lane's sums NaN.
    """
    steps = (drive.shape[0] - 1) // 2
    lanes = y.shape[0]
    log_growth[:, :] = 0.0
    for period in range(log_growth.shape[1] * periods_per_block):
        for k in range(steps):
            c0, ch, c1 = drive_at_step(drive, k)
            for lane in range(lanes):
                pa = p_a[lane]
                yy, vv, ey, ev = y[lane], v[lane], dy[lane], dv[lane]
                y[lane], v[lane], dy[lane], dv[lane], _, _ = rk4_step_tangents(
                    yy, vv, ey, ev, 0.0, 0.0, dt[lane], pa * c0, pa * ch, pa * c1)
                if SWITCHES and near_switch(yy, vv, y[lane], v[lane], dt[lane]):  # noqa: F821
                    y[lane], v[lane], dy[lane], dv[lane], _, _ = switched_tangents(
                        yy, vv, dt[lane], pa, k, drive, y[lane], v[lane], dy[lane], dv[lane],
                        0.0, 0.0, ey, ev, 0.0, 0.0)
        block = period // periods_per_block
        for lane in range(lanes):
            norm = math.sqrt(dy[lane] * dy[lane] + (dv[lane] / v_scale) ** 2)
            if norm > 0.0:  # False for NaN too
                log_growth[lane, block] += math.log(norm)
                dy[lane] /= norm
                dv[lane] /= norm
            else:
                log_growth[lane, block] = math.nan
        mark_failed(y, v, failed_period, first + period, limit)


@numba.njit(cache=True)
def strobe_periods(y, v, dt, p_a, drive, periods, strobe_y, strobe_v, span, failed_period, first,
                   limit):
    """Advance by whole periods, keeping the state at the end of every period
    (the stroboscopic, once-per-period samples) in strobe_y[:, j], strobe_v[:, j],
    and the sampled max - min of y over the last period in ``span``."""
    steps = (drive.shape[0] - 1) // 2
    lanes = y.shape[0]
    low = np.empty(lanes)
    high = np.empty(lanes)
    y_start, v_start = np.empty(lanes), np.empty(lanes)
    for period in range(periods):
        copy_into(low, y)
        copy_into(high, y)
        for k in range(steps):
            if advance_step(y, v, dt, p_a, drive, k, y_start, v_start):
                settle_switches(y, v, dt, p_a, drive, k, y_start, v_start)
            for lane in range(lanes):
                low[lane] = min(low[lane], y[lane])
                high[lane] = max(high[lane], y[lane])
        for lane in range(lanes):
            strobe_y[lane, period] = y[lane]
            strobe_v[lane, period] = v[lane]
            span[lane] = high[lane] - low[lane]
        mark_failed(y, v, failed_period, first + period, limit)
