"""Scenes (issue 11): a study written as data, run with only the effects it calls for."""

import dataclasses
import subprocess
import sys
from functools import partial as _partial

import numpy as np
import pytest

from numerics import attractor_census, simulate, sweep
from numerics.scenes import SceneError, parse_scene, read_scene, run_scene
from numerics.scenes import auto as auto
from numerics.scenes.studies import model_of, run_study
from numerics.steady.census import DEFAULT_GRID
from perturb import (
    EQ_2_6,
    FULL,
    PAPER,
    ContactModel,
    eq26_numbers,
    frequency_response,
    parameters_with,
)
from perturb.common import Status, load

from .test_results_contract import json_keys

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")

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
    ("effects = 'full'\n[study]\nkind = 'analytic_response'\ntruncation = 'paper'\n"
     "[excitation]\npa_frac = 0.1\nfrequency_hz = [1.0]\n", "effects", 1),
    ("effects = 'linear'\n[study]\nkind = 'analytic_response'\n[excitation]\npa_frac = 0.1\n"
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
                         "--json", str(out), "--truncation", "paper"]) == 0
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
    direct = attractor_census(1400.0, 0.15, model=model)
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
    truncation = "paper"
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
    # the paper's contact at 0.05 Q, away from the peak: the series has a second (invalid)
    # root over 883-895 Hz (measured), at 888 Hz of this grid: no candidate, and the
    # reduced model runs
    ("", 300.0, 1000.0, 51, "reduced model", "not a candidate"),
    # the same on a grid that misses those: one valid response of the series everywhere,
    # and the full model, stepping from its orbits, agrees (1.3e-5 of App, measured)
    ("", 300.0, 1000.0, 36, "series", "taken"),
    # another rough contact: the same
    ("m2 = 1.5\nl = 0.5", 300.0, 900.0, 31, "series", "taken"),
])
def test_auto_drops_what_does_not_matter_and_stays_within_tolerance(model, start, stop, count,
                                                                     route, series):
    scene = parse_scene(AUTO.format(model=model, start=start, stop=stop, count=count))
    run = run_scene(scene)
    full = _full_model_twin(scene).outcomes[0].runs[0]
    chosen = run.observables[0]
    assert run.route == route, run.selection_note
    verdicts = {row["effect"]: row["verdict"] for row in run.selection}
    assert verdicts["contact loss: switched off"] == "dropped"  # no point nears losing contact
    assert run.effects["contact_loss"] is (route == "series")  # the series stands for FULL
    assert (full.ymin_m > 0).all()
    scale = full.app_m.max()
    assert np.max(np.abs(chosen["app_m"] - full.app_m)) / scale <= scene.tolerance
    assert np.max(np.abs(chosen["ymin_m"] - full.ymin_m)) / scale <= scene.tolerance
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
    for (r, first), points in zip(windows, auto._full_through(scene, study, windows,
                                                            auto._window_length(runs[0]))):
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
    # half the tolerance; the full model, stepping from the series' orbit before every
    # point and swept through the windows, agrees: the scene is the series, and nothing is simulated
    # for it. Its App is within the tolerance of the full model's sweep at every point.
    scene = parse_scene(AUTO.format(model="", start=200.0, stop=650.0, count=19)
                        .replace("pa_frac = 0.05", "pa_frac = 0.02")
                        .replace('"up"', '"both"'))
    run = run_scene(scene, out=tmp_path)
    row = run.selection[-1]
    assert "perturbation series" in row["effect"] and row["verdict"] == "taken: the route"
    assert run.route == "series" and run.effects == FULL.__dict__
    for ours, full in zip(run.outcomes[0].runs, _full_model_twin(scene).outcomes[0].runs):
        assert set(ours.method) == {"series"} and not ours.periods_run.any()
        assert np.max(np.abs(ours.app_m - full.app_m)) / full.app_m.max() <= scene.tolerance
    run.to_json(tmp_path / "run.json")
    assert load(tmp_path / "run.json").selection[-1]["verdict"] == "taken: the route"


