"""The scaled period map that continuation walks along, and its corrector.

A periodic orbit of period p T (T = 1 / f_e) is a zero of the residual

    R(x, f) = Phi_p(x, f) - x,      x = (y, v) at the drive's phase 0,

where Phi_p is p periods of the very RK4 map the simulator iterates (Eq. 2.4,
a fixed N steps per period, dt = 1 / (N f)): with N fixed, Phi_p is a smooth
function of (x, f) while the slider stays in contact, and a piecewise smooth
one through loss of contact (Eq. 2.1). d/dx, the monodromy matrix, and d/df come
together from the compiled tangent kernel (``shoot_jacobian``): the exact
derivatives of the discrete map, f entering it through the step dt = 1 / (N f).

The unknowns are scaled to order one so that an arclength weighs them alike:
z = (y / y0, v / (omega0 y0), f / f_n0).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from perturb import ContactModel, eq26_numbers

from ..kernels.codegen import compiled_kernels
from ..kernels.lanes import drive_table
from .options import WalkOptions

__all__ = ["ForceMap", "PeriodMap", "Point", "floquet_multipliers", "near_enough"]

def near_enough(step: float, before: float, tol: float) -> bool:
    """Whether the walk's Newton may stop after the step ``step`` (the largest component
    of it; ``before``, of the step before it): the steps still to come, at the rate
    q = step / before, add up to at most step q / (1 - q) (the a posteriori bound of a
    contraction), so the iterate is within ``tol`` (``WalkOptions.newton_tol``) of the
    root once that is.

    This saves the evaluation of R that would only show the next step below ``tol``:
    at 0.15 Q, N = 1024, Newton's steps on the bouncing arcs are some 2e-5, 4e-9, 4e-14
    (medians), and 4e-9 x 2e-4 is 8e-13. There the Python walk took 14,031 evaluations of
    R against 17,409, with the same folds (2026-11-23, before ``largest_step``). It
    stands in for one iteration, and is counted as one (``Point.iterations``), so that
    the step control sees the iterations the exact test took. The iterate's Jacobian
    and monodromy are those at the start of its last step (the exact test, too, keeps
    those from before its last step, one below ``tol``). Patient corrections (Brent's
    points, a step in f alone, the first point, the fold curves) keep the exact test.
    """
    rate = step / before
    return rate < 1.0 and step * rate < tol * (1.0 - rate)


@dataclass
class Point:
    """A corrected point of a branch: z, the Jacobian (2 x 3) and monodromy there,
    and how many Newton iterations it took (one stood in for by ``near_enough``
    counted)."""

    z: np.ndarray
    jacobian: np.ndarray
    monodromy: np.ndarray
    iterations: int

    def tangent(self, reference: np.ndarray, orientation: float) -> np.ndarray:
        """The unit tangent of the branch: the null vector of the Jacobian (from the
        bordered system with the row ``reference``, the previous tangent), signed so
        that det([J; t]) has the sign ``orientation``, the branch's own. That sign is
        kept through a fold, smooth or at a corner of the piecewise smooth map, where
        t turns back (the sign of t . reference would turn the walk around there)."""
        bordered = np.vstack([self.jacobian, reference])
        last = np.zeros(bordered.shape[0])  # any number of unknowns (the fold curves: 4)
        last[-1] = 1.0
        try:
            t = np.linalg.solve(bordered, last)
        except np.linalg.LinAlgError:  # no tangent here: NaN, taken as a failed step
            return np.full(bordered.shape[0], np.nan)
        t /= np.linalg.norm(t)
        return t if np.linalg.det(np.vstack([self.jacobian, t])) * orientation > 0 else -t

    def orientation(self, t: np.ndarray) -> float:
        """The sign of det([J; t]): the orientation that ``t`` gives the branch."""
        return float(np.sign(np.linalg.det(np.vstack([self.jacobian, t]))))

    @cached_property
    def multipliers(self) -> np.ndarray:
        """The Floquet multipliers: eigenvalues of the monodromy matrix
        (``floquet_multipliers``)."""
        return floquet_multipliers(self.monodromy)

    @property
    def stable(self) -> bool:
        return bool(np.abs(self.multipliers).max() < 1.0)

    @property
    def period_doubling_test(self) -> float:
        """det(M + I) = (1 + mu1)(1 + mu2) = 1 + tr(M) + det(M): changes sign where a
        multiplier crosses -1."""
        (a, b), (c, d) = self.monodromy
        return float(1.0 + a + d + a * d - b * c)


def floquet_multipliers(monodromy) -> np.ndarray:
    """The Floquet multipliers of each monodromy matrix (shape (..., 2, 2)): its
    eigenvalues, the roots of mu^2 - tr(M) mu + det(M) = 0, in a closed form (shape
    (..., 2), complex; a branch's points all at once)."""
    m = np.asarray(monodromy, dtype=float)
    a, b, c, d = m[..., 0, 0], m[..., 0, 1], m[..., 1, 0], m[..., 1, 1]
    half_trace, det = 0.5 * (a + d), a * d - b * c
    root = np.sqrt((half_trace * half_trace - det).astype(complex))
    return np.stack([half_trace + root, half_trace - root], axis=-1)


class PeriodMap:
    """Phi_p at one P_a and N steps per period, in the scaled unknowns z; ``options``,
    the walk's tuning (its corrector's here, its step control for the walks on it)."""

    def __init__(self, model: ContactModel, p_a_n: float, steps: int, period: int,
                 engine: str = "auto", options: WalkOptions | None = None) -> None:
        numbers = eq26_numbers(model.parameters)
        self.model, self.engine = model, engine
        self.options = WalkOptions() if options is None else options
        self.kernels = compiled_kernels(model)
        self.steps, self.period = steps, period
        self.drive = drive_table(steps)
        # z = (y / y0, v / (omega0 y0), f / f_n0).
        self.scale = np.array([numbers.y0_m, numbers.omega0_rad_s * numbers.y0_m,
                               numbers.f_n0_hz])
        self.evaluations = 0  # of R from Python (the compiled walk's are not counted)
        # Which drive is the parameter, and the other one's value (P_a [N] here).
        self.force_is_parameter, self.other = False, float(p_a_n)

    @cached_property
    def walker(self):
        """The compiled walk of the model (``kernels.walk_codegen``: built once, some 12 s), or
        None for ``engine="python"``, the reference: the walk steps in Python."""
        if self.engine == "python":
            return None
        from ..kernels.walk_codegen import compiled_walk

        return compiled_walk(self.model)

    def physical(self, z: np.ndarray) -> tuple[float, float, float]:
        """(y [m], v [m/s], the parameter: f_e [Hz]) of a scaled point."""
        y, v, f = z * self.scale
        return float(y), float(v), float(f)

    def scaled(self, y: float, v: float, f: float) -> np.ndarray:
        return np.array([y, v, f]) / self.scale

    def drives(self, parameter: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(f_e [Hz], P_a [N]) at each value of the parameter (in its physical unit)."""
        parameter = np.asarray(parameter, dtype=float)
        other = np.full(parameter.shape, self.other)
        return (other, parameter) if self.force_is_parameter else (parameter, other)

    def label(self, z: np.ndarray) -> str:
        """The parameter's value at z, for messages."""
        return f"f_e = {z[2] * self.scale[2]:.6g} Hz"

    def residual(self, z: np.ndarray):
        """R (2,), its Jacobian dR/dz (2, 3) and the monodromy matrix (2, 2) at z: one
        orbit of the compiled tangent kernel."""
        y, v, value = self.physical(z)
        (freq,), (p_a,) = self.drives([value])
        ys, vs, dt = np.array([y]), np.array([v]), np.array([1.0 / (self.steps * freq)])
        exact = np.empty((1, 2, 3))
        self.kernels.shoot_jacobian(ys, vs, dt, np.array([p_a]), self.drive, self.period,
                                    self.force_is_parameter, exact)
        self.evaluations += 1
        jacobian = exact[0] * (self.scale[None, :] / self.scale[:2, None])  # D_x^-1 J D_z
        jacobian[:, :2] -= np.eye(2)  # R = Phi - x
        if not self.force_is_parameter:
            jacobian[:, 2] *= -dt[0] / freq  # by f through dt = 1 / (N f)
        residual = (np.array([ys[0], vs[0]]) - [y, v]) / self.scale[:2]
        return residual, jacobian, exact[0, :, :2].copy()

    def correct(self, z: np.ndarray, row: np.ndarray, target: float,
                contraction: float = np.inf, estimated: bool = False) -> Point | None:
        """Newton on R(z) = 0 with the one extra equation row . z = target (the
        arclength or a fixed f); None when it does not converge, or when a Newton step is
        more than ``contraction`` times the one before (the walk's arclength steps pass
        ``WalkOptions.contraction``, ``walk.arclength_step``; by default no such test).
        It stops when a step is below ``WalkOptions.newton_tol``, or, ``estimated``, when
        the steps to come are estimated to be (``near_enough``).

        Through loss of contact the map is only piecewise smooth, and at a corner the
        Jacobian of one side points past the root on the other: a step that does not
        reduce |F| is halved (a line search, up to ``backtracks`` times), which makes
        Newton converge there too, linearly at first.

        With the compiled walk (not ``engine="python"``), the same Newton runs in its
        compiled ``correct``: a correction in Python spent some 80 % of its time around
        the kernel's (0.15 Q: 118 corrections, 385 evaluations of R, 0.096 s, of which
        0.012 s in ``shoot_jacobian``; 2026-11-23, one profile).
        """
        if self.walker is not None:
            return self._compiled_correct(z, row, target, contraction, estimated)
        tol, reach, backtracks = (self.options.newton_tol, self.options.newton_reach,
                                  self.options.backtracks)
        z = z.copy()
        bordered = np.empty((row.size, row.size))  # [dR/dz; row], any number of unknowns
        bordered[-1] = row
        before = np.inf  # the largest component of the step before
        with np.errstate(all="ignore"):
            r, jacobian, monodromy = self.residual(z)
            full = np.append(r, row @ z - target)
            for iteration in range(1, self.options.newton_iterations + 1):
                if not (np.isfinite(full).all() and np.isfinite(jacobian).all()):
                    return None
                bordered[:-1] = jacobian
                try:
                    step = np.linalg.solve(bordered, -full)
                except np.linalg.LinAlgError:
                    return None
                largest = np.abs(step).max()
                if largest < tol:
                    return Point(z + step, jacobian, monodromy, iteration)
                if not (largest < reach and largest <= contraction * before):
                    return None
                if estimated and before < np.inf and near_enough(largest, before, tol):
                    return Point(z + step, jacobian, monodromy, iteration + 1)
                before = largest
                norm = np.linalg.norm(full)
                for _ in range(backtracks):
                    trial = z + step
                    r, j_trial, m_trial = self.residual(trial)
                    f_trial = np.append(r, row @ trial - target)
                    if np.linalg.norm(f_trial) < norm:
                        break
                    step = 0.5 * step
                else:
                    return None  # no halving reduced |F|: stuck at a corner of the map
                z, full, jacobian, monodromy = trial, f_trial, j_trial, m_trial
        return None


    def _compiled_correct(self, z: np.ndarray, row: np.ndarray, target: float,
                          contraction: float, estimated: bool) -> Point | None:
        """``correct`` by the compiled walk's Newton (``kernels.walk_template.correct``)."""
        walker = self.walker
        # The corrector's numbers; the step control's are not read by ``correct``.
        settings = self.options.numbers(np.nan, np.nan, np.nan, np.nan)._replace(
            contraction=float(contraction), stop_by_estimate=float(estimated))
        z_out, jacobian, monodromy = np.empty(3), np.empty((2, 3)), np.empty((2, 2))
        iterations = walker.correct(
            np.array(z, dtype=float), np.array(row, dtype=float), float(target), self.scale,
            self.steps, self.period, self.drive, self.force_is_parameter, self.other,
            settings, z_out, jacobian, monodromy)
        return Point(z_out, jacobian, monodromy, int(iterations)) if iterations else None


class ForceMap(PeriodMap):
    """Phi_p at one f_e and N steps per period, with P_a the parameter: the scaled
    unknowns are z = (y / y0, v / (omega0 y0), P_a / Q)."""

    def __init__(self, model: ContactModel, f_hz: float, steps: int, period: int,
                 engine: str = "auto", options: WalkOptions | None = None) -> None:
        super().__init__(model, 0.0, steps, period, engine, options)
        self.scale[2] = model.parameters.Q_n
        self.force_is_parameter, self.other = True, float(f_hz)

    def label(self, z: np.ndarray) -> str:
        return f"P_a = {z[2]:.6g} Q"
