"""The stability of the series' roots: the Floquet multipliers of the orbits they describe.

A root of the frequency equation (Eq. 2.7, 2.8) at f_e describes a periodic orbit
of Eq. 2.6; ``perturb.series_orbits`` gives its state x = (y, v) at the drive's
phase 0. Here that state starts Newton on the RK4 period map of Eq. 2.6 at the
root's f_e (Phi(x) = x, fixed f, N steps per period: the shooting of
``steady_states`` and ``continue_orbits``), all roots of all branches as lanes of
one kernel call per iteration. The eigenvalues of the monodromy matrix at the
orbit Newton converges to are its Floquet multipliers; the orbit is stable when
both lie inside the unit circle.

A flag is given only where the orbit found is the root's: Newton converged, the
orbit lies within ``reach`` times the series' error estimate, plus RK4's own
error, of the series' state, and no other root's state at that f_e lies nearer
to it (an estimate of 300 %, as on the 1/2 superharmonic at 0.3 Q, would let
any orbit in). Elsewhere the stability is unknown (``None``), with the reason: no
error estimate (the series has no root of orders N+1, N+2 nearby, typically past
loss of contact or next to a fold), no convergence, an orbit too far away, or
another root's orbit (Newton from a root far from its own orbit lands on another).
"""

from __future__ import annotations

import time

import numpy as np

from perturb import ContactModel, Response, eq26_numbers, series_orbits
from perturb.common import Result, Status, check_int, check_positive, result

from ..continuation.options import WalkOptions
from ..steady.options import SteadyOptions
from ..steady.shooting import SPAN_FLOOR, Batch, eigenvalues, solve_2x2

__all__ = ["SeriesBranchStability", "SeriesStability", "series_stability", "DEFAULTS"]

DEFAULTS = {"steps_per_period": 512, "reach": 4.0}
#: RK4's own error on the orbit's state, relative to App/2, is bounded by (omega0 dt)^4:
#: measured (N = 512 against N = 4096, order-6 roots at 0.05 and 0.15 Q, 250-1600 Hz) at
#: most 0.28 of it, at the 1/2 superharmonic peak (742 Hz, 0.15 Q).
_RK4_ERROR_ORDER = 4
#: ``Batch.newton`` stops when a step is below tol * 1e-3 (of y0): this tol makes that
#: the continuation's corrector tolerance, ``WalkOptions.newton_tol`` (1e-10 y0).
_NEWTON_TOL = WalkOptions().newton_tol
_NEWTON_BATCH_TOL = _NEWTON_TOL * 1e3


@result
class SeriesBranchStability(Result):
    """The stability of one branch of a ``perturb.Response``, root by root.

    Attributes
    ----------
    frequency_hz : ndarray
        f_e of each root [Hz] (the branch's).
    app_m : ndarray
        The series' App of each root [m] (the branch's).
    multipliers : ndarray, shape (roots, 2), complex
        The Floquet multipliers of the Eq. 2.6 orbit the root describes (NaN where
        that orbit was not found).
    orbit_distance : ndarray
        |dy| / (App/2) + |dv| / (Omega App/2): how far the RK4 orbit Newton converged
        to lies from the series' state at phase 0 (NaN where it did not converge).
    y_start_m, v_start_m_s : ndarray
        The RK4 orbit's state at phase 0 [m, m/s] (NaN where not found).
    status : ndarray of int
        ``common.Status``: success where the flag is backed by the orbit, failed where
        the stability is unknown.
    message : list of str
        Why the stability is unknown ("" where it is known).

    ``stable`` (derived, in the JSON too): True, False, or None where unknown.
    """

    LANES = "frequency_hz"  # a table of lanes: every array has one row per lane

    frequency_hz: np.ndarray
    app_m: np.ndarray
    multipliers: np.ndarray
    orbit_distance: np.ndarray
    y_start_m: np.ndarray
    v_start_m_s: np.ndarray
    status: np.ndarray
    message: list[str]

    @property
    def known(self) -> np.ndarray:
        """Where the stability flag is backed by the orbit (status success)."""
        return np.asarray(self.status) == int(Status.SUCCESS)

    @property
    def stable(self) -> np.ndarray:
        """Per root: True (both multipliers inside the unit circle), False, or None."""
        inside = np.abs(np.asarray(self.multipliers)).max(axis=1, initial=0.0) < 1.0
        out = np.full(self.known.size, None, dtype=object)
        out[self.known] = inside[self.known]
        return out

    def derived(self) -> dict:
        return {"stable": self.stable}

    def summary(self) -> str:
        flags = self.stable.tolist()
        return (f"SeriesBranchStability: {len(flags)} roots, {flags.count(True)} stable, "
                f"{flags.count(False)} unstable, {flags.count(None)} unknown")


