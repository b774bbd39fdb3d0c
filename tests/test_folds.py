"""Fold curves in the (f_e, P_a) plane and their cusps (issue 13, item 4).

Two routes to the same folds: the fold curve (Newton on [R; det(M - I)] in four
unknowns, continued in (f_e, P_a)) and one-parameter continuation in f_e at a fixed
P_a, which locates each fold by Brent's method on the sign of the tangent's f-part.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from common import Status, load
from numerics import FoldCurves, continue_orbits, fold_curves

#: continue_orbits locates a fold to LOCATE_TOL = 1e-8 in f / f_n0 (1.5e-5 Hz) along the
#: arclength; the fold curve solves g = 0 to Newton's 1e-10. Measured: the two agree
#: within 7e-7 Hz at every level below (1e-9 relative in App).
F_TOL_HZ = 2e-5
APP_RTOL = 1e-8

#: (box fmin, fmax, pa_min, pa_max; seeds; levels checked; resonance m; cusp f, P_a as
#: measured; the share above the cusp at which continuation sees two folds)
CASES = {
    "primary": ((1300.0, 1500.0, 0.03, 0.05), [0.05], (0.035, 0.04, 0.045), 1,
                1442.43, 0.0334268, 1.05),
    "1/2": ((650.0, 800.0, 0.3, 0.4), None, (0.35, 0.37, 0.4), 2, 714.658, 0.344527, 1.01),
    "1/3": ((400.0, 520.0, 0.6, 0.8), None, (0.62, 0.7, 0.8), 3, 469.014, 0.607179, 1.01),
}


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    box, seeds, *rest = CASES[request.param]
    return fold_curves(*box, seed_pa_fracs=seeds), CASES[request.param]


def test_the_fold_curves_pass_through_the_folds_of_one_parameter_continuation(case):
    folds, (box, _, levels, *_) = case
    for pa in levels:
        continued = continue_orbits(pa, box[0], box[1]).folds()
        on_curves = folds.folds_at(pa)
        assert continued, f"no fold at {pa} Q: the comparison would be empty"
        for fold in continued:
            gaps = [abs(c.frequency_hz - fold.frequency_hz) for c in on_curves]
            nearest = on_curves[int(np.argmin(gaps))]
            assert min(gaps) < F_TOL_HZ, (pa, fold, on_curves)
            assert nearest.app_m == pytest.approx(fold.app_m, rel=APP_RTOL)


def test_a_cusp_exists_and_below_it_continuation_finds_no_fold(case):
    folds, (box, _, _, m, f_cusp, pa_cusp, above) = case
    [cusp] = folds.cusps
    assert cusp.resonance == m
    # The cusp as measured (its f to 0.01 Hz, P_a to 1e-6 Q: it is located to 1e-8 in
    # the arclength, where P_a is stationary).
    assert cusp.frequency_hz == pytest.approx(f_cusp, abs=0.01)
    assert cusp.pa_frac == pytest.approx(pa_cusp, abs=1e-6)
    assert min(c.pa_frac.min() for c in folds.fold_curves) == pytest.approx(cusp.pa_frac,
                                                                              abs=1e-9)
    assert continue_orbits(0.99 * cusp.pa_frac, box[0], box[1]).folds() == []
    # The negative control: just above the cusp continuation does find the two folds
    # (the primary's pair is 0.9 Hz apart at 1.05 times its cusp; continuation drops
    # turns of f under 0.15 Hz, so nearer the cusp it sees none).
    assert len(continue_orbits(above * cusp.pa_frac, box[0], box[1]).folds()) == 2


def test_the_folds_on_a_curve_are_folds():
    """A point of a fold curve has a Floquet multiplier 1 (to the Newton tolerance)."""
    folds = fold_curves(1300.0, 1500.0, 0.03, 0.05, seed_pa_fracs=[0.05])
    [curve] = folds.fold_curves
    assert curve.status == Status.SUCCESS, curve.message
    nearest_one = np.abs(curve.multipliers - 1.0).min(axis=1)
    assert nearest_one.max() < 1e-8
    # Both ends on the box's top edge: the curve runs from one fold at 0.05 Q to the other.
    assert curve.pa_frac[[0, -1]] == pytest.approx([0.05, 0.05], abs=1e-12)


def test_json_round_trip(tmp_path, case):
    folds, _ = case
    folds.to_json(tmp_path / "folds.json")
    back = load(tmp_path / "folds.json")
    assert isinstance(back, FoldCurves)
    assert back.cusps[0].pa_frac == folds.cusps[0].pa_frac
    np.testing.assert_array_equal(back.fold_curves[0].frequency_hz,
                                  folds.fold_curves[0].frequency_hz)


@pytest.mark.parametrize("kwargs, name", [
    ({"fmin_hz": -1.0}, "fmin_hz"),
    ({"fmax_hz": 1200.0}, "fmax_hz"),
    ({"pa_min": 0.0}, "pa_min"),
    ({"pa_max": 0.02}, "pa_max"),
    ({"seed_pa_fracs": [0.2]}, "seed_pa_fracs"),
    ({"ds_max": 0.0}, "ds_max"),
    ({"max_points": 1}, "max_points"),
])
def test_bad_input_names_the_argument(kwargs, name):
    args = {"fmin_hz": 1300.0, "fmax_hz": 1500.0, "pa_min": 0.03, "pa_max": 0.05, **kwargs}
    box = [args.pop(k) for k in ("fmin_hz", "fmax_hz", "pa_min", "pa_max")]
    with pytest.raises(ValueError, match=f"`{name}`"):
        fold_curves(*box, **args)


def test_the_folds_command(tmp_path):
    out, png = tmp_path / "folds.json", tmp_path / "folds.png"
    done = subprocess.run([sys.executable, "-m", "numerics", "folds", "--fmin", "1300",
                           "--fmax", "1500", "--pa-min", "0.03", "--pa-max", "0.05",
                           "--seed-pa-frac", "0.05", "--json", str(out), "--plot", str(png),
                           "--quiet"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "Cusp: primary at 1442.43 Hz" in done.stdout
    assert done.stderr == ""
    data = json.loads(out.read_text())
    assert data["kind"] == "FoldCurves"
    assert [c["resonance"] for c in data["cusps"]] == [1]
    assert png.stat().st_size > 10_000


def test_the_folds_command_rejects_a_bad_band():
    done = subprocess.run([sys.executable, "-m", "numerics", "folds", "--fmin", "1300",
                           "--fmax", "1500", "--pa-min", "0.05", "--pa-max", "0.03"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "--pa-max" in done.stderr.splitlines()[-1]
