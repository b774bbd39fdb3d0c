"""Continuation of the whole primary branch at 0.15 Q, 250-1800 Hz, with stability.

Issue 13's goal: under 0.5 s once compiled. Baselines, measured in the same run:
- the sweep up and down of the same band on a 5 Hz grid (311 points each way), which
  sees only the stable parts;
- the walk's corrections as before the contraction test and the stall hand-over
  (emulated through their ``WalkOptions``), in time and in the Python walk's
  evaluations of R;
- the walk as before Newton's stop by estimate and the steps past ds_max on large
  orbits (emulated through ``WalkOptions.stop_by_estimate`` and
  ``WalkOptions.size_ceiling``), in time, evaluations of R and points;
- the walk as before the corner's step grew with the orbit's size and a step that failed
  below it shrank faster (emulated through ``WalkOptions.corner_ceiling`` and
  ``corner_shrink``), in time, evaluations of R and points;
- the time numba takes to compile the walk (``numerics.kernels.walk_template``), the walk's cache
  bypassed, the kernels it calls already compiled (median of 3);
- continuation packages from the package index, pycont-lite and contique, driving
  ``continue_orbits``' own shooting residual from the same start points over the same
  band (``_pycont``): their time, residual calls, the points they reached and how far
  those are from the branch (|R|), the folds they reported and how each walk ended,
  and one run of each with another setting. They are not dependencies: when one is not
  installed, one line says how to install it.
Medians of interleaved repeats, warm (kernels compiled).
"""

from __future__ import annotations

import numpy as np

from numerics import WalkOptions, continue_orbits, sweep
from numerics.kernels import compiled_kernels, drive_table
from perturb import ContactModel, eq26_numbers

from ._pycont import (
    INSTALL,
    contique_walks,
    installed_version,
    period_map,
    pycont_walks,
    residual_calls,
    residual_norms,
)
from ._timing import header, interleaved_medians, row

PA_FRAC, BAND = 0.15, (250.0, 1800.0)
GRID = np.arange(BAND[0], BAND[1] + 0.5, 5.0)
PACKAGE_REPEATS = 3  # a pycont-lite run takes 15 to 20 s here
COMPILE_REPEATS = 3  # a build of the walk takes some 5 s
PACKAGES = (("pycont-lite", "pycont_lite"), ("contique", "contique"))  # name, distribution


def _continue(options: WalkOptions | None = None):
    return continue_orbits(PA_FRAC, *BAND, options=options)


def _continue_in_python(options: WalkOptions | None = None):
    return continue_orbits(PA_FRAC, *BAND, engine="python", options=options)


#: The routes before, as options of today's walk.
_DEFAULT = WalkOptions()
#: Every fold the walk meets located by Brent's method, not only those near a turn of f
#: that is reported.
_EVERY_FOLD = WalkOptions(near_turn=10**9)
#: The corrections before the contraction test and the stall hand-over: Newton spends its
#: 12 iterations at a corner, and a step shrinks to ``ds_min`` before a step in f alone
#: is tried. (The walk down at the coarser N that "auto" no longer makes is not emulated.)
_PATIENT = WalkOptions(contraction=np.inf, stall_ds=_DEFAULT.ds_min)
#: Before ``period_map.near_enough`` and ``walk.largest_step``: Newton's arclength steps
#: stop by the exact test alone (one more evaluation of R), and no step grows past ds_max.
_BEFORE_ESTIMATES = WalkOptions(stop_by_estimate=False, size_ceiling=1.0)
#: Before ``walk.corner_step`` grew the corner's step with the orbit's size (corner_ds on
#: every orbit) and a step that failed below it shrank by corner_shrink (halved, as any
#: other).
_CORNERS_BEFORE = WalkOptions(corner_ceiling=1.0, corner_shrink=_DEFAULT.shrink)