def test_the_series_is_not_the_route_where_the_full_model_finds_another_orbit():
    # The consistent series has one valid response at every frequency and agrees with the
    # full model on the sample (2.4e-7 of App, measured), but the full model, stepping
    # from the series' orbit at 2895.1 Hz as its sweep does, does not settle at 2937.7 Hz,
    # and its sweep goes on to a period-2 orbit near 2 f_n0 (0.66 of App off at
    # 2980.3 Hz). Sought from the series' own orbit at each point instead, the full model
    # settles on it everywhere: only the step finds where the paths part.
    scene = parse_scene(AUTO.format(model="", start=2000.0, stop=4600.0, count=62)
                        .replace("pa_frac = 0.05", "pa_frac = 0.5"))
    rows = auto.select_effects(scene).rows
    assert rows[-1]["verdict"].startswith("not taken (the full model through every step")
    assert "largest change at 2937.7 Hz" in rows[-1]["verdict"]
    # Sought from the series' own orbit at each point instead, the full model settles
    # on it everywhere, within the tolerance (measured 2.4e-7 of App): that check alone
    # took this series as the route.
    from numerics.scenes.series_route import series_study
    from numerics.steady.orbits import Orbits
    from numerics.steady.shooting import steady_states

    study, _, _ = series_study(scene, scene.frequency_hz, auto.MARGIN * scene.tolerance)
    points = Orbits.stack(study.outcomes[0].runs)
    found = steady_states(points.frequency_hz, points.p_a_n, y_init_m=points.y_start_m,
                          v_init_m_s=points.v_start_m_s, period_guess=points.period,
                          app_guess_m=points.app_m, **auto._accuracy(study))
    assert found.settled.all() and (found.period == 1).all()
    assert np.max(np.abs(found.app_m - points.app_m)) / points.app_m.max() < 1e-5
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
    # The consistent series keeps every Taylor term of both laws to its order: 2.2e-10 of
    # App off the full model at every step (measured; Eq. 2.6's series, which drops the
    # damper's u u' term and the spring's cubic, was 2.2e-5 off), within half the
    # tolerance, so it is the route, and the reduced model does not run.
    assert run.route == "series" and run.effects == FULL.__dict__
    change = run.selection[-1]["change"]
    assert max(change.values()) < 1e-8, change


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


# --- issue 13, item 7: continuation, fold curves and the atlas are studies of a scene -------

CONTINUATION = """
[excitation]
pa_frac = 0.05
frequency_hz = [1300.0, 1600.0]
[study]
kind = "continuation"
"""
FOLDS = """
[excitation]
pa_frac = [0.03, 0.05]
frequency_hz = [1300.0, 1500.0]
[study]
kind = "folds"
"""
ATLAS = """
[excitation]
pa_frac = {start = 0.05, stop = 0.5, count = 2}
frequency_hz = {start = 480.0, stop = 500.0, count = 3}
[study]
kind = "atlas"
workers = 1
y_over_y0 = [-4.0, 1.0]
v_over_omega0_y0 = [0.0]
"""


def _with(text: str, study: str = "", excitation: str = "", top: str = "") -> str:
    """``text`` with lines added to its [study] and its [excitation], and at its top."""
    text = text.replace("[study]\n", f"[study]\n{study}", 1)
    return top + text.replace("[excitation]\n", f"[excitation]\n{excitation}", 1)


def _without(text: str, key: str) -> str:
    return "\n".join(line for line in text.splitlines() if not line.startswith(f"{key} ="))


def _line(text: str, start: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(start))