@result
class SeriesStability(Result):
    """The stability of every root of a ``perturb.Response``.

    Attributes
    ----------
    order : int
        N of the series.
    pa_frac : float
        P_a / Q.
    branches : list of SeriesBranchStability
        Branch j: the stability of the response's branch j.
    model : dict
        The response's model (``EQ_2_6`` effects for the paper's truncation).
    settings : dict
        ``steps_per_period`` (N of the RK4 period map) and ``reach``.
    elapsed_s : float
    """

    order: int
    pa_frac: float
    branches: list[SeriesBranchStability]
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        roots = sum(b.frequency_hz.size for b in self.branches)
        unknown = sum(int(np.sum(~b.known)) for b in self.branches)
        return (f"SeriesStability: order {self.order}, P_a = {self.pa_frac:g} Q, "
                f"{len(self.branches)} branch(es), {roots} roots ({unknown} unknown), "
                f"{self.elapsed_s:.3g} s")

    def table(self) -> str:
        return "\n".join(f"  branch {j}: {b.summary()}" for j, b in enumerate(self.branches))


def series_stability(response: Response, *, steps_per_period: int = DEFAULTS["steps_per_period"],
                     reach: float = DEFAULTS["reach"]) -> SeriesStability:
    """Stable, unstable or unknown: each root of ``response``, by the Floquet multipliers
    of the orbit it describes, in the response's model (Eq. 2.6's for the paper's
    truncation, the contact's own for the consistent one).

    Parameters
    ----------
    response : perturb.Response
        The series' response (``perturb.frequency_response``).
    steps_per_period : int
        N of the RK4 period map (``continue_orbits`` takes at least 512 too).
    reach : float
        The orbit backs a flag only within ``reach`` times the series' error estimate
        (plus RK4's own error, (omega0 dt)^4) of the series' state, relative to App/2.

    Returns
    -------
    SeriesStability

    Examples
    --------
    >>> import numpy as np
    >>> from perturb import frequency_response
    >>> response = frequency_response(np.array([1000.0, 1400.0]), 0.05, 6, truncation="paper")
    >>> [b.stable.tolist() for b in series_stability(response).branches]
    [[True, True], [None, False], [None, True]]
    """
    if not isinstance(response, Response):
        raise ValueError(f"`response` must be a perturb.Response, got {response!r}.")
    steps = check_int("steps_per_period", steps_per_period, minimum=4)
    reach = check_positive("reach", reach)
    start = time.perf_counter()
    model = ContactModel.from_dict(response.model)
    branches = response.branches
    lanes = _Roots.gather(branches, response.order, model,
                          response.settings.get("truncation", "paper"))
    found = _shoot(model, lanes, response.pa_frac * model.parameters.Q_n, steps)
    distance, status, message = _verdict(lanes, found, model, steps, reach)
    out = []
    for b, part in zip(branches, lanes.branches()):
        known = status[part] == int(Status.SUCCESS)
        out.append(SeriesBranchStability(
            frequency_hz=b.frequency_hz.copy(), app_m=b.app_m.copy(),
            multipliers=np.where(known[:, None], found.multipliers[part], np.nan),
            orbit_distance=distance[part],
            y_start_m=np.where(known, found.y[part], np.nan),
            v_start_m_s=np.where(known, found.v[part], np.nan),
            status=status[part], message=[message[i] for i in part]))
    return SeriesStability(order=response.order, pa_frac=response.pa_frac, branches=out,
                           model=response.model,
                           settings={"steps_per_period": steps, "reach": reach},
                           elapsed_s=time.perf_counter() - start)


class _Roots:
    """Every root of every branch as one lane: f_e, App, error estimate, series' state;
    branch j's lanes are ``bounds[j]:bounds[j + 1]``."""

    def __init__(self, f, app, estimate, y, v, bounds):
        self.f, self.app, self.estimate, self.y, self.v = f, app, estimate, y, v
        self.bounds = bounds

    def branches(self) -> list[np.ndarray]:
        """The lanes of each branch."""
        return [np.arange(lo, hi) for lo, hi in zip(self.bounds[:-1], self.bounds[1:])]

    @classmethod
    def gather(cls, branches, order: int, model: ContactModel, truncation: str) -> _Roots:
        starts = [series_orbits(b, order, model.parameters, truncation=truncation)
                  for b in branches]

        def column(values):
            return np.concatenate([np.asarray(a, dtype=float) for a in values] or [[]])

        return cls(column(b.frequency_hz for b in branches), column(b.app_m for b in branches),
                   column(b.error_estimate for b in branches),
                   column(s.y_start_m for s in starts), column(s.v_start_m_s for s in starts),
                   np.cumsum([0] + [b.frequency_hz.size for b in branches]))


class _Found:
    """Newton's result per lane: the state, the multipliers there, and whether it converged."""

    def __init__(self, y, v, multipliers, converged):
        self.y, self.v, self.multipliers, self.converged = y, v, multipliers, converged


#: The farthest (in App/2) an orbit may lie from a root's state and still give it a flag.
MOST_ALLOWED = 0.5


