"""Scenes (issue 11): a study written as data, run with only the effects it calls for."""

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from common import Status, load
from numerics import attractors, simulate, sweep
from numerics.scenes import SceneError, parse_scene, read_scene, run_scene
from numerics.scenes import _auto as auto
from numerics.scenes._studies import model_of, run_study
from perturb import EQ_2_6, FULL, PAPER, ContactModel, frequency_response

SWEEP = """
title = "two points"
[excitation]
pa_frac = [0.05]
frequency_hz = [1300.0, 1400.0]
[study]
kind = "sweep"
direction = "up"
"""


def _error(text: str) -> str:
    with pytest.raises(SceneError) as caught:
        parse_scene(text, "s.toml")
    return str(caught.value)


# --- item 4: data, never code -------------------------------------------------------------

@pytest.mark.parametrize("text, key, line", [
    ("[study]\nkind = 'sweep'\n[excitation]\npa_frac = 0.1\nfrequency_hz = [1.0]\n"
     "[model]\nmass = 2.0\n", "model.mass", 7),
    ("[study]\nkind = 'sweep'\ndirection = 'sideways'\n[excitation]\npa_frac = 0.1\n"
     "frequency_hz = [1.0]\n", "study.direction", 3),
    ("[study]\nkind = 'sweep'\n[excitation]\npa_frac = -0.1\nfrequency_hz = [1.0]\n",
     "excitation.pa_frac[0]", None),
    ("[study]\nkind = 'sweep'\n[excitation]\npa_frac = 0.1\nfrequency_hz = [2.0, 1.0]\n",
     "excitation.frequency_hz", 5),
    ("[study]\nkind = 'sweep'\n[excitation]\npa_frac = 0.1\n"
     "frequency_hz = {start = 1, stop = 2}\n", "excitation.frequency_hz.count", None),
    ("[study]\nkind = 'sweep'\n[excitation]\npa_frac = '0.1'\nfrequency_hz = [1.0]\n",
     "excitation.pa_frac[0]", None),
    ("colour = 'red'\n[study]\nkind = 'backbone'\n", "colour", 1),
    ("[study]\nkind = 'fourier'\n", "study.kind", 2),
    ("[study]\nkind = 'backbone'\norder = 1.5\n", "study.order", 3),
    ("[study]\nkind = 'backbone'\npoints = true\n", "study.points", 3),
    ("[study]\nkind = 'backbone'\nperiods = 3\n", "study.periods", 3),
    ("tolerance = 0\n[study]\nkind = 'backbone'\n", "tolerance", 1),
    ("effects = 'some'\n[study]\nkind = 'backbone'\n", "effects", 1),
    ("effects = 'auto'\n[study]\nkind = 'backbone'\n", "effects", 1),
    ("effects = 'linear'\n[study]\nkind = 'natural_frequency'\n", "effects", 1),
    ("[effects]\nspring = 'cubic'\n[study]\nkind = 'backbone'\n", "effects.spring", None),
    ("observables = ['colour']\n[study]\nkind = 'backbone'\n", "observables[0]", None),
    ("observables = ['spectrum']\n[study]\nkind = 'backbone'\n", "observables", 1),
    ("[study]\nkind = 'backbone'\n[output]\njson = '../elsewhere.json'\n", "output.json", 4),
    ("[study]\nkind = 'backbone'\n[output]\nfigures = ['census']\n", "output.figures[0]", None),
    ("[study]\nkind = 'sweep'\n", "excitation", None),
    (SWEEP.replace("[study]", "[output]\nfigures = ['spectrum']\n[study]"),
     "output.figures", None),
    ("observables = ['extrema']\n[study]\nkind = 'analytic_response'\n[excitation]\n"
     "pa_frac = 0.1\nfrequency_hz = [1.0]\n[output]\nfigures = ['app']\n",
     "output.figures", None),
    ("[model]\nm2 = 0.5\n[study]\nkind = 'backbone'\n", "model.m2", 2),
    ("effects = 'full'\n[study]\nkind = 'analytic_response'\n[excitation]\npa_frac = 0.1\n"
     "frequency_hz = [1.0]\n", "effects", 1),
])
def test_a_bad_scene_is_one_error_naming_file_key_line_and_value(text, key, line):
    message = _error(text)
    assert f"`{key}`" in message
    assert message.startswith(f"s.toml:{line}:" if line else "s.toml:")