def main() -> None:
    run = _continue()  # compile / load the kernels
    sweep(GRID, PA_FRAC)
    continued, swept = interleaved_medians(_continue, lambda: sweep(GRID, PA_FRAC), repeats=5)
    header(f"Continuation at {PA_FRAC} Q, {BAND[0]:g}-{BAND[1]:g} Hz (warm, medians of 5)")
    row("continue_orbits [s] vs sweep up+down, 5 Hz [s]", continued, swept, "s",
        higher_is_better=False)
    row("continue_orbits [s] vs the goal of 0.5 s", continued, 0.5, "s",
        higher_is_better=False)
    every = interleaved_medians(_continue, lambda: _continue(_EVERY_FOLD), repeats=5)
    row("continue_orbits [s] vs locating every fold met (the route before, emulated) [s]", *every,
        "s", higher_is_better=False)
    # The Python walk's evaluations of R now, counted once for every row beside it.
    calls = residual_calls(_continue_in_python)
    _route_rows(run, calls, "Newton's exact stop, no step past ds_max", _BEFORE_ESTIMATES)
    _route_rows(run, calls, "corners as before (corner_ds on every orbit, halved)",
                _CORNERS_BEFORE)
    row(f"compiling the walk (numba, the walk's cache bypassed, the kernels' warm; median of "
        f"{COMPILE_REPEATS}) [s]", _walk_compile_seconds(), unit="s")
    patient = interleaved_medians(_continue, lambda: _continue(_PATIENT), repeats=5)
    row("continue_orbits [s] vs no contraction test, no stall hand-over (emulated) [s]",
        *patient, "s", higher_is_better=False)
    row("R evaluations of the Python walk: now vs no contraction test, no stall hand-over",
        calls, residual_calls(lambda: _continue_in_python(_PATIENT)),
        higher_is_better=False)
    steps = run.settings["steps_per_period"]
    row("N steps per period the branch took ('auto')", steps)
    compiled, python = interleaved_medians(
        lambda: continue_orbits(PA_FRAC, *BAND, steps_per_period=512),
        lambda: continue_orbits(PA_FRAC, *BAND, steps_per_period=512, engine="python"),
        repeats=3)
    row("the walk at N = 512: compiled [s] vs Python (engine='python') [s]", compiled, python,
        "s", higher_is_better=False)
    exact, differenced = _evaluation_routes(steps if isinstance(steps, int) else 1024)
    row("one evaluation of R and its Jacobian: exact [ms] vs central difference in f [ms]",
        exact, differenced, "ms", higher_is_better=False)
    points = sum(b.frequency_hz.size for b in run.branches)
    row("points on the continued branches", points)
    for branch in run.branches:
        f = branch.frequency_hz
        print(f"  {branch.summary()}; f {f.min():.3f}-{f.max():.3f} Hz")
    for mark in run.bifurcations:
        print(f"  {mark.kind} at {mark.frequency_hz:.4f} Hz, App {mark.app_m * 1e9:.2f} nm, "
              f"{mark.precision()}")
    _beside_packages(run, calls)


def _route_rows(run, calls: int, route: str, before: WalkOptions) -> None:
    """The rows of one route before, the walk with the options ``before``: time, the
    Python walk's evaluations of R and the points, against ``run``'s (and ``calls``, the
    Python walk's evaluations now)."""
    times = interleaved_medians(_continue, lambda: _continue(before), repeats=5)
    row(f"continue_orbits [s] vs {route} (the route before, emulated) [s]", *times, "s",
        higher_is_better=False)
    row("R evaluations of the Python walk: now vs that route before", calls,
        residual_calls(lambda: _continue_in_python(before)), higher_is_better=False)
    row("points on the branches: now vs that route before",
        sum(b.frequency_hz.size for b in run.branches),
        sum(b.frequency_hz.size for b in _continue(before).branches),
        higher_is_better=False)


def _walk_compile_seconds() -> float:
    """The median seconds (of COMPILE_REPEATS) numba takes to compile the paper model's
    walk (the text that ``numerics.kernels.walk_codegen`` generates, with numba's cache off, loaded
    afresh from a scratch folder each time) and run its smoke test. The kernels it
    imports are loaded already (compiled, from their cache), so this is the walk's own
    build: a first continuation's wait when the kernels are built and the walk is not,
    not the wait with an empty cache (which compiles the kernels too)."""
    import importlib.util
    import tempfile
    import time
    from pathlib import Path

    from numerics.kernels import walk_codegen

    source = walk_codegen._source(compiled_kernels(ContactModel()))
    seconds = []
    with tempfile.TemporaryDirectory() as folder:
        for repeat in range(COMPILE_REPEATS):
            name = f"walk_bench_{repeat}"  # a new module: numba compiles its functions anew
            path = Path(folder) / f"{name}.py"
            path.write_text(source.replace("cache=True", "cache=False"))
            spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            start = time.perf_counter()
            walk_codegen._smoke(module)
            seconds.append(time.perf_counter() - start)
    return float(np.median(seconds))


def _evaluation_routes(steps: int) -> tuple[float, float]:
    """Median times [ms] of one evaluation of R(z) with its Jacobian at the branch's N,
    on an orbit of the bouncing branch: ``shoot_jacobian`` (one lane, the derivative in
    f exact) against the route it replaced, ``shoot_periods`` (one lane) and a central
    difference in f of two lanes of ``advance_periods``."""
    model = ContactModel()
    kernels, drive = compiled_kernels(model), drive_table(steps)
    y0 = eq26_numbers(model.parameters).y0_m
    state = (np.array([-27.0 * y0]), np.zeros(1), np.array([1.0 / (steps * 400.0)]),
             np.array([PA_FRAC * model.parameters.Q_n]))

    def exact():
        kernels.shoot_jacobian(*[a.copy() for a in state], drive, 1, False, np.empty((1, 2, 3)))

    def differenced():
        kernels.shoot_periods(*[a.copy() for a in state], drive, 1, np.empty((1, 2, 2)))
        y, v, dt, p_a = (np.repeat(a, 2) for a in state)
        kernels.advance_periods(y, v, dt * np.array([1 + 1e-7, 1 - 1e-7]), p_a, drive, 1,
                                np.full(2, -1), np.full(2, np.inf))

    exact(), differenced()  # compiled
    seconds = interleaved_medians(lambda: [exact() for _ in range(20)],
                                  lambda: [differenced() for _ in range(20)], repeats=7)
    return tuple(1e3 * t / 20 for t in seconds)


