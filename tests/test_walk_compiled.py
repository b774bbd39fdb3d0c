"""The compiled continuation walk (``numerics/kernels/walk_template.py``) against the Python walk
it repeats (``engine="python"``, the reference)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from numerics import continue_orbits
from numerics.continuation.period_map import ForceMap, PeriodMap
from numerics.continuation.walk import _band_walk, walk_band
from numerics.kernels import codegen, walk_codegen
from numerics.kernels.walk_codegen import compiled_walk
from perturb import LINEAR, ContactModel, eq26_numbers
from perturb.cache import intact
from perturb.common import Status


@pytest.fixture(scope="module")
def peak_005q():
    """The bent primary peak at 0.05 Q by both engines."""
    return {engine: continue_orbits(0.05, 1300.0, 1600.0, engine=engine)
            for engine in ("python", "compiled")}


def test_both_engines_walk_the_same_points_to_newtons_tolerance(peak_005q):
    python, compiled = peak_005q["python"], peak_005q["compiled"]
    assert (python.settings["engine"], compiled.settings["engine"]) == ("python", "compiled")
    (a,), (b,) = python.branches, compiled.branches
    assert a.frequency_hz.size == b.frequency_hz.size == 120
    assert np.array_equal(a.stable, b.stable)
    # Newton stops at a step of 1e-10 in z (f / f_n0: some 1.5e-7 Hz), so the engines'
    # points may differ by that; measured 3.7e-8 Hz and 3.0e-10 of App.
    assert np.abs(a.frequency_hz - b.frequency_hz).max() < 1.5e-7
    assert np.abs(b.app_m / a.app_m - 1).max() < 1e-9


def test_both_engines_locate_the_same_folds(peak_005q):
    python, compiled = peak_005q["python"], peak_005q["compiled"]
    assert [m.kind for m in python.bifurcations] == [m.kind for m in compiled.bifurcations]
    for a, b in zip(python.bifurcations, compiled.bifurcations):
        # Brent brackets the same sign change in both: measured 6.1e-12 Hz, 2.2e-14 of App.
        assert abs(a.frequency_hz - b.frequency_hz) < 1e-10
        assert abs(a.app_m / b.app_m - 1) < 1e-12


def test_the_compiled_walk_continues_in_the_force_amplitude_as_python_does():
    model = ContactModel()
    runs = {}
    for engine in ("python", "compiled"):
        shoot = ForceMap(model, 1400.0, 512, 1, engine)
        runs[engine] = walk_band(shoot, model, 0.02 * model.parameters.Q_n,
                                 0.1 * model.parameters.Q_n, 0.02, 0.1, 20_000, True)
    (a,), folds_a = runs["python"]
    (b,), folds_b = runs["compiled"]
    assert a.pa_frac.size == b.pa_frac.size
    assert np.abs(a.pa_frac - b.pa_frac).max() < 1e-11  # measured 1.4e-12
    assert [round(m.pa_frac, 4) for m in folds_a] == [round(m.pa_frac, 4) for m in folds_b]
    assert sorted(round(m.pa_frac, 4) for m in folds_b) == [0.0456, 0.0695]


def test_an_explicit_step_count_is_kept():
    # At 0.15 Q and 512 steps the walk passes the bouncing fold (without the contact
    # switches located within the step, both walks stopped at corners, and 512 steps
    # were kept all the same).
    run = continue_orbits(0.15, 250.0, 1800.0, steps_per_period=512)
    assert run.settings["steps_per_period"] == 512
    assert [b.status for b in run.branches] == [Status.SUCCESS]


def test_steps_in_f_alone_never_turn_a_walk_back_onto_its_own_points(monkeypatch):
    # Regression: at 0.17 Q a step in f alone landed on a point the walk had passed (where
    # f zigzagged over the map's corners) and the walk retraced its branch up to 1800 Hz,
    # with two "folds" where it turned round. With each contact switch located within its
    # step the map has no corners: "auto" walks once, at 512 steps, over the whole band
    # (1,211 points), through both folds, each located (the bouncing one at 263.28 Hz;
    # without the events it took walks at 512, 1024 and 2048 steps, and the bouncing fold
    # was only marked, 263.29 Hz +-0.15 Hz). No point is walked twice.
    from numerics.continuation import walk as c

    made, band_walk = [], c._band_walk
    monkeypatch.setattr(c, "_band_walk", lambda shoot, *args: made.append(
        (shoot.steps, args[-1])) or band_walk(shoot, *args))
    run = continue_orbits(0.17, 250.0, 1800.0)
    assert run.settings["steps_per_period"] == 512
    assert made == [(512, 1)]
    assert [round(b.frequency_hz) for b in run.folds()] == [1318, 263]
    assert all(b.located for b in run.folds())
    for branch in run.branches:
        states = np.c_[branch.y_start_m / np.abs(branch.y_start_m).max(),
                       branch.v_start_m_s / np.abs(branch.v_start_m_s).max(),
                       branch.frequency_hz / branch.frequency_hz.max()]
        pairs = cKDTree(states).query_pairs(1e-9, output_type="ndarray")
        assert not np.any(np.abs(np.diff(pairs, axis=1)) > 50), branch.summary()


def test_an_unknown_engine_is_refused():
    with pytest.raises(ValueError, match="engine"):
        continue_orbits(0.05, 1300.0, 1600.0, engine="fortran")


@pytest.mark.slow
def test_a_damaged_walk_file_is_written_and_compiled_again(tmp_path, monkeypatch):
    # Slow: compiles the linear model's kernels and walk into an empty cache (some 25 s).
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    monkeypatch.setattr(codegen, "_LOADED", {})
    monkeypatch.setattr(walk_codegen, "_LOADED", {})
    model = ContactModel(effects=LINEAR)
    path = Path(compiled_walk(model).__file__)
    path.write_text(path.read_text()[:200])  # truncated: a crash while writing
    monkeypatch.setattr(walk_codegen, "_LOADED", {})
    walk = compiled_walk(model)
    assert Path(walk.__file__) == path and intact(path)
    run = continue_orbits(0.02, 1300.0, 1600.0, model=model)
    assert run.settings["engine"] == "compiled" and run.branches[0].status == 0


def test_the_compiled_walk_reads_each_number_of_its_options_by_name():
    # The walk's numbers reach the compiled walk as a named tuple (WalkNumbers), made from
    # its WalkOptions: each field must hold the option of its name. Options that are equal
    # by default (size_ceiling and corner_ceiling 20, shrink and contraction 0.5, ...) are
    # made distinct here, and all are checked to be, so that two fields swapped fail.
    # The template must read every field: one it never reads is a setting without effect.
    import dataclasses
    import re

    from numerics.continuation import period_map as m
    from numerics.continuation import walk as c
    from numerics.continuation.options import WalkNumbers, WalkOptions
    from numerics.kernels import walk_codegen

    options = WalkOptions(ds_start=2e-3, ds_min=3e-9, stall_ds=4e-5, grow=1.6, shrink=0.45,
                          easy_iterations=4, turn_share=0.85, corner_ds=1.1e-3,
                          corner_ceiling=21.0, corner_shrink=0.26, straight=0.032,
                          size_reference=2.2, size_ceiling=19.0, near_turn=5,
                          newton_tol=1.1e-10, newton_iterations=13, newton_reach=0.12,
                          backtracks=7, contraction=0.55, stop_by_estimate=True)
    shoot = m.ForceMap(ContactModel(), 1400.0, 512, 1, options=options)
    walk = c.Walk(shoot, 0.01, 0.2, 1, 0.031, 0.07, 10, None)
    given = {"ds_max": 0.031, "max_angle": 0.07, "f_lo": 0.01 / shoot.scale[2],
             "f_hi": 0.2 / shoot.scale[2]}
    expected = {name: float(given[name] if name in given else getattr(options, name))
                for name in WalkNumbers._fields}
    switches = {"stop_by_estimate", "corners", "shrink_by_turn"}  # True: 1.0 each
    numbers = [value for name, value in expected.items() if name not in switches]
    assert len(set(numbers)) == len(numbers) and 1.0 not in numbers  # a swap would show
    assert walk.settings._asdict() == expected
    for switch in switches:  # each switch in its own field
        off = c.Walk(m.ForceMap(ContactModel(), 1400.0, 512, 1,
                                options=dataclasses.replace(options, **{switch: False})),
                     0.01, 0.2, 1, 0.031, 0.07, 10, None).settings._asdict()
        assert {k for k in off if off[k] != expected[k]} == {switch}
    unused = {f.name for f in dataclasses.fields(WalkOptions)} - set(WalkNumbers._fields)
    assert unused == {"ds_start", "near_turn"}  # Python's alone: the walk's start, its folds
    read = set(re.findall(r"settings\.(\w+)", walk_codegen._TEMPLATE.read_text()))
    assert read == set(WalkNumbers._fields)


def test_the_corners_step_grows_with_the_orbit_but_not_past_ds_max():
    # ``corner_step`` in Python and in the compiled walk: corner_ds (1e-3) times the
    # orbit's size |(y, v)| in z over size_reference (2), up to corner_ceiling times,
    # and never above the user's ds_max (with ds_max = 0.005 at 0.15 Q the uncapped step
    # reached 0.014, so that a sharp turn over any step up to ds_max was taken for a
    # corner; capped, that walk took 5075 points against 4978, the same two folds:
    # measured once by hand, 2026-11-24).
    from numerics.continuation import period_map as m
    from numerics.continuation import walk as c

    shoot = m.PeriodMap(ContactModel(), 0.15 * ContactModel().parameters.Q_n, 512, 1)
    module = shoot.walker
    for ds_max, size, step in [(0.02, 1.0, 1e-3), (0.02, 28.0, 0.014), (0.02, 100.0, 0.02),
                               (0.005, 28.0, 0.005), (0.005, 6.0, 0.003),
                               (5e-4, 1.0, 5e-4)]:
        z = np.array([0.6 * size, -0.8 * size, 0.3])
        settings = c.Walk(shoot, 250.0, 1800.0, 1, ds_max, 0.1, 10, None).settings
        # rel 1e-12: the round-off of |(y, v)| alone (0.6 and 0.8 are not exact in binary).
        python = c.corner_step(z, ds_max, shoot.options)
        assert python == pytest.approx(step, rel=1e-12), (ds_max, size)
        assert module.corner_step(z, settings) == python, (ds_max, size)


def test_both_engines_walk_the_same_bouncing_branch_at_0_15_q():
    # The twin tests above walk orbits in contact (orbit_scale 1); this one walks the
    # bouncing branch, where the largest and the corner's steps grow with the orbit's size
    # (|(y, v)| up to 25.8 in z here), up from 250 Hz at N = 512, through both folds.
    model = ContactModel()
    p_a = 0.15 * model.parameters.Q_n
    walks = {engine: _band_walk(PeriodMap(model, p_a, 512, 1, engine), model, 250.0, 1800.0,
                                0.02, 0.1, 20_000, True, 1)
             for engine in ("python", "compiled")}
    a, b = (np.array([p.z for p in walks[e].points]) for e in ("python", "compiled"))
    scale_f = PeriodMap(model, p_a, 512, 1, "python").scale[2]
    # Measured: 1,069 points each, the same Newton iterations at every point, the same two
    # folds located, both walks to the band's end. (Without the contact switches located
    # within the step: 792 points, stopped at a corner at 353.9985 Hz, two folds marked.)
    assert len(a) == len(b) == 1069
    assert [p.iterations for p in walks["python"].points] == [
        p.iterations for p in walks["compiled"].points]
    marks = {e: [m[:3] for m in w.marks] for e, w in walks.items()}  # index, kind, located
    assert marks["python"] == marks["compiled"] == [(161, "fold", True), (617, "fold", True)]
    assert all(w.status == Status.SUCCESS for w in walks.values())
    # Newton stops at a step of 1e-10 in z (some 1.5e-7 Hz), so the points may differ by
    # that; measured 6.5e-10 Hz (round-off: the same steps in the same order).
    assert np.abs(a[:, 2] - b[:, 2]).max() * scale_f < 1.5e-7
    assert np.abs(a - b).max() < 1e-10  # in z, Newton's tolerance; measured 7.6e-12
    assert a[-1, 2] * scale_f == pytest.approx(1800.0, abs=1e-9)


@pytest.mark.parametrize("engine", ["compiled", "python"])
@pytest.mark.parametrize(("pa_frac", "band", "kind", "errors_hz", "reaches_hz"), [
    # Measured: the doubling marked 0.149 Hz below where Brent locates it (the steps here
    # are some 6 Hz in f; 0.63 Hz without the contact switches located within the step),
    # reach 6.15 Hz; the two folds of 0.05 Q marked 0.096 and 0.034 Hz away, reaches 0.20
    # and 0.12 Hz.
    (1.25, (1500.0, 1700.0), "period-doubling", [0.149], [6.15]),
    (0.05, (1300.0, 1600.0), "fold", [0.096, 0.034], [0.20, 0.12]),
])
def test_a_bifurcation_that_cannot_be_located_is_marked_not_lost(
        monkeypatch, engine, pa_frac, band, kind, errors_hz, reaches_hz):
    # Where Newton cannot correct between two points (a corner between them), Brent's
    # method fails: the bifurcation is then marked at the last point kept, within one
    # step, and says so: not located, with the step's reach in f as its tolerance, which
    # holds where Brent's method (not forced to fail) locates it.
    from numerics.continuation import walk as c

    located = [b for b in continue_orbits(pa_frac, *band, engine=engine).bifurcations
               if b.kind == kind]
    assert [b.located for b in located] == [True] * len(errors_hz)
    # Brent's xtol of 1e-8 in z, in f: 1e-8 f_n0 (1.4856e-5 Hz; measured within 7.6e-9 of
    # it, relative, as the difference of two f_e each rounded to 2.3e-13 Hz).
    f_tol = c.LOCATE_TOL * eq26_numbers().f_n0_hz
    assert all(b.frequency_tol_hz == pytest.approx(f_tol, rel=5e-8) and b.pa_frac_tol == 0.0
               for b in located)
    monkeypatch.setattr(c.Walk, "locate", lambda self, *args: None)
    marked = [b for b in continue_orbits(pa_frac, *band, engine=engine).bifurcations
              if b.kind == kind]
    assert [b.located for b in marked] == [False] * len(errors_hz)
    for at, near, error, reach in zip(located, marked, errors_hz, reaches_hz):
        assert abs(near.frequency_hz - at.frequency_hz) < near.frequency_tol_hz
        # Close to the measured error and reach (10 %): a change in either is seen.
        assert abs(near.frequency_hz - at.frequency_hz) == pytest.approx(error, rel=0.1)
        assert near.frequency_tol_hz == pytest.approx(reach, rel=0.1)
        assert near.pa_frac_tol == 0.0
        assert "marked within one step" in near.summary()


def test_both_engines_walk_alike_without_corners_and_with_the_plain_shrink():
    # The fold curves' walk takes no corners and shrinks a sharp turn by `shrink` alone
    # (WalkOptions.for_fold_curves); the compiled walk reads the same two switches. At
    # 0.15 Q the switches change the walk (its points, against the default's), and both
    # engines walk it alike.
    from numerics import WalkOptions

    plain = WalkOptions(corners=False, shrink_by_turn=False)
    runs = {engine: continue_orbits(0.15, 250.0, 1800.0, engine=engine, options=plain,
                                    steps_per_period=512)
            for engine in ("python", "compiled")}
    default = continue_orbits(0.15, 250.0, 1800.0, steps_per_period=512)
    a, b = runs["python"].branches, runs["compiled"].branches
    assert [x.frequency_hz.size for x in a] == [x.frequency_hz.size for x in b]
    assert [x.frequency_hz.size for x in a] != [x.frequency_hz.size for x in default.branches]
    for x, y in zip(runs["python"].bifurcations, runs["compiled"].bifurcations, strict=True):
        assert x.kind == y.kind and abs(x.frequency_hz - y.frequency_hz) < 1e-6
