"""The scaled period map that continuation walks along, and its corrector.

A periodic orbit of period p T (T = 1 / f_e) is a zero of the residual

    R(x, f) = Phi_p(x, f) - x,      x = (y, v) at the drive's phase 0,

where Phi_p is p periods of the very RK4 map the simulator iterates (Eq. 2.4,
a fixed N steps per period, dt = 1 / (N f)): with N fixed, Phi_p is a smooth
function of (x, f) while the slider stays in contact, and a piecewise smooth
one through loss of contact (Eq. 2.1). d/dx is the monodromy matrix from the
compiled tangent kernel (``shoot_periods``), d/df a central difference, both
in one kernel call of three lanes.

The unknowns are scaled to order one so that an arclength weighs them alike:
z = (y / y0, v / (omega0 y0), f / f_n0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perturb import ContactModel, eq26_numbers

from ._codegen import compiled_kernels
from ._lanes import drive_table

__all__ = ["ForceMap", "PeriodMap", "Point"]

#: Relative step of the central difference in f: its truncation error (h^2, 1e-10) and
#: its round-off (1e-14 of y over h, 1e-9) are both far below Newton's tolerance.
_DF_REL = 1e-5
#: Newton stops when the scaled update is below this (y to 1e-10 y0, some 2e-17 m on
#: the paper's model; the round-off of one period of RK4 is about 1e-13 y0).
NEWTON_TOL = 1e-10
NEWTON_ITERATIONS = 12
#: Newton gives up when a step exceeds this (in z: a tenth of y0, of f_n0): it has left
#: the point it was asked to correct.
_NEWTON_REACH = 0.1
_BACKTRACKS = 6


@dataclass
class Point:
    """A corrected point of a branch: z, the Jacobian (2 x 3) and monodromy there,
    and how many Newton iterations it took."""

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
        t = np.linalg.solve(bordered, last)
        t /= np.linalg.norm(t)
        return t if np.linalg.det(np.vstack([self.jacobian, t])) * orientation > 0 else -t

    def orientation(self, t: np.ndarray) -> float:
        """The sign of det([J; t]): the orientation that ``t`` gives the branch."""
        return float(np.sign(np.linalg.det(np.vstack([self.jacobian, t]))))

    @property
    def multipliers(self) -> np.ndarray:
        """The Floquet multipliers: eigenvalues of the monodromy matrix."""
        return np.linalg.eigvals(self.monodromy).astype(complex)

    @property
    def stable(self) -> bool:
        return bool(np.abs(self.multipliers).max() < 1.0)

    @property
    def period_doubling_test(self) -> float:
        """det(M + I) = (1 + mu1)(1 + mu2): changes sign where a multiplier crosses -1."""
        return float(np.linalg.det(self.monodromy + np.eye(2)))


class PeriodMap:
    """Phi_p at one P_a and N steps per period, in the scaled unknowns z."""

    def __init__(self, model: ContactModel, p_a_n: float, steps: int, period: int) -> None:
        numbers = eq26_numbers(model.parameters)
        self.kernels = compiled_kernels(model)
        self.steps, self.period = steps, period
        self.drive = drive_table(steps)
        self.p_a = np.full(3, p_a_n)
        # z = (y / y0, v / (omega0 y0), f / f_n0).
        self.scale = np.array([numbers.y0_m, numbers.omega0_rad_s * numbers.y0_m,
                               numbers.f_n0_hz])
        self.evaluations = 0

    def physical(self, z: np.ndarray) -> tuple[float, float, float]:
        """(y [m], v [m/s], the parameter: f_e [Hz]) of a scaled point."""
        y, v, f = z * self.scale
        return float(y), float(v), float(f)

    def scaled(self, y: float, v: float, f: float) -> np.ndarray:
        return np.array([y, v, f]) / self.scale

    def drives(self, parameter: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(f_e [Hz], P_a [N]) at each value of the parameter (in its physical unit)."""
        parameter = np.asarray(parameter, dtype=float)
        return parameter, np.full(parameter.shape, self.p_a[0])

    def label(self, z: np.ndarray) -> str:
        """The parameter's value at z, for messages."""
        return f"f_e = {z[2] * self.scale[2]:.6g} Hz"

    def difference_step(self, value: float) -> float:
        """The step of the central difference in the parameter at ``value``."""
        return _DF_REL * value

    def residual(self, z: np.ndarray):
        """R (2,), its Jacobian dR/dz (2, 3) and the monodromy matrix (2, 2) at z."""
        y, v, value = self.physical(z)
        h = self.difference_step(value)
        freq, p_a = self.drives(np.array([value, value + h, value - h]))
        ys, vs = np.full(3, y), np.full(3, v)
        monodromy = np.empty((3, 2, 2))
        self.kernels.shoot_periods(ys, vs, 1.0 / (self.steps * freq), p_a, self.drive,
                                   self.period, monodromy)
        self.evaluations += 1
        d = self.scale[:2]
        r = np.array([ys[0] - y, vs[0] - v]) / d
        jacobian = np.empty((2, 3))
        # D^-1 (M - I) D: the monodromy in the scaled state.
        jacobian[:, :2] = (monodromy[0] - np.eye(2)) * d[None, :] / d[:, None]
        jacobian[:, 2] = np.array([ys[1] - ys[2], vs[1] - vs[2]]) / (2 * h) * self.scale[2] / d
        return r, jacobian, monodromy[0]


    def correct(self, z: np.ndarray, row: np.ndarray, target: float) -> Point | None:
        """Newton on R(z) = 0 with the one extra equation row . z = target (the
        arclength or a fixed f); None when it does not converge.

        Through loss of contact the map is only piecewise smooth, and at a corner the
        Jacobian of one side points past the root on the other: a step that does not
        reduce |F| is halved (a line search, up to _BACKTRACKS times), which makes
        Newton converge there too, linearly at first.
        """
        z = z.copy()
        with np.errstate(all="ignore"):
            r, jacobian, monodromy = self.residual(z)
            full = np.append(r, row @ z - target)
            for iteration in range(1, NEWTON_ITERATIONS + 1):
                if not (np.isfinite(full).all() and np.isfinite(jacobian).all()):
                    return None
                try:
                    step = np.linalg.solve(np.vstack([jacobian, row]), -full)
                except np.linalg.LinAlgError:
                    return None
                if np.abs(step).max() < NEWTON_TOL:
                    return Point(z + step, jacobian, monodromy, iteration)
                if not np.abs(step).max() < _NEWTON_REACH:
                    return None
                norm = np.linalg.norm(full)
                for _ in range(_BACKTRACKS):
                    trial = z + step
                    r, j_trial, m_trial = self.residual(trial)
                    f_trial = np.append(r, row @ trial - target)
                    if np.linalg.norm(f_trial) < norm:
                        break
                    step = 0.5 * step
                z, full, jacobian, monodromy = trial, f_trial, j_trial, m_trial
        return None


class ForceMap(PeriodMap):
    """Phi_p at one f_e and N steps per period, with P_a the parameter: the scaled
    unknowns are z = (y / y0, v / (omega0 y0), P_a / Q)."""

    def __init__(self, model: ContactModel, f_hz: float, steps: int, period: int) -> None:
        super().__init__(model, 0.0, steps, period)
        self.f_hz = f_hz
        self.scale[2] = model.parameters.Q_n

    def drives(self, parameter: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        parameter = np.asarray(parameter, dtype=float)
        return np.full(parameter.shape, self.f_hz), parameter

    def label(self, z: np.ndarray) -> str:
        return f"P_a = {z[2]:.6g} Q"

    def difference_step(self, value: float) -> float:
        return _DF_REL * max(abs(value), self.scale[2])  # relative to Q: P_a may be near 0
