"""The compiled continuation walk (``numerics/_walk_template.py``) against the Python walk
it repeats (``engine="python"``, the reference)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from numerics import _codegen, _walk_codegen, continue_orbits
from numerics._continuation import walk_band
from numerics._continuation_map import ForceMap
from numerics._walk_codegen import compiled_walk
from perturb import LINEAR, ContactModel


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
    # Newton stops at a step of 1e-10 in z (f / f_n0: some 1.5e-7 Hz); measured 3.7e-8 Hz
    # and 3.0e-10 of App.
    assert np.abs(a.frequency_hz - b.frequency_hz).max() < 1.5e-7
    assert np.abs(b.app_m / a.app_m - 1).max() < 1e-9


def test_both_engines_locate_the_same_folds(peak_005q):
    python, compiled = peak_005q["python"], peak_005q["compiled"]
    assert [m.kind for m in python.bifurcations] == [m.kind for m in compiled.bifurcations]
    for a, b in zip(python.bifurcations, compiled.bifurcations):
        assert abs(a.frequency_hz - b.frequency_hz) < 1e-6  # LOCATE_TOL in z: 1.5e-5 Hz
        assert abs(a.app_m / b.app_m - 1) < 1e-8


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
    assert np.abs(a.pa_frac - b.pa_frac).max() < 1e-9
    assert [round(m.pa_frac, 4) for m in folds_a] == [round(m.pa_frac, 4) for m in folds_b]
    assert sorted(round(m.pa_frac, 4) for m in folds_b) == [0.0456, 0.0695]


def test_an_unknown_engine_is_refused():
    with pytest.raises(ValueError, match="engine"):
        continue_orbits(0.05, 1300.0, 1600.0, engine="fortran")


@pytest.mark.slow
def test_a_damaged_walk_file_is_written_and_compiled_again(tmp_path, monkeypatch):
    # Slow: compiles the linear model's kernels and walk into an empty cache (some 25 s).
    monkeypatch.setenv("CONTACT_RESONANCES_CACHE", str(tmp_path))
    monkeypatch.setattr(_codegen, "_LOADED", {})
    monkeypatch.setattr(_walk_codegen, "_LOADED", {})
    model = ContactModel(effects=LINEAR)
    path = Path(compiled_walk(model).__file__)
    path.write_text(path.read_text()[:200])  # truncated: a crash while writing
    monkeypatch.setattr(_walk_codegen, "_LOADED", {})
    walk = compiled_walk(model)
    assert Path(walk.__file__) == path and _codegen._intact(path)
    run = continue_orbits(0.02, 1300.0, 1600.0, model=model)
    assert run.settings["engine"] == "compiled" and run.branches[0].status == 0