@pytest.mark.parametrize("text, key, start", [
    # unknown options and bad values of the walk's settings, at their lines
    (_with(CONTINUATION, "steps = 512\n"), "study.steps", "steps ="),
    (_with(CONTINUATION, "ds_max = 0\n"), "study.ds_max", "ds_max ="),
    (_with(CONTINUATION, "max_angle = 'wide'\n"), "study.max_angle", "max_angle ="),
    (_with(CONTINUATION, "max_points = 1\n"), "study.max_points", "max_points ="),
    (_with(CONTINUATION, "steps_per_period = 3\n"), "study.steps_per_period",
     "steps_per_period ="),
    # the period is checked by continue_orbits' own check (PERIODS_TRIED)
    (_with(CONTINUATION, "period = 9\n"), "study.period", "period ="),
    (_with(CONTINUATION, "continued_in = 'f_e'\n"), "study.continued_in", "continued_in ="),
    # the band is the excitation's two frequencies, within the model's reach
    (CONTINUATION.replace("[1300.0, 1600.0]", "[1300.0]"), "excitation.frequency_hz",
     "frequency_hz ="),
    (CONTINUATION.replace("[1300.0, 1600.0]", "[1300.0, 1400.0, 1600.0]"),
     "excitation.frequency_hz", "frequency_hz ="),
    (CONTINUATION.replace("[1300.0, 1600.0]", "[0.01, 1600.0]"), "excitation.frequency_hz",
     "frequency_hz ="),
    (CONTINUATION.replace("pa_frac = 0.05", "pa_frac = 0.0"), "excitation.pa_frac[0]",
     "pa_frac ="),
    # in P_a: the range of pa_frac, no branch switching, no figure against f_e
    (_with(CONTINUATION, "continued_in = 'pa_frac'\n"), "excitation.pa_frac", "pa_frac ="),
    (_with(CONTINUATION.replace("0.05", "[0.08, 0.02]"), "continued_in = 'pa_frac'\n"),
     "excitation.pa_frac", "pa_frac ="),
    (_with(CONTINUATION.replace("0.05", "[0.02, 0.08]"),
           "continued_in = 'pa_frac'\nswitch_branches = true\n"), "study.switch_branches",
     "switch_branches ="),
    (_with(CONTINUATION.replace("0.05", "[0.02, 0.08]"), "continued_in = 'pa_frac'\n")
     + "[output]\nfigures = ['continuation']\n", "output.figures", "figures ="),
    # what no continuation gives
    (_with(CONTINUATION, top="effects = 'auto'\n"), "effects", "effects ="),
    (_with(CONTINUATION, top="observables = ['app']\n"), "observables", "observables ="),
    (CONTINUATION + "[output]\nfigures = ['census']\n", "output.figures[0]", "figures ="),
    (_with(CONTINUATION, top="effects = 'cubic'\n"), "effects", "effects ="),
    (_without(CONTINUATION, "pa_frac"), "excitation.pa_frac", None),  # missing: no line
    # fold curves: a box with its low P_a above 0, seeds inside it
    (FOLDS.replace("[0.03, 0.05]", "[0.0, 0.05]"), "excitation.pa_frac", "pa_frac ="),
    (FOLDS.replace("[0.03, 0.05]", "0.05"), "excitation.pa_frac", "pa_frac ="),
    (_with(FOLDS, "seed_pa_fracs = [0.5]\n"), "study.seed_pa_fracs", "seed_pa_fracs ="),
    (_with(FOLDS, "seed_pa_fracs = 0.04\n"), "study.seed_pa_fracs", "seed_pa_fracs ="),
    (_with(FOLDS, "seed_pa_fracs = [0.04, 'x']\n"), "study.seed_pa_fracs[1]",
     "seed_pa_fracs ="),
    (_with(FOLDS, "period = 2\n"), "study.period", "period ="),
    # the atlas: evenly spaced axes, its options' ranges, its bound on the work
    (ATLAS.replace("{start = 480.0, stop = 500.0, count = 3}", "[480.0, 490.0, 520.0]"),
     "excitation.frequency_hz", "frequency_hz ="),
    (ATLAS.replace("{start = 0.05, stop = 0.5, count = 2}", "[0.5, 0.05]"),
     "excitation.pa_frac", "pa_frac ="),
    (ATLAS.replace("stop = 0.5, count = 2", "stop = 0.01, count = 2"),
     "excitation.pa_frac.stop", None),  # in an inline table: no line
    (ATLAS.replace("workers = 1", "workers = 0"), "study.workers", "workers ="),
    (ATLAS.replace("workers = 1", "workers = 1.5"), "study.workers", "workers ="),
    (_with(ATLAS, "tol = 0\n"), "study.tol", "tol ="),
    (_with(ATLAS, "steps_per_period = 'fine'\n"), "study.steps_per_period",
     "steps_per_period ="),
    (ATLAS.replace("[-4.0, 1.0]", "[]"), "study.y_over_y0", "y_over_y0 ="),
    (ATLAS.replace("[0.0]", "[0.0, inf]"), "study.v_over_omega0_y0[1]", "v_over_omega0_y0 ="),
    (ATLAS.replace("[-4.0, 1.0]", "[" + ", ".join(["1.0"] * 10_001) + "]"),
     "study.y_over_y0", "y_over_y0 ="),
    (ATLAS.replace("count = 3", "count = 100000").replace("count = 2", "count = 100"),
     "excitation", "[excitation]"),
    (_with(ATLAS, "overlay_folds = true\n").replace("count = 2", "count = 1")
     .replace("stop = 0.5", "stop = 0.05"), "study.overlay_folds", "overlay_folds ="),
    (_with(ATLAS, "scheduler = 'tcp://host:8786'\n"), "study.scheduler", "scheduler ="),
])
def test_a_bad_orbit_study_is_one_error_naming_key_and_line(text, key, start):
    message = _error(text)
    where = "s.toml" if start is None else f"s.toml:{_line(text, start)}"
    assert message.startswith(f"{where}: `{key}` "), message


