"""The perturbation series against the exact backbone and RK4 steady states."""

import json
from functools import partial as _partial

import numpy as np
import pytest

from numerics import Orbits, Status, compare
from numerics.cli import main
from numerics.comparison.backbones import compare_backbones
from numerics.comparison.responses import SteadyCurve, compare_response, steady_curve
from perturb import frequency_response

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")
compare = _partial(compare, truncation="paper")
compare_backbones = _partial(compare_backbones, truncation="paper")

ORDERS = (2, 4, 6, 8, 10)


@pytest.fixture(scope="module")
def backbones():
    return compare_backbones(ORDERS)


def error_at(backbones, a1: float) -> np.ndarray:
    """Each order's relative error at the fundamental amplitude a1 (log-log interpolation)."""
    return np.exp([np.interp(np.log(a1), np.log(backbones.a1_m), np.log(np.maximum(e, 1e-300)))
                   for e in backbones.relative_error])


@pytest.mark.parametrize("a1_over_y0", [0.2, 0.5, 0.8])
def test_series_backbone_converges_below_contact_loss(backbones, a1_over_y0):
    # Contact is lost at a1 = 0.861 y0 (193.9 nm); below it the full model is Eq. 2.6 (m2 = 2:
    # the quadratic Taylor spring is exact) and the series converges to it.
    y0 = backbones.contact_loss_app_m / np.sqrt(3)
    errors = error_at(backbones, a1_over_y0 * y0)
    assert np.all(np.diff(errors) < 0), f"a1 = {a1_over_y0} y0: errors {errors}"


def test_series_backbone_diverges_past_contact_loss(backbones):
    # Bouncing: the series of Eq. 2.6 knows nothing of the flight, and higher
    # orders only go further wrong.
    errors = backbones.relative_error[:, -1]
    assert np.all(np.diff(errors) > 0) and errors[0] > 0.5, errors


def test_backbone_limits_bracket_contact_loss(backbones):
    loss = backbones.contact_loss_app_m
    assert backbones.limit_app_m[0] < loss  # order 2 fails before contact is lost
    assert np.all((backbones.limit_app_m > 0.9 * loss) & (backbones.limit_app_m < 1.5 * loss))
    # Within its limit each order is within 1 %, just past it it is not.
    for n, limit, error in zip(ORDERS, backbones.limit_app_m, backbones.relative_error):
        assert np.all(error[backbones.app_m < 0.99 * limit] <= 0.01), n


@pytest.fixture(scope="module")
def half_superharmonic():
    # The 1/2 superharmonic peak at 0.05 Q (f_e ~ f_n0 / 2, Eq. 3.1).
    return compare((4, 6, 8), (0.05,), frequency_hz=np.arange(700.0, 800.0, 5.0))


def test_series_response_converges_to_rk4_of_eq26(half_superharmonic):
    errors = [half_superharmonic.response("eq26", 0.05, n).largest_error for n in (4, 6, 8)]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-5, errors
    peak = half_superharmonic.response("eq26", 0.05, 8).peaks[1]
    assert peak.k == 2 and peak.series_hz == peak.rk4_hz == 745.0
    assert peak.height_ratio == pytest.approx(1, abs=1e-5)


def test_full_model_parts_by_its_damping_law_at_the_half_peak(half_superharmonic):
    # Measured 0.16 %, whatever the order: the power-law damping y^l ydot is not
    # its linearisation at y0; the series (of Eq. 2.6) cannot follow it.
    errors = [half_superharmonic.response("full", 0.05, n).largest_error for n in (4, 6, 8)]
    assert np.all((np.array(errors) > 1e-3) & (np.array(errors) < 3e-3)), errors


def test_where_the_full_model_parts_from_eq26():
    result = compare((6,), (0.05, 0.10), frequency_hz=np.arange(1300.0, 1500.0, 5.0))
    gentle, strong = result.parting(0.05), result.parting(0.10)
    # 0.05 Q: no contact loss; near the primary peak the damping law alone parts them.
    assert gentle["differ_with_contact_loss"] == 0 and gentle["differ_in_contact"] > 0
    assert min(gentle["in_contact_hz"]) >= 1370 and max(gentle["in_contact_hz"]) <= 1445
    # 0.10 Q: every state that differs loses contact.
    assert strong["differ"] > 0 and strong["differ_in_contact"] == 0


