"""The observables a scene asks for, read off its study's results.

Each study gives curves (a sweep run, an attractor, a simulated lane, ...). Every
curve is a dict with a ``label`` and the arrays of the observables asked for, in
SI units, named as in the glossary; nothing that was not asked for is kept.
"""

from __future__ import annotations

import numpy as np

from .schema import Scene

__all__ = ["observe", "orbit_observables", "harmonic_amplitudes", "contact_fraction", "replay",
           "HARMONICS_OF_F_E"]

#: The spectrum keeps the harmonics up to this multiple of f_e.
HARMONICS_OF_F_E = 16


def harmonic_amplitudes(y_m: np.ndarray, periods: int = 1) -> np.ndarray:
    """Amplitudes of the harmonics of y sampled evenly over ``periods`` excitation periods.

    Entry k is the amplitude at k f_e / periods (entry 0: the mean), up to
    ``HARMONICS_OF_F_E`` f_e.

    Examples
    --------
    >>> t = np.arange(64) / 64
    >>> y = 2.0 + np.cos(2 * np.pi * t) + 0.5 * np.sin(6 * np.pi * t)
    >>> np.round(harmonic_amplitudes(y), 12)[:4]
    array([2. , 1. , 0. , 0.5])
    """
    y = np.asarray(y_m, dtype=float)
    coefficients = np.fft.rfft(y) / y.size
    amplitudes = 2 * np.abs(coefficients)
    amplitudes[0] = np.abs(coefficients[0])
    if y.size % 2 == 0:  # the Nyquist term is not doubled
        amplitudes[-1] = np.abs(coefficients[-1])
    return amplitudes[: HARMONICS_OF_F_E * periods + 1]


def contact_fraction(y_m: np.ndarray) -> float:
    """Fraction of the samples (of a period, sampled evenly) where y <= 0: contact lost."""
    y = np.asarray(y_m)
    return float(np.mean(y <= 0)) if y.size else float("nan")


def observe(scene: Scene, outcomes: list, model) -> list[dict]:
    """The curves of ``outcomes`` with the scene's observables (see the module's doc)."""
    return _OBSERVERS.get(scene.study, lambda *_: [])(scene, outcomes, model)


def orbit_observables(wanted, orbits: list, periods) -> dict:
    """Spectrum and contact fraction of orbits given as y after every step."""
    out = {}
    if "spectrum" in wanted:
        out["spectrum_m"] = [harmonic_amplitudes(y, int(p)) if np.size(y) else np.empty(0)
                             for y, p in zip(orbits, periods)]
    if "contact_fraction" in wanted:
        out["contact_fraction"] = np.array([contact_fraction(y) for y in orbits])
    return out


def _sweep_curves(scene, outcomes, model) -> list[dict]:
    wanted, curves = set(scene.observables), []
    for run in outcomes[0].runs:
        curve = {"label": f"{run.pa_frac:g} Q {run.direction}", "pa_frac": run.pa_frac,
                 "direction": run.direction, "frequency_hz": run.frequency_hz,
                 "status": run.status}
        if "app" in wanted:
            curve["app_m"] = run.app_m
        if "extrema" in wanted:
            curve.update(ymin_m=run.ymin_m, ymax_m=run.ymax_m, maxima_m=run.maxima_m,
                         minima_m=run.minima_m)
        if run.orbit_y_m is not None:
            curve.update(orbit_observables(wanted, run.orbit_y_m, run.period))
        curves.append(curve)
    return curves


def replay(model, orbits, i: int, periods: int) -> dict:
    """``periods`` periods of the orbit at point ``i`` of ``orbits`` (an ``Orbits``),
    simulated again from its start with the steps it settled at: t, y and v, the start
    state first, so that a whole number of orbit periods closes on itself."""
    from ..simulation.rk4 import simulate

    f_e = float(orbits.frequency_hz[i])
    run = simulate(f_e, orbits.p_a_n[i], periods=periods,
                   steps_per_period=int(orbits.steps_used[i]), model=model,
                   y_init_m=orbits.y_start_m[i], v_init_m_s=orbits.v_start_m_s[i],
                   record=("history",), record_periods=periods)
    return {"time_s": np.r_[0.0, run.history_phase / f_e],
            "y_m": np.r_[orbits.y_start_m[i], run.history_y_m[0]],
            "v_m_s": np.r_[orbits.v_start_m_s[i], run.history_v_m_s[0]]}