def test_the_errors_of_an_orbit_study_say_what_is_wanted():
    assert "two increasing values [low, high], got [1300.0]" in _error(
        CONTINUATION.replace("[1300.0, 1600.0]", "[1300.0]"))
    assert "must be one of (1, 2, 3, 4, 5, 6, 7, 8), got 9" in _error(
        _with(CONTINUATION, "period = 9\n"))
    assert "its options are continued_in, period, steps_per_period, ds_max" in _error(
        _with(CONTINUATION, "steps = 512\n"))
    # The band follows the model's f_n0 (1e-4 to 100 f_n0): at 0.9e-4 f_n0 of a ten times
    # stiffer contact, a band the paper's model takes is refused.
    stiffer = eq26_numbers(parameters_with({"c_n": 10 * PAPER.c_n})).f_n0_hz
    text = CONTINUATION.replace("[1300.0, 1600.0]", f"[{0.9e-4 * stiffer}, 1600.0]")
    assert parse_scene(text).frequency_hz[0] > 1e-4 * eq26_numbers(PAPER).f_n0_hz
    message = _error(f"[model]\nc_n = {10 * PAPER.c_n}\n" + text)
    assert f"must lie within {1e-4 * stiffer:.3g}-{100 * stiffer:.3g} Hz" in message
    assert "evenly spaced and increasing" in _error(
        ATLAS.replace("{start = 480.0, stop = 500.0, count = 3}", "[480.0, 490.0, 520.0]"))


def test_orbit_studies_fill_in_the_apis_defaults():
    from numerics.continuation.folds import DEFAULTS as FOLD_DEFAULTS
    from numerics.continuation.walk import DEFAULTS as CONTINUATION_DEFAULTS
    from numerics.steady.shooting import DEFAULTS as STEADY_DEFAULTS

    continuation = parse_scene(CONTINUATION).options
    assert continuation == {"continued_in": "frequency_hz", "period": 1,
                            "switch_branches": False} | CONTINUATION_DEFAULTS
    folds = parse_scene(FOLDS).options
    assert folds == {"seed_pa_fracs": None} | FOLD_DEFAULTS
    atlas_options = parse_scene(ATLAS.replace("workers = 1\n", "")
                                .replace("y_over_y0 = [-4.0, 1.0]\n", "")).options
    assert atlas_options["workers"] is None  # every processor, as atlas() by default
    assert atlas_options["tol"] == STEADY_DEFAULTS["tol"]
    assert atlas_options["y_over_y0"] == DEFAULT_GRID["y_over_y0"]


def test_a_continuation_scene_equals_the_api_call_with_its_model():
    from numerics import continue_orbits

    run = run_scene(parse_scene(_with(CONTINUATION, top='effects = "eq26"\n')))
    direct = continue_orbits(0.05, 1300.0, 1600.0, model=ContactModel(PAPER, EQ_2_6))
    (got,), (want,) = run.outcomes[0].branches, direct.branches
    for name in ("frequency_hz", "app_m", "stable", "multipliers"):
        assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert [b.frequency_hz for b in run.outcomes[0].bifurcations] == [
        b.frequency_hz for b in direct.bifurcations]
    assert run.effects == EQ_2_6.__dict__ and run.route == "reduced model"