def test_cli_compare_prints_writes_and_draws(tmp_path, capsys):
    path, picture = tmp_path / "compare.json", tmp_path / "compare.png"
    code = main(["compare", "--orders", "2", "4", "--pa-frac", "0.05", "--json", str(path),
                 "--plot", str(picture), "--quiet"])
    assert code == 0
    payload = json.loads(path.read_text())
    assert payload["backbone"]["orders"] == [2, 4]
    assert {(r["model_name"], r["order"]) for r in payload["responses"]} == {
        (m, n) for m in ("eq26", "full") for n in (2, 4)}
    assert picture.read_bytes()[:4] == b"\x89PNG"
    out = capsys.readouterr()
    assert "A_pp limit" in out.out and out.err == ""


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="`orders`"):
        compare_backbones(())
    with pytest.raises(ValueError, match="`model_name`"):
        steady_curve(np.array([700.0, 710.0]), 0.05, "linear")


def test_unmatched_states_count_in_the_largest_error():
    # Regression: largest_error left out RK4 states with no valid series response
    # within 10 %, so a disagreement showed only as "+N". At 0.05 Q, 1395 Hz the
    # order-4 series has one response (the lower branch, 99.1 nm): its fold lies
    # above 1395 Hz, while RK4 of Eq. 2.6 also holds the upper branch (327.0 nm).
    grid = np.array([1390.0, 1395.0])
    points = Orbits.empty(np.array([1395.0, 1395.0]), np.zeros(2), 128)
    points.status[:] = Status.SUCCESS
    points.ymin_m[:] = 1e-7
    points.ymax_m[:] = 1e-7 + np.array([99.12e-9, 327.02e-9])
    curve = SteadyCurve(model_name="eq26", pa_frac=0.05, direction=np.array(["up", "down"]),
                        notes=[], **points.columns())
    result = compare_response(curve, 4, grid)
    assert result.unmatched.tolist() == [False, True]
    assert result.largest_error == pytest.approx(1 - 99.1 / 327.0, abs=2e-3)
    assert result.largest_matched_error < 1e-3
    # compare() solves the series once for both models' curves and hands it in.
    given = compare_response(curve, 4, grid, response=frequency_response(grid, 0.05, 4))
    assert given.as_dict() == result.as_dict()
    # A response that is not the series asked for is refused, saying what differs: only
    # that (regression: the order's mismatch was said to be "on another grid").
    mismatches = {
        "order": (frequency_response(grid, 0.05, 6),
                  "not the series asked for: its order is 6, not 4."),
        "amplitude": (frequency_response(grid, 0.1, 4),
                      "not the series asked for: its P_a is 0.1 Q, not the curve's 0.05 Q."),
        "grid size": (frequency_response(np.array([1390.0, 1395.0, 1400.0]), 0.05, 4),
                      "its grid has 3 points (1390-1400 Hz), `grid` 2 (1390-1395 Hz)."),
        "grid points": (frequency_response(np.array([1390.0, 1396.0]), 0.05, 4),
                        "its grid differs from `grid` at 1 of 2 points, first at 1396.0 Hz "
                        "against 1395.0 Hz."),
    }
    for what, (response, message) in mismatches.items():
        with pytest.raises(ValueError) as raised:
            compare_response(curve, 4, grid, response=response)
        assert str(raised.value).endswith(message), (what, str(raised.value))
        assert str(raised.value).count(";") == 0, (what, str(raised.value))


def test_backbone_limits_stop_at_contact_loss(backbones):
    # Regression: the 1 % limits of orders 4-10 (540, 498, 485 nm, ...) lay past
    # contact loss (390 nm), where the slider flies and the series' error only
    # passes through zero on its way from + to -: the limit is capped there, and
    # the crossing is kept apart.
    loss = backbones.contact_loss_app_m
    assert np.all(backbones.limit_app_m <= loss)
    assert np.all(backbones.crossing_app_m[1:] > loss) and backbones.capped[1:].all()
    assert backbones.limit_app_m[0] == backbones.crossing_app_m[0] < loss
    beyond = backbones.app_m > loss
    for n, error, signed in zip(ORDERS[1:], backbones.relative_error[1:],
                                backbones.series_hz[1:] / backbones.exact_hz - 1):
        assert signed[beyond & (error > 0.003)].min() < 0 < signed[beyond].max(), n


