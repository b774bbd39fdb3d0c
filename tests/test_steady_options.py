"""``SteadyOptions``: the steady-state settings as one object, read by both routes."""

import ast
import dataclasses
import inspect
from pathlib import Path

import numpy as np
import pytest

from numerics import SteadyOptions, atlas, attractor_census, steady_states, sweep
from numerics.steady import options as options_module
from numerics.steady.sweep_compiled import supported
from perturb import PAPER

ENGINE_FIELDS = [f.name for f in dataclasses.fields(SteadyOptions)
                 if f.name not in options_module.ACCURACY_FIELDS]
SOURCES = Path(options_module.__file__).parents[1]


@pytest.mark.parametrize(("field", "bad"), [
    ("steps_per_period", 2), ("steps_per_period", "fine"), ("tol", 0.0), ("app_rtol", -1.0),
    ("max_periods", 0), ("method", "shoot"), ("refinements", 9), ("newton_iterations", 0),
    ("reach_continuation", 0.0), ("reach_polish", float("nan")), ("distinct_lag", -1.0),
    ("verify_periods", 1.5), ("verify_first", 0), ("verify_shrink", 1.5),
    ("verify_linear", 0.0), ("early_shrink", 2.0), ("sharpen_slack", 0.0),
    ("unestimated_slack", -0.1), ("resolved_omega_dt", 0.0),
    ("unknown_amplification", 0.0), ("order_factor", float("inf")),
])
def test_every_field_is_checked_and_the_error_names_it(field, bad):
    with pytest.raises(ValueError, match=f"`{field}`"):
        SteadyOptions(**{field: bad})


def test_the_approach_check_cannot_decide_after_it_ends():
    with pytest.raises(ValueError, match="`verify_first` must be at most `verify_periods`"):
        SteadyOptions(verify_first=17)
    # ... nor end before one whole orbit of the longest period sought (8).
    with pytest.raises(ValueError, match="`verify_periods` must be an integer >= 8"):
        SteadyOptions(verify_periods=4, verify_first=4)


def test_the_options_round_trip_through_json():
    import json

    changed = SteadyOptions(steps_per_period=256, app_rtol=None, max_periods=500,
                            verify_first=8, reach_polish=0.02)
    assert SteadyOptions.from_dict(json.loads(json.dumps(changed.as_dict()))) == changed
    with pytest.raises(ValueError, match="unknown steady-state options \\['verify'\\]"):
        SteadyOptions.from_dict({"verify": 3})


def test_the_verbs_keyword_defaults_are_the_options_defaults():
    # One source of the defaults: each verb's accuracy keywords default to the fields'.
    for verb in (steady_states, sweep, attractor_census, atlas):
        for name, parameter in inspect.signature(verb).parameters.items():
            if name in options_module.ACCURACY_FIELDS:
                assert parameter.default == getattr(SteadyOptions, name), (verb, name)


def test_a_keyword_beside_options_is_refused_naming_it():
    with pytest.raises(ValueError, match="`steps_per_period` given beside `options`"):
        sweep([1000.0], 0.05, steps_per_period=256, options=SteadyOptions())
    # One left at its default defers to the options.
    assert steady_states([1000.0], 0.1, tol=1e-6,
                         options=SteadyOptions(tol=1e-8)).settings["tol"] == 1e-8
    with pytest.raises(TypeError, match="`options` must be a SteadyOptions"):
        steady_states([1000.0], 0.1, options={"tol": 1e-6})


def test_options_give_what_the_keywords_give():
    grid = [1300.0, 1400.0, 1500.0]
    by_keywords = sweep(grid, 0.05, steps_per_period=256, tol=1e-7, engine="python")
    by_options = sweep(grid, 0.05, engine="python",
                       options=SteadyOptions(steps_per_period=256, tol=1e-7))
    assert by_keywords.settings == by_options.settings
    for a, b in zip(by_keywords.runs, by_options.runs, strict=True):
        np.testing.assert_array_equal(a.app_m, b.app_m)


def test_the_engine_decisions_change_the_python_route_and_are_recorded():
    # Newton may not move a continued guess at all: every continued lane marches.
    f = np.array([1000.0, 1010.0])
    first = steady_states(f[:1], 0.05 * PAPER.Q_n)
    tight = SteadyOptions(reach_continuation=1e-12)

    def continued(options):
        return steady_states(f[1:], 0.05 * PAPER.Q_n, y_init_m=first.y_start_m,
                             v_init_m_s=first.v_start_m_s, app_guess_m=first.app_m,
                             options=options)

    assert continued(SteadyOptions()).method.tolist() == ["newton"]
    held = continued(tight)
    assert held.method.tolist() == ["march+newton"]
    assert held.settings["steady_options"] == {"reach_continuation": 1e-12}
    assert "steady_options" not in first.settings


def test_the_compiled_sweep_takes_the_default_engine_only():
    assert supported(SteadyOptions(steps_per_period=64, tol=1e-8, refinements=0))
    assert not supported(SteadyOptions(verify_first=16))
    assert not supported(SteadyOptions(), keep_orbits=True)
    # Asked for, the compiled route passes other decisions to the Python route.
    run = sweep([1000.0], 0.05, engine="compiled", options=SteadyOptions(verify_first=16))
    assert run.settings["steady_options"] == {"verify_first": 16} and run.runs[0].settled.all()


def _attributes_read(path: Path) -> set[str]:
    return {node.attr for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, ast.Attribute)}


def test_every_engine_decision_is_read_by_both_routes():
    # The Python route reads each field off the options; the compiled sweep freezes the
    # default of each into its machine code, from the same object.
    python = _attributes_read(SOURCES / "steady" / "shooting.py")
    template = _attributes_read(SOURCES / "kernels" / "sweep_template.py")
    for name in ENGINE_FIELDS:
        assert name in python, name
        assert name in template, name