def test_a_continuation_in_force_scene_is_one_per_frequency():
    from numerics import continue_in_force

    text = _with(CONTINUATION.replace("0.05", "[0.02, 0.08]")
                 .replace("[1300.0, 1600.0]", "[1400.0, 1450.0]"), "continued_in = 'pa_frac'\n")
    run = run_scene(parse_scene(text))
    assert [o.frequency_hz for o in run.outcomes] == [1400.0, 1450.0]
    direct = continue_in_force(1400.0, 0.02, 0.08)
    assert np.array_equal(run.outcomes[0].branches[0].pa_frac, direct.branches[0].pa_frac)
    # At 1400 Hz the force-response curve folds twice (continue_in_force's docstring).
    assert [b.kind for b in run.outcomes[0].bifurcations] == ["fold", "fold"]


def test_a_folds_scene_equals_the_api_call():
    from numerics import fold_curves

    run = run_scene(parse_scene(_with(FOLDS, "seed_pa_fracs = [0.05, 0.04]\nmax_points = 300\n")))
    direct = fold_curves(1300.0, 1500.0, 0.03, 0.05, seed_pa_fracs=[0.05, 0.04],
                         max_points=300)
    assert [(c.frequency_hz, c.pa_frac) for c in run.outcomes[0].cusps] == [
        (c.frequency_hz, c.pa_frac) for c in direct.cusps]
    assert np.array_equal(run.outcomes[0].fold_curves[0].pa_frac,
                          direct.fold_curves[0].pa_frac)


def test_an_atlas_scene_with_fold_curves_over_it_draws_both(tmp_path):
    from numerics import atlas

    text = ATLAS.replace("0.05, stop = 0.5", "0.03, stop = 0.05").replace(
        "480.0, stop = 500.0", "1300.0, stop = 1500.0")
    text = _with(text, "overlay_folds = true\n") + "[output]\nfigures = ['atlas']\n"
    run = run_scene(parse_scene(text), out=tmp_path)
    found, folds = run.outcomes
    direct = atlas(1300.0, 1500.0, 0.03, 0.05, grid=(3, 2), workers=1,
                   initial_states={"y_over_y0": (-4.0, 1.0), "v_over_omega0_y0": (0.0,)})
    assert np.array_equal(found.attractor_count, direct.attractor_count)
    assert [c.resonance for c in folds.cusps] == [1]  # the primary's cusp, at 0.033 Q
    assert run.files == ["atlas.png"] and (tmp_path / "atlas.png").stat().st_size > 1000


@pytest.mark.parametrize("text, command", [
    (CONTINUATION, ["continue", "--pa-frac", "0.05", "--fmin", "1300", "--fmax", "1600"]),
    (FOLDS, ["folds", "--fmin", "1300", "--fmax", "1500", "--pa-min", "0.03",
             "--pa-max", "0.05"]),
    (ATLAS, ["atlas", "--fmin", "480", "--fmax", "500", "--pa-min", "0.05", "--pa-max", "0.5",
             "--grid", "3", "2", "--workers", "1"]),
], ids=["continue", "folds", "atlas"])
def test_an_orbit_scene_writes_the_json_its_command_writes(text, command, tmp_path):
    """The scene's JSON holds, as its outcome, what the command's --json writes: one
    layout (the result's own ``as_dict``), not a second one."""
    import json

    if command[0] == "atlas":  # the command's census takes the default initial states
        text = text.replace("y_over_y0 = [-4.0, 1.0]\nv_over_omega0_y0 = [0.0]\n", "")
    run_scene(parse_scene(text + '[output]\njson = "scene.json"\n'), out=tmp_path)
    subprocess.run([sys.executable, "-m", "numerics", *command, "--quiet", "--json",
                    str(tmp_path / "command.json")], check=True, capture_output=True)
    scene = json.loads((tmp_path / "scene.json").read_text())["outcomes"][0]
    written = json.loads((tmp_path / "command.json").read_text())
    for data in (scene, written):  # the times differ from run to run
        data.pop("elapsed_s")
        data.pop("cell_time_s", None)
    assert written.pop("provenance")["version"]  # the file's own: where it comes from
    assert scene == written


def test_every_json_key_of_an_orbit_scene_is_in_the_glossary():
    from perturb.common import GLOSSARY

    keys = set()
    for text in (_with(CONTINUATION, "switch_branches = true\n"), FOLDS,
                 _with(ATLAS, "overlay_folds = false\n")):
        keys |= json_keys(run_scene(parse_scene(text)).as_dict())
    assert keys <= set(GLOSSARY), sorted(keys - set(GLOSSARY))