def _phase_portrait(census, attractor, model) -> dict:
    """y and v over one period of the attractor, simulated again from the start of a
    lane that reached it (the start state included, so the curve is closed)."""
    lanes = census.lanes
    candidates = np.flatnonzero(lanes.settled & (lanes.period == attractor.period))
    lane = candidates[np.argmin(np.abs(lanes.app_m[candidates] - attractor.app_m))]
    orbit = replay(model, lanes, lane, int(attractor.period))
    return {"y_m": orbit["y_m"], "v_m_s": orbit["v_m_s"]}


def _attractor_curves(scene, outcomes, model) -> list[dict]:
    wanted, curves = set(scene.observables), []
    for census in outcomes:
        for a in census.attractors:
            curve = {"label": f"{a.label}, {census.frequency_hz:g} Hz, {census.pa_frac:g} Q",
                     "frequency_hz": census.frequency_hz, "pa_frac": census.pa_frac,
                     "period": a.period, "basin_fraction": a.basin_fraction}
            if "app" in wanted:
                curve["app_m"] = a.app_m
            if "extrema" in wanted:
                curve.update(ymin_m=a.ymin_m, ymax_m=a.ymax_m)
            curve.update({k: v[0] for k, v in
                          orbit_observables(wanted, [a.orbit_y_m], [a.period]).items()})
            if "phase_portrait" in wanted:
                curve.update(_phase_portrait(census, a, model))
            curves.append(curve)
    return curves


def _time_history_curves(scene, outcomes, model) -> list[dict]:
    wanted, run, curves = set(scene.observables), outcomes[0], []
    periods = run.settings["record_periods"]
    for i, (f, p_a) in enumerate(zip(run.frequency_hz, run.p_a_n)):
        curve = {"label": f"{f:g} Hz, {p_a / model.parameters.Q_n:g} Q", "frequency_hz": f,
                 "pa_frac": p_a / model.parameters.Q_n, "status": run.status[i]}
        if "app" in wanted:
            curve["app_m"] = run.app_m[i]
        if "extrema" in wanted:
            curve.update(extrema_m=run.extrema[i], ymin_m=run.ymin_m[i], ymax_m=run.ymax_m[i])
        if run.history_y_m is not None:
            y = run.history_y_m[i]
            curve.update({k: v[0] for k, v in orbit_observables(wanted, [y], [periods]).items()})
            if wanted & {"time_history", "phase_portrait", "hysteresis"}:
                curve["time_s"] = run.history_phase / f
                curve.update(y_m=y, v_m_s=run.history_v_m_s[i])
            if "hysteresis" in wanted:
                curve["pressure_pa"] = _pressure(model, y, run.history_v_m_s[i])
        curves.append(curve)
    return curves


def _pressure(model, y, v) -> np.ndarray:
    from ..contact.hysteresis import contact_pressure

    return contact_pressure(model, y, v)


def _hysteresis_curves(scene, outcomes, model) -> list[dict]:
    return [{"label": f"{loop.frequency_hz:g} Hz, {loop.pa_frac:g} Q",
             "frequency_hz": loop.frequency_hz, "pa_frac": loop.pa_frac, "y_m": loop.y_m,
             "pressure_pa": loop.pressure_pa, "app_m": float(np.ptp(loop.y_m))}
            for loop in outcomes]


def _analytic_curves(scene, outcomes, model) -> list[dict]:
    curves = []
    for frac, response in zip(scene.pa_frac, outcomes):
        for j, branch in enumerate(response.branches):
            curve = {"label": f"{frac:g} Q, branch {j}", "pa_frac": frac,
                     "frequency_hz": branch.frequency_hz, "app_m": branch.app_m,
                     "valid": branch.valid}
            curves.append(curve)
    return curves


def _backbone_curves(scene, outcomes, model) -> list[dict]:
    exact = outcomes[0]
    return [{"label": "exact backbone", "frequency_hz": exact.frequency_hz,
             "app_m": exact.app_m}]


_OBSERVERS = {
    "sweep": _sweep_curves,
    "attractors": _attractor_curves,
    "time_history": _time_history_curves,
    "hysteresis": _hysteresis_curves,
    "analytic_response": _analytic_curves,
    "backbone": _backbone_curves,
}