@pytest.mark.parametrize(
    "flags, option",
    [(["--pa-frac", "nan"], "--pa-frac"), (["--pa-frac", "-0.1"], "--pa-frac"),
     (["--pa-frac", "inf"], "--pa-frac"), (["--orders", "-1"], "--orders"),
     (["--orders", "2.5"], "--orders")],
)
def test_cli_compare_bad_input_is_an_argparse_error(flags, option, capsys):
    # Regression: --pa-frac nan ran the RK4 sweeps into a traceback naming the
    # internal `p_a_n`; -1 gave a message that did not say which option was wrong.
    with pytest.raises(SystemExit) as exit_info:
        main(["compare", *flags, "--quiet"])
    assert exit_info.value.code == 2
    assert f"argument {option}:" in capsys.readouterr().err


@pytest.mark.parametrize(
    "kwargs, name",
    [({"pa_frac": (0.05, np.nan)}, "`pa_frac`"), ({"pa_frac": (-0.1,)}, "`pa_frac`"),
     ({"pa_frac": ()}, "`pa_frac`"), ({"orders": (2, -1)}, "`orders`"),
     ({"orders": (2.5,)}, "`orders`"), ({"orders": ()}, "`orders`"),
     ({"tolerance": 0.0}, "`tolerance`"), ({"tolerance": np.nan}, "`tolerance`")],
)
def test_compare_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        compare(**kwargs, frequency_hz=np.array([700.0, 710.0]))


def test_compare_without_force_is_rest_everywhere():
    # Regression: P_a = 0 gave the series no response (0/0 in b_n) and 0/0 in the
    # relative errors; both routes give rest, so the errors are 0.
    result = compare((2,), (0.0,), frequency_hz=np.array([700.0, 710.0]))
    assert result.response("eq26", 0.0, 2).largest_error == 0.0
    assert result.parting(0.0)["differ"] == 0


@pytest.mark.slow
def test_series_agrees_with_rk4_of_eq26_where_valid():
    # docs/backbone.md quotes these (matched states, 0.05-0.15 Q over the paper's
    # band): better than 0.75 % at order 4, 0.26 % at order 8 (measured 0.71 %, 0.25 %).
    result = compare((4, 8), (0.05, 0.10, 0.15))
    largest = {n: max(result.response("eq26", p, n).largest_matched_error
                      for p in (0.05, 0.10, 0.15)) for n in (4, 8)}
    assert largest[4] < 0.0075 and largest[8] < 0.0026, largest


def test_the_comparison_runs_the_model_it_is_given(tmp_path):
    # --set and a scene's [model] reach every part of the comparison: the series, RK4 of
    # Eq. 2.6 and of the full model, and the backbone. With m2 = 1.5, l = 0.5 (f_n0 16.5
    # kHz, y0 1.37 nm) the order-6 series is 1.7e-6 from RK4 of Eq. 2.6 (measured); had
    # either side kept the paper's model, the two would be apart by orders of magnitude.
    from perturb import ContactModel, parameters_with

    other = parameters_with({"m2": 1.5, "l": 0.5})
    grid = np.arange(300.0, 900.0, 50.0)
    result = compare((6,), 0.05, frequency_hz=grid, model=ContactModel(other))
    paper = compare((6,), 0.05, frequency_hz=grid)
    with pytest.warns(DeprecationWarning, match="model=ContactModel"):
        spelled_before = compare((6,), 0.05, frequency_hz=grid, parameters=other)
    assert spelled_before.response("eq26", 0.05, 6).largest_error == \
        result.response("eq26", 0.05, 6).largest_error
    assert result.model["parameters"]["m2"] == 1.5
    assert result.response("eq26", 0.05, 6).largest_error < 1e-5
    ours, theirs = result.curve("eq26", 0.05).app_m, paper.curve("eq26", 0.05).app_m
    assert np.all(ours < 0.1 * theirs)  # the stiffer contact moves far less
    assert result.backbone.model == result.model
    assert main(["compare", "--orders", "2", "--pa-frac", "0.05", "--set", "m2=1.5",
                 "--set", "l=0.5", "--quiet", "--json", str(tmp_path / "c.json")]) == 0
    assert json.loads((tmp_path / "c.json").read_text())["model"]["parameters"]["m2"] == 1.5


def test_the_comparison_refuses_a_model_that_is_not_the_full_one():
    # It runs Eq. 2.6's model beside the full one: a model of other effects would be
    # silently replaced, so it is refused, naming the argument.
    from perturb import EQ_2_6, PAPER, ContactModel

    with pytest.raises(ValueError, match="`model` must be a ContactModel with the full"):
        compare((2,), 0.05, model=ContactModel(effects=EQ_2_6))
    with pytest.raises(ValueError, match="not both"), pytest.warns(DeprecationWarning):
        compare((2,), 0.05, model=ContactModel(), parameters=PAPER)
