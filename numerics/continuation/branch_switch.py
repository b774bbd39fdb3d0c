"""Branch switching at a period doubling: the period-2p branch born there, continued.

Where a multiplier of a p-periodic orbit passes -1 (a period doubling), a branch
of 2p-periodic orbits is born. At that point x* both branches
are zeros of the 2p-fold residual R_2p(x, f) = Phi_2p(x, f) - x: the p-branch
(each of its orbits repeats after 2p periods too) and the new one, which cross
there. The 2 x 3 Jacobian [M^2 - I, dR_2p/df] has a two-dimensional null space,
spanned by the p-branch's tangent t and by (e, 0), e the eigenvector of M for the
multiplier -1 (M^2 e = e). The new branch leaves x* along the part of (e, 0)
orthogonal to t, phi: Newton on R_2p = 0 with the extra equation
phi . (z - z*) = delta lands on it, a step delta from x*, and not on the old
branch, which meets that hyperplane only far away (it is tangent to phi's
orthogonal complement at z*). From there the new branch is walked like any other
(``walk.Walk``), with the same step control and the same bifurcation tests.
"""

from __future__ import annotations

import time

import numpy as np

from perturb import ContactModel
from perturb.common import Status

from .options import WalkOptions
from .period_map import PeriodMap
from .walk import (
    PERIODS_TRIED,
    Bifurcation,
    Continuation,
    Coverage,
    Walk,
    branch_results,
    join_walks,
)

__all__ = ["switch_branch", "with_doubled_branches"]

#: The first step off the period doubling, in the scaled unknowns z (y / y0 ...): the
#: new orbits split from the old as the square root of the distance in f. At 1.25 Q
#: (doubling at 1557.16 Hz) 1e-5 puts the first point 2e-4 Hz past it; 1e-3 put it
#: 0.6 Hz past, and the branch in between was missed. Newton's tolerance is 1e-10.
_FIRST_STEP = 1e-5
#: A first point whose p-fold residual is below this (in z) is on the old branch (off it,
#: the residual is about 2 _FIRST_STEP: e turns into -e over p periods).
_OFF_OLD_BRANCH = 0.1 * _FIRST_STEP


def switch_branch(run: Continuation, bifurcation: Bifurcation, *, quiet: bool = True
                  ) -> Continuation:
    """Continue the branch of 2p-periodic orbits born at a period doubling of ``run``.

    Parameters
    ----------
    run : Continuation
        A continuation (``continue_orbits``) with ``bifurcation`` among its bifurcations.
    bifurcation : Bifurcation
        One of ``run.bifurcations`` of kind "period-doubling".
    quiet : bool
        No progress bar on stderr.

    Returns
    -------
    Continuation
        One branch of period 2p, walked from the doubling, in the band and at the steps
        per period of ``run`` (``settings["switched_at_hz"]``, a list of one, says where
        it started);
        its status and message say why it ended if it ended inside the band.

    Examples
    --------
    >>> from numerics import continue_orbits
    >>> run = continue_orbits(1.25, 1500.0, 1700.0)
    >>> doubled = switch_branch(run, run.bifurcations[0])
    >>> branch = doubled.branches[0]
    >>> branch.period, round(float(branch.frequency_hz[0]), 2), float(branch.frequency_hz[-1])
    (2, 1556.68, 1500.0)
    """
    if not isinstance(run, Continuation):
        raise ValueError(f"`run` must be a Continuation, got {type(run).__name__}.")
    if bifurcation not in run.bifurcations or bifurcation.kind != "period-doubling":
        raise ValueError("`bifurcation` must be one of `run.bifurcations` of kind "
                         f"'period-doubling', got {bifurcation!r}.")
    branch = _branch_through(run, bifurcation)
    if 2 * branch.period not in PERIODS_TRIED:
        raise ValueError(f"the doubled period {2 * branch.period} is beyond the longest "
                         f"continued, {max(PERIODS_TRIED)}.")
    start = time.perf_counter()
    model = ContactModel.from_dict(run.model)
    settings = run.settings
    p_a = run.pa_frac * model.parameters.Q_n
    engine = settings.get("engine", "auto")  # the engine the run walked with
    # The run's tuning (a run saved before it was recorded: the defaults).
    options = WalkOptions.from_dict(settings.get("walk_options", {}))
    old = PeriodMap(model, p_a, settings["steps_per_period"], branch.period, engine, options)
    new = PeriodMap(model, p_a, settings["steps_per_period"], 2 * branch.period, engine,
                    options)
    at = branch.frequency_hz == bifurcation.frequency_hz
    z_star = old.scaled(branch.y_start_m[at][0], branch.v_start_m_s[at][0],
                        bifurcation.frequency_hz)
    doubling = old.correct(z_star, np.array([0.0, 0.0, 1.0]), z_star[2])
    bar = Coverage(settings["fmin_hz"], settings["fmax_hz"], quiet)
    first, phi = (None, None) if doubling is None else first_point(old, new, doubling)
    if first is None:
        walk = Walk(new, settings["fmin_hz"], settings["fmax_hz"], 1, settings["ds_max"],
                     settings["max_angle"], settings["max_points"], bar)
        walk.end(Status.FAILED, "Newton found no period-doubled orbit next to the doubling "
                 f"at {bifurcation.frequency_hz:.6g} Hz")
    else:
        # The side of the doubling in f where the new orbits exist (they split off as
        # the square root of the distance in f past it).
        direction = 1 if first.z[2] >= doubling.z[2] else -1
        walk = Walk(new, settings["fmin_hz"], settings["fmax_hz"], direction,
                     settings["ds_max"], settings["max_angle"], settings["max_points"], bar)
        walk.run(first, away=phi)
    bar.close()
    branches, bifurcations = branch_results(new, model, join_walks([walk]))
    return Continuation(pa_frac=run.pa_frac, branches=branches, bifurcations=bifurcations,
                        model=run.model,
                        settings=settings | {"switched_at_hz": [bifurcation.frequency_hz]},
                        elapsed_s=time.perf_counter() - start)