def _beside_packages(run, calls: int) -> None:
    """The continuation packages on the same residual, start points and band as ``run``
    (``calls``: the evaluations of R of the Python walk of the same branch); one line for
    those not installed."""
    versions = {name: installed_version(distribution) for name, distribution in PACKAGES}
    missing = [name for name, version in versions.items() if version is None]
    if missing:
        print(f"\n{' and '.join(missing)} not installed, so not run beside continue_orbits: "
              f"{INSTALL}")
    if len(missing) == len(versions):
        return
    model = ContactModel()
    shoot = period_map(model, PA_FRAC, run.settings["steps_per_period"])
    ours_z = np.vstack([np.column_stack([b.y_start_m, b.v_start_m_s, b.frequency_hz])
                        for b in run.branches]) / shoot.scale
    # The compiled walk evaluates R out of Python's sight: its calls are counted on the
    # Python walk, the reference that takes the same steps (engine="python").
    ours = {"points": sum(b.frequency_hz.size for b in run.branches),
            "calls": calls,
            "largest |R|": residual_norms(shoot, ours_z).max(initial=0.0),
            "folds": ", ".join(f"{b.frequency_hz:.3f}" for b in run.folds()) or "none"}
    runs = _runs(shoot, model, run.settings["ds_max"])
    for name, version in versions.items():
        if version is not None:
            compared, setting, other = runs[name]
            _beside(name, version, compared, ours, shoot)
            other_run = other()
            print(f"  {name}, {setting}, one run of {other_run.elapsed_s:.3g} s:")
            for walk in other_run.walks:
                print(f"    {walk.describe(shoot.scale[2])}")


def _runs(shoot, model, ds_max: float) -> dict:
    """Per package: the compared run (continue_orbits' settings where they have the same
    knob), and one run with another setting, named."""
    quarter = ds_max / 4
    return {
        "pycont-lite": (lambda: pycont_walks(shoot, model, *BAND),
                        "its branch-point test on (its default)",
                        lambda: pycont_walks(shoot, model, *BAND, bifurcation_detection=True)),
        "contique": (lambda: contique_walks(shoot, model, *BAND),
                     f"its step cap {quarter:g} (a quarter of ds_max)",
                     lambda: contique_walks(shoot, model, *BAND, step_max=quarter)),
    }


def _beside(name: str, version: str, theirs, ours: dict, shoot) -> None:
    """One package's time, residual calls, points and their |R|, folds and walks, each
    beside ``continue_orbits``' (``ours``)."""
    run = theirs()  # its imports, and the run whose points are shown
    ours_s, theirs_s = interleaved_medians(_continue, theirs, repeats=PACKAGE_REPEATS)
    header(f"The same branch by {name} {version}: same residual, start points, band "
           f"(warm, medians of {PACKAGE_REPEATS})")
    row(f"continue_orbits [s] vs {name} [s]", ours_s, theirs_s, "s", higher_is_better=False)
    row(f"R calls: ours (its Python walk) vs {name}", ours["calls"], run.evaluations,
        higher_is_better=False)
    row(f"points reached: continue_orbits vs {name}", ours["points"],
        sum(w.points for w in run.walks), ratio=False)
    row(f"largest |R| at the points [z]: ours vs {name}", ours["largest |R|"],
        residual_norms(shoot, run.z).max(initial=0.0), ratio=False)
    folds = run.folds_z
    theirs_folds = "none"
    if folds.size and run.walks[0].folds_are == "folds (LP)":
        theirs_folds = (f"{', '.join(f'{z[2] * shoot.scale[2]:.3f}' for z in folds)} Hz, |R| "
                        f"there {', '.join(f'{n:.1e}' for n in residual_norms(shoot, folds))}")
    elif folds.size:
        theirs_folds = f"none reported ({run.walks[0].folds_are} below)"
    print(f"  folds at {PA_FRAC} Q: continue_orbits {ours['folds']} Hz; {name} {theirs_folds}")
    for walk in run.walks:
        print(f"  {name} {walk.describe(shoot.scale[2])}")


if __name__ == "__main__":
    main()