def test_a_syntax_error_names_the_line_tomllib_gives():
    message = _error("[study]\nkind = 'sweep' 'x'\n")
    assert message.startswith("s.toml:2:") and "not valid TOML" in message


def test_a_scene_file_that_cannot_be_read_is_a_scene_error(tmp_path):
    with pytest.raises(SceneError, match="cannot be read"):
        read_scene(tmp_path / "missing.toml")
    (tmp_path / "latin.toml").write_bytes(b"title = '\xe9'\n")
    with pytest.raises(SceneError, match="cannot be read"):
        read_scene(tmp_path / "latin.toml")


#: Strings that run code if anything evaluated them: each must stay inert text.
HOSTILE = [
    "__import__('os').system('touch PWNED')",
    "exec('import os')",
    "lambda: 1",
    "sympify",
    "1e-7; import os",
    "${HOME}",
]


@pytest.mark.parametrize("payload", HOSTILE)
def test_no_string_of_a_scene_is_evaluated(payload, tmp_path, monkeypatch):
    import builtins

    import sympy

    def refuse(*args, **kwargs):
        raise AssertionError("a scene made the toolkit evaluate text")

    for name in ("eval", "exec"):
        monkeypatch.setattr(builtins, name, refuse)
    monkeypatch.setattr(sympy, "sympify", refuse)
    monkeypatch.chdir(tmp_path)
    quoted = repr(payload)
    for text in (f"[model]\nM = {quoted}\n[study]\nkind = 'backbone'\n",
                 f"[study]\nkind = 'backbone'\norder = {quoted}\n",
                 f"effects = {quoted}\n[study]\nkind = 'backbone'\n",
                 f"[study]\nkind = {quoted}\n",
                 f"observables = [{quoted}]\n[study]\nkind = 'backbone'\n",
                 f"[study]\nkind = 'sweep'\n[excitation]\npa_frac = 0.1\n"
                 f"frequency_hz = {{start = {quoted}, stop = 2, count = 2}}\n"):
        with pytest.raises(SceneError):
            parse_scene(text, "s.toml")
    assert not (tmp_path / "PWNED").exists()


def test_the_command_exits_2_with_one_line_and_no_traceback(tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text("[study]\nkind = 'sweep'\ndirection = 'sideways'\n", encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "numerics", "scene", str(scene)],
                          capture_output=True, text=True)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines() == [
        f"error: {scene}:3: `study.direction` must be one of up, down, both; got 'sideways'"]