def with_doubled_branches(run: Continuation, *, quiet: bool = True) -> Continuation:
    """``run`` with the branch born at each of its period doublings appended (and their
    bifurcations); ``settings["switched_at_hz"]`` lists the doublings switched at (not
    those of an orbit whose doubled period is beyond the longest continued: they stay in
    ``run.bifurcations``, unswitched, rather than lose the result after the work)."""
    start = time.perf_counter()
    doublings = [b for b in run.bifurcations if b.kind == "period-doubling"
                 and 2 * _branch_through(run, b).period in PERIODS_TRIED]
    switched = [switch_branch(run, b, quiet=quiet) for b in doublings]
    return Continuation(
        pa_frac=run.pa_frac, model=run.model,
        branches=run.branches + [b for s in switched for b in s.branches],
        bifurcations=run.bifurcations + [b for s in switched for b in s.bifurcations],
        settings=run.settings | {"switched_at_hz": [b.frequency_hz for b in doublings]},
        elapsed_s=run.elapsed_s + time.perf_counter() - start)


def _branch_through(run: Continuation, bifurcation: Bifurcation):
    """The branch of ``run`` that holds the bifurcation (it is one of its points)."""
    for branch in run.branches:
        if np.any(branch.frequency_hz == bifurcation.frequency_hz):
            return branch
    raise ValueError(f"no branch of `run` holds {bifurcation.summary()}")


def first_point(old: PeriodMap, new: PeriodMap, doubling):
    """The first point of the doubled branch, a step off the doubling along phi, and phi
    (both signs of phi give the same orbit, half a doubled period apart); (None, None)
    when Newton finds none off the old branch."""
    mu, vectors = np.linalg.eig(doubling.monodromy)
    e = np.real(vectors[:, np.argmin(np.abs(mu + 1.0))]) / old.scale[:2]  # into z
    t = doubling.tangent(np.array([0.0, 0.0, 1.0]), 1.0)
    phi = np.append(e, 0.0)
    phi -= (phi @ t) * t
    phi /= np.linalg.norm(phi)
    for step in (_FIRST_STEP, -_FIRST_STEP):
        point = new.correct(doubling.z + step * phi, phi, phi @ doubling.z + step)
        if point is None:
            continue
        r, *_ = old.residual(point.z)
        if np.linalg.norm(r) > _OFF_OLD_BRANCH:
            return point, np.sign(step) * phi
    return None, None