def _shoot(model, lanes: _Roots, p_a: float, steps: int) -> _Found:
    """Newton on the RK4 period map of Eq. 2.6 from the series' states, all lanes at once
    (``Batch.newton``: one kernel call per iteration), then one more call at the result:
    its monodromy gives the multipliers, and the Newton step it gives says whether Newton
    converged (``Batch.newton`` folds that into one flag with stability)."""
    n = lanes.f.size
    if not n:
        return _Found(np.empty(0), np.empty(0), np.empty((0, 2), dtype=complex),
                      np.empty(0, dtype=bool))
    batch = Batch(model, lanes.f, np.full(n, p_a), steps, SteadyOptions(tol=_NEWTON_BATCH_TOL))
    index = np.arange(n)
    _, y, v, _, _ = batch.newton(index, lanes.y, lanes.v, 1, lanes.app, np.inf)
    with np.errstate(all="ignore"):
        yp, vp, monodromy = y.copy(), v.copy(), np.empty((n, 2, 2))
        batch.kernels.shoot_periods(yp, vp, batch.dt, batch.p_a, batch.drive, 1, monodromy)
        step_y, step_v = solve_2x2(monodromy - np.eye(2), y - yp, v - vp)
        size = batch.distance(index, step_y, step_v, batch.length)
    converged = np.isfinite(size) & (size < _NEWTON_TOL)
    return _Found(y, v, eigenvalues(monodromy), converged)


def _verdict(lanes: _Roots, found: _Found, model, steps: int, reach: float):
    """Per lane: the orbit's distance from the series' state, and status and message."""
    numbers = eq26_numbers(model.parameters)
    omega = 2 * np.pi * lanes.f
    # Relative to App/2 (v to Omega App/2), App at least a thousandth of y0 (at rest).
    half = np.maximum(lanes.app, SPAN_FLOOR * numbers.y0_m) / 2

    def distance_to(y, v):
        with np.errstate(all="ignore"):
            return np.abs(found.y - y) / half + np.abs(found.v - v) / (omega * half)

    distance = np.where(found.converged, distance_to(lanes.y, lanes.v), np.nan)
    rk4_error = (numbers.omega0_rad_s / (steps * lanes.f)) ** _RK4_ERROR_ORDER
    # At most half the amplitude, whatever the estimate: an estimate above 1 (an invalid
    # root) would let in any orbit (a review found 0.3 Q, 690 Hz flagged stable on a
    # 98 nm orbit for a 206 nm root, 1.35 App/2 away).
    allowed = np.minimum(reach * lanes.estimate + rk4_error, MOST_ALLOWED)
    nearest = _nearest_root(lanes, distance_to)
    near = (found.converged & np.isfinite(lanes.estimate) & (distance <= allowed)
            & (nearest == np.arange(lanes.f.size)))
    status = np.where(near, int(Status.SUCCESS), int(Status.FAILED))
    message = [""] * lanes.f.size
    for i in np.flatnonzero(~near):
        message[i] = _why_unknown(lanes, found, i, distance[i], allowed[i], reach, nearest[i])
    return distance, status, message


def _nearest_root(lanes: _Roots, distance_to) -> np.ndarray:
    """Per lane, the lane whose series' state (of the roots at the same f_e) lies nearest
    the orbit found; a lane whose own root is as near as any other gets itself."""
    _, group = np.unique(lanes.f, return_inverse=True)
    best, nearest = distance_to(lanes.y, lanes.v), np.arange(lanes.f.size)
    # Branch j has at most one root per frequency: one vectorised pass per branch's lanes,
    # each lane compared with the same-frequency root of that branch where there is one.
    for other in lanes.branches():
        at = np.full(group.max(initial=-1) + 1, -1)
        at[group[other]] = other
        j = at[group]
        has = j >= 0
        j = np.where(has, j, 0)
        d = np.where(has, distance_to(lanes.y[j], lanes.v[j]), np.inf)
        closer = has & (d < best)
        best, nearest = np.where(closer, d, best), np.where(closer, j, nearest)
    return nearest


def _why_unknown(lanes: _Roots, found: _Found, i: int, distance, allowed, reach,
                 nearest) -> str:
    where = f"f_e = {lanes.f[i]:g} Hz"
    if not found.converged[i]:
        return (f"{where}: Newton on the RK4 period map of Eq. 2.6 did not converge from "
                "the series' state")
    if not np.isfinite(lanes.estimate[i]):
        return (f"{where}: the series has no error estimate here (no root of orders N+1, "
                f"N+2 nearby), so nothing says whether the orbit found, {distance:.3g} App/2 "
                "from its state, is the root's")
    if distance > allowed:
        return (f"{where}: the orbit found lies {distance:.3g} App/2 from the series' "
                f"state, beyond {allowed:.3g} ({reach:g} x its error estimate "
                f"{lanes.estimate[i]:.3g} plus RK4's error, at most {MOST_ALLOWED:g}): "
                "another orbit")
    return (f"{where}: the orbit found lies nearer the state of another root of the series "
            f"(App {lanes.app[nearest]:.4g} m) than its own: another root's orbit")