def test_set_overrides_the_model_on_a_command_and_refuses_unknown_names():
    run = [sys.executable, "-m", "numerics", "info"]
    done = subprocess.run(run + ["--set", "M=0.4212"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    q = float(next(line.split()[1] for line in done.stdout.splitlines()
                   if line.startswith("Q_n")))
    assert q == pytest.approx(2 * PAPER.Q_n, rel=1e-6)  # twice the mass, twice the weight
    done = subprocess.run(run + ["--set", "mass=1"], capture_output=True, text=True)
    assert done.returncode == 2 and "the parameters are S, c_n, m2, h_n, l, M, g" in done.stderr


def test_set_reaches_the_analytic_response_command(tmp_path):
    from perturb import parameters_with
    from perturb.__main__ import main as perturb_main

    out = tmp_path / "r.json"
    assert perturb_main(["response", "--pa-frac", "0.05", "--set", "m2=1.5", "--set", "l=0.5",
                         "--fmin", "5000", "--fmax", "9000", "--points", "5", "--quiet",
                         "--json", str(out)]) == 0
    written = load(out)
    expected = frequency_response(np.linspace(5000.0, 9000.0, 5), 0.05,
                                  parameters=parameters_with({"m2": 1.5, "l": 0.5}))
    assert written.model["parameters"]["m2"] == 1.5
    np.testing.assert_array_equal(written.branches[0].app_m, expected.branches[0].app_m)


# --- items 1, 2: the scene runs what the API runs, and records only what is asked ----------

def test_a_sweep_scene_equals_the_api_call_bit_for_bit():
    run = run_scene(parse_scene(SWEEP))
    direct = sweep([1300.0, 1400.0], [0.05], direction="up")
    for name in ("app_m", "ymin_m", "ymax_m", "status", "y_start_m", "steps_used"):
        assert np.array_equal(getattr(run.outcomes[0].runs[0], name),
                              getattr(direct.runs[0], name)), name
    assert run.recorder == "steady states: extrema of one response period"
    assert run.outcomes[0].runs[0].orbit_y_m is None  # App only: no orbit is kept
    assert set(run.observables[0]) == {"label", "pa_frac", "direction", "frequency_hz",
                                       "status", "app_m", "ymin_m", "ymax_m", "maxima_m",
                                       "minima_m"}


def test_a_reduced_model_scene_equals_the_api_call_with_those_effects():
    text = SWEEP.replace('title = "two points"', 'effects = "eq26"\nobservables = ["app"]')
    run = run_scene(parse_scene(text))
    direct = sweep([1300.0, 1400.0], [0.05], direction="up",
                   model=ContactModel(PAPER, EQ_2_6))
    assert np.array_equal(run.outcomes[0].runs[0].app_m, direct.runs[0].app_m)
    assert run.effects == EQ_2_6.__dict__ and run.route == "reduced model"
    assert "ymin_m" not in run.observables[0]


def test_a_census_scene_with_a_model_override_equals_the_api_call():
    text = """
    observables = ["app", "phase_portrait"]
    [model]
    l = 0.5
    [excitation]
    pa_frac = 0.15
    frequency_hz = 1400.0
    [study]
    kind = "attractors"
    """
    run = run_scene(parse_scene(text))
    model = ContactModel(dataclasses.replace(PAPER, l=0.5))
    direct = attractors(1400.0, 0.15, model=model)
    assert [a.app_m for a in run.outcomes[0].attractors] == [a.app_m for a in direct.attractors]
    assert run.model["parameters"]["l"] == 0.5
    curve = run.observables[0]
    # The phase portrait is the orbit simulated again from its start: it closes on itself
    # (one period later the state repeats to the settling tolerance) and spans App.
    assert np.ptp(curve["y_m"]) == pytest.approx(curve["app_m"], rel=1e-6)
    assert abs(curve["y_m"][-1] - curve["y_m"][0]) < 1e-4 * curve["app_m"]


def test_a_time_history_scene_records_only_what_it_is_asked():
    text = """
    observables = ["app"]
    [excitation]
    pa_frac = 0.1
    frequency_hz = [900.0, 1400.0]
    [study]
    kind = "time_history"
    periods = 20
    """
    run = run_scene(parse_scene(text))
    direct = simulate([900.0, 1400.0], 0.1 * PAPER.Q_n, periods=20, steps_per_period=256,
                      record=("final", "minmax"), record_periods=4)
    assert run.outcomes[0].history_y_m is None and run.outcomes[0].extrema is None
    assert np.array_equal(run.outcomes[0].app_m, direct.app_m)
    assert "final, minmax" in run.recorder


def test_spectrum_and_contact_fraction_of_a_bouncing_orbit():
    text = """
    observables = ["app", "spectrum", "contact_fraction"]
    [excitation]
    pa_frac = 0.5
    frequency_hz = [1200.0]
    [study]
    kind = "sweep"
    direction = "up"
    """
    curve = run_scene(parse_scene(text)).observables[0]
    spectrum, lost = curve["spectrum_m"][0], curve["contact_fraction"][0]
    assert 0.05 < lost < 0.95  # the orbit bounces (Fig. 3: minima below zero at 0.5 Q)
    # The harmonics rebuild the orbit's swing: the fundamental carries most of App / 2.
    assert 0.3 * curve["app_m"][0] < spectrum[1] <= curve["app_m"][0] / 2


def test_the_analytic_response_scene_is_the_series_of_eq26():
    text = """
    [excitation]
    pa_frac = 0.05
    frequency_hz = [800.0, 1000.0]
    [study]
    kind = "analytic_response"
    order = 2
    """
    run = run_scene(parse_scene(text))
    direct = frequency_response([800.0, 1000.0], 0.05, 2, tolerance=5e-3)
    assert run.route == "series" and run.effects == EQ_2_6.__dict__
    assert np.array_equal(run.outcomes[0].branches[0].app_m, direct.branches[0].app_m)


def test_a_scene_writes_what_it_asks_into_its_folder_and_reads_back(tmp_path):
    text = SWEEP + '[output]\njson = "run.json"\nfigures = ["app", "extrema"]\n'
    run = run_scene(parse_scene(text), out=tmp_path)
    assert run.files == ["app.png", "extrema.png", "run.json"]
    back = load(tmp_path / "run.json")
    assert np.array_equal(back.outcomes[0].runs[0].app_m, run.outcomes[0].runs[0].app_m)
    assert np.array_equal(back.observables[0]["app_m"], run.observables[0]["app_m"])


# --- item 3: effects = "auto" --------------------------------------------------------------

AUTO = """
effects = "auto"
observables = ["app", "extrema"]
tolerance = 5e-3
[model]
{model}
[excitation]
pa_frac = 0.05
frequency_hz = {{start = {start}, stop = {stop}, count = {count}}}
[study]
kind = "sweep"
direction = "up"
"""


def _full_model_twin(scene):
    return run_scene(dataclasses.replace(scene, effects=FULL))


@pytest.mark.parametrize("model, start, stop, count, route, series", [
    # the paper's contact at 0.05 Q, away from the peak: the series has three responses
    # at some frequencies (the bent 1/2 superharmonic): no candidate
    ("", 300.0, 1000.0, 36, "reduced model", "not a candidate"),
    # another rough contact: one valid response of the series everywhere, and the full
    # model from its orbits agrees at every point: the series is the route
    ("m2 = 1.5\nl = 0.5", 300.0, 900.0, 31, "series", "taken"),
])
def test_auto_drops_what_does_not_matter_and_stays_within_tolerance(model, start, stop, count,
                                                                     route, series):
    scene = parse_scene(AUTO.format(model=model, start=start, stop=stop, count=count))
    run = run_scene(scene)
    full = _full_model_twin(scene).outcomes[0].runs[0]
    chosen = run.observables[0]
    assert run.route == route, run.selection_note
    assert run.effects["contact_loss"] is False  # no point comes near losing contact
    assert (full.ymin_m > 0).all()
    scale = full.app_m.max()
    assert np.max(np.abs(chosen["app_m"] - full.app_m)) / scale <= scene.tolerance
    assert np.max(np.abs(chosen["ymin_m"] - full.ymin_m)) / scale <= scene.tolerance
    verdicts = {row["effect"]: row["verdict"] for row in run.selection}
    assert verdicts["gravity preload: switched off"] == "kept"  # no preload, no contact
    verdict = next(v for e, v in verdicts.items() if "perturbation series" in e)
    assert verdict.startswith(series), verdict
    assert "effect switched off" in str(run)


def test_a_window_of_the_full_model_continues_the_sweep_it_checks():
    # The check of a chosen sweep runs the full model through windows, each continuing
    # from the scene's orbit before it; with the full model as the "chosen" one, every
    # window must give back the sweep's own points (same lanes, same seeds, same steps).
    # At 0.3 Q the up and down sweeps differ over 1000-1220 Hz (two coexisting orbits):
    # a window there seeded from any other orbit than the scene's lands on the other one.
    scene = parse_scene(AUTO.format(model="", start=1000.0, stop=1300.0, count=16)
                        .replace("pa_frac = 0.05", "pa_frac = 0.3")
                        .replace('"up"', '"both"'))
    study = run_study(scene, model_of(scene, FULL))
    runs = study.outcomes[0].runs
    windows = [(r, first) for r, run in enumerate(runs)
               for first in auto._window_starts(run, set())]
    assert any(first > 0 for _, first in windows) and any(run.jumps() for run in runs)
    for (r, first), points in zip(windows, auto._full_through(scene, study, windows)):
        swept = runs[r].take(np.arange(first, first + points.status.size))
        np.testing.assert_array_equal(points.status, swept.status)
        np.testing.assert_allclose(points.app_m, swept.app_m, rtol=1e-12)


@pytest.mark.slow
def test_auto_falls_back_where_the_full_model_jumps_a_grid_step_earlier():
    # A review found this scene 51 % off at 2882.5 Hz while reported "reduced model": the
    # full model jumps one grid step before the chosen one (Taylor-4 spring, linear
    # damping), which neither the 24-point sample nor a separate spot sweep visits.
    scene = parse_scene(AUTO.format(model="m2 = 1.8", start=2500.0, stop=3500.0, count=401)
                        .replace("pa_frac = 0.05", "pa_frac = 0.2")
                        .replace('"up"', '"both"').replace("5e-3", "0.02")
                        .replace('["app", "extrema"]', '["app"]'))
    run = run_scene(scene)
    full = _full_model_twin(scene).outcomes[0].runs
    worst = max(np.nanmax(np.abs(a.app_m - b.app_m)) / np.nanmax(b.app_m)
                for a, b in zip(run.outcomes[0].runs, full))
    assert worst <= scene.tolerance, run.selection_note
    assert run.route == "full model" and "2882.5 Hz" in run.selection_note


def test_the_series_is_the_route_where_the_full_model_confirms_it_at_every_point(tmp_path):
    # At 0.02 Q below the peaks the series has one response at every frequency, valid at
    # half the tolerance; the full model, sought from the series' orbit at every point and
    # swept through the windows, agrees: the scene is the series, and nothing is simulated
    # for it. Its App is within the tolerance of the full model's sweep at every point.
    scene = parse_scene(AUTO.format(model="", start=200.0, stop=650.0, count=19)
                        .replace("pa_frac = 0.05", "pa_frac = 0.02")
                        .replace('"up"', '"both"'))
    run = run_scene(scene, out=tmp_path)
    row = run.selection[-1]
    assert "perturbation series" in row["effect"] and row["verdict"] == "taken: the route"
    assert run.route == "series" and run.effects == EQ_2_6.__dict__
    for ours, full in zip(run.outcomes[0].runs, _full_model_twin(scene).outcomes[0].runs):
        assert set(ours.method) == {"series"} and not ours.periods_run.any()
        assert np.max(np.abs(ours.app_m - full.app_m)) / full.app_m.max() <= scene.tolerance
    run.to_json(tmp_path / "run.json")
    assert load(tmp_path / "run.json").selection[-1]["verdict"] == "taken: the route"


def test_the_series_is_not_the_route_where_the_full_model_finds_another_orbit():
    # Reviewer's case A (below): the series has one valid response at every frequency and
    # agrees with the full model on the sample, but the full model, sought from the
    # series' orbit, does not settle at 2937.7 Hz and finds a period-2 orbit near 2 f_n0.
    scene = parse_scene(AUTO.format(model="", start=2000.0, stop=4600.0, count=62)
                        .replace("pa_frac = 0.05", "pa_frac = 0.5"))
    rows = auto.select_effects(scene).rows
    assert rows[-1]["verdict"].startswith("not taken (the full model at every point")
    assert max(rows[-1]["change"].values()) <= auto.MARGIN * scene.tolerance


def test_auto_sees_an_orbit_the_sample_and_the_series_miss():
    # A review found this scene reported "series" while 0.656 of App off at 2980 Hz,
    # where the full model settles on a period-2 orbit near 2 f_n0 between the sample's
    # points, and does not settle at 2937.7 Hz: every point is now checked.
    scene = parse_scene(AUTO.format(model="", start=2000.0, stop=4600.0, count=62)
                        .replace("pa_frac = 0.05", "pa_frac = 0.5"))
    run = run_scene(scene)
    assert run.route == "full model", run.selection_note
    assert "above the tolerance" in run.selection_note
    full = _full_model_twin(scene).outcomes[0].runs[0]
    np.testing.assert_array_equal(run.outcomes[0].runs[0].app_m, full.app_m)


def test_auto_keeps_contact_loss_where_the_slider_bounces():
    scene = parse_scene(AUTO.format(model="", start=1100.0, stop=1300.0, count=9)
                        .replace("pa_frac = 0.05", "pa_frac = 0.5"))
    run = run_scene(scene)
    assert run.effects["contact_loss"] is True
    row = next(r for r in run.selection if r["effect"].startswith("contact loss"))
    assert row["verdict"] == "kept" and row["change"]["app"] > scene.tolerance


def test_effects_that_cannot_be_dropped_are_kept_and_say_why():
    # l = 0.5 is no polynomial: contact loss can go only with linear damping, and at a
    # tolerance of 1e-4 near the peak linearising the damping on top of the linear spring
    # changes the extrema by 6.5e-5 of App (measured), above half the tolerance: the
    # damping law stays.
    scene = parse_scene(AUTO.format(model="l = 0.5", start=1400.0, stop=1480.0, count=3)
                        .replace("tolerance = 5e-3", "tolerance = 1e-4"))
    run = run_scene(scene)
    verdicts = {row["effect"].split(":")[0]: row["verdict"] for row in run.selection}
    assert verdicts["power-law damping"] == "kept"
    assert verdicts["contact loss"].startswith("kept (cannot be switched off")
    # The series of Eq. 2.6 keeps the quadratic term of the spring that the linear spring
    # drops: 2.2e-5 off the full model at every point (measured), within half the
    # tolerance, so it is the route, and the reduced model does not run.
    assert run.route == "series" and run.effects == EQ_2_6.__dict__


def test_status_is_carried_into_the_observables():
    run = run_scene(parse_scene(SWEEP))
    assert (run.observables[0]["status"] == Status.SUCCESS).all()


@pytest.mark.parametrize("title", ["a lone $ sign", "mathtext $f_e$ pairs",
                                   "not mathtext $\\\\frac$ at all"])
def test_a_title_with_dollar_signs_draws(title, tmp_path):
    # The last one would make matplotlib fail: it is drawn with its "$" as they are.
    scene = parse_scene(f'title = "{title}"\n[excitation]\npa_frac = 0.05\n'
                        'frequency_hz = [800.0, 900.0]\n[study]\nkind = "analytic_response"\n'
                        '[output]\nfigures = ["app"]\n')
    assert run_scene(scene, out=tmp_path).files == ["app.png"]


def test_the_natural_frequency_study_says_it_is_the_closed_form_of_eq26():
    run = run_scene(parse_scene('[study]\nkind = "natural_frequency"\npoints = 3\n'))
    assert run.route == "closed form" and run.effects == EQ_2_6.__dict__


def test_auto_at_rest_measures_changes_in_the_models_own_length():
    # With no force App is 0 in every model: the extrema are compared relative to the
    # largest |y| (about y0), so switching the preload off is seen (it was measured in
    # metres, 1e-7, and dropped).
    scene = parse_scene(AUTO.format(model="", start=500.0, stop=1500.0, count=5)
                        .replace("pa_frac = 0.05", "pa_frac = 0.0"))
    run = run_scene(scene)
    row = next(r for r in run.selection if r["effect"].startswith("gravity"))
    assert row["verdict"] == "kept" and row["change"]["extrema"] > 0.1
