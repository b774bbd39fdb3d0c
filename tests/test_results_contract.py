"""Every public result class keeps the contract of ``common.Result`` (issue 9, item 2).

For a small instance of each top-level result: it carries its model (parameters and
effects, as data) and its settings; its repr is one short line; ``as_dict()`` is
strict JSON; and ``load`` reads the file that ``to_json`` wrote back into an object
that writes the very same JSON. The nested results are walked through their parents,
and every class registered by ``@result`` must be reached.
"""

import json
from dataclasses import fields
from functools import partial as _partial

import numpy as np
import pytest

from numerics import (
    atlas,
    attractor_census,
    compare,
    continue_in_force,
    continue_orbits,
    exact_backbone,
    fold_curves,
    hysteresis_loop,
    largest_lyapunov,
    natural_frequency_vs_height,
    series_stability,
    simulate,
    steady_states,
    sweep,
)
from numerics.scenes import parse_scene, run_scene
from perturb import PAPER, backbone_series, frequency_response
from perturb.common import GLOSSARY, RESULT_CLASSES, Result, glossary_table, load

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")
backbone_series = _partial(backbone_series, truncation="paper")

FACTORIES = {
    "Simulation": lambda: simulate([900.0, 1400.0], 0.1 * PAPER.Q_n, periods=20,
                                   record=("final", "extrema", "history")),
    "SteadyStates": lambda: steady_states([700.0, 1400.0], 0.05 * PAPER.Q_n),
    "Sweep": lambda: sweep([1300.0, 1400.0], 0.05),
    # Chaos beside period-6 and period-7 orbits: attractors and Lyapunov exponents.
    "Census": lambda: attractor_census(1200.0, 1.5, grid={"y_over_y0": (-22.0, 0.0),
                                                    "v_over_omega0_y0": (0.0, 10.3, 12.5)}),
    "Atlas": lambda: atlas(740.0, 760.0, 0.15, 0.15, grid=(2, 1), workers=1),
    "LyapunovExponents": lambda: largest_lyapunov([1000.0, 1200.0], [0.05, 1.5], 2.25e-7, 0.0,
                                                  periods=64),
    "Backbone": lambda: exact_backbone(points=5),
    "HysteresisLoop": lambda: hysteresis_loop(1600.0, 0.4, periods=20, steps_per_period=64),
    "HeightSweep": lambda: natural_frequency_vs_height(),
    "Comparison": lambda: compare((2,), 0.05, frequency_hz=np.array([700.0, 1400.0])),
    "Continuation": lambda: continue_orbits(0.05, 1350.0, 1450.0),
    "ForceContinuation": lambda: continue_in_force(1400.0, 0.04, 0.06),
    "FoldCurves": lambda: fold_curves(1300.0, 1500.0, 0.03, 0.05, seed_pa_fracs=[0.05]),
    "Response": lambda: frequency_response([800.0, 1420.0], 0.05, order=2),
    "BackboneSeries": lambda: backbone_series(4),
    "SceneRun": lambda: run_scene(parse_scene(
        'effects = "auto"\nobservables = ["app", "extrema", "spectrum", "contact_fraction"]\n'
        '[excitation]\npa_frac = 0.05\nfrequency_hz = [700.0, 1400.0]\n'
        '[study]\nkind = "sweep"\ndirection = "up"\n')),
    "SeriesStability": lambda: series_stability(frequency_response([1000.0, 1400.0], 0.05,
                                                                   order=2)),
}


@pytest.fixture(scope="module")
def instances():
    return {name: make() for name, make in FACTORIES.items()}


def _nested(value):
    """Every result object inside ``value`` (itself included)."""
    if isinstance(value, Result):
        yield value
        for f in fields(value):
            yield from _nested(getattr(value, f.name))
    elif isinstance(value, (list, tuple)):
        for item in value:
            yield from _nested(item)


@pytest.mark.parametrize("name", sorted(FACTORIES))
def test_a_result_carries_its_model_and_settings(name, instances):
    result = instances[name]
    assert type(result).__name__ == name
    assert set(result.model) >= {"parameters", "effects"}, result.model
    assert result.model["parameters"]["c_n"] == PAPER.c_n
    assert isinstance(result.settings, dict)
    # Only the backbone series, a derivation of exact rationals, has no settings.
    assert result.settings or name == "BackboneSeries"


@pytest.mark.parametrize("name", sorted(FACTORIES))
def test_every_result_inside_prints_one_short_line(name, instances):
    for part in _nested(instances[name]):
        line = repr(part)
        assert "\n" not in line and len(line) < 200 and "array(" not in line, line
        assert str(part).splitlines()[0] == part.summary()


@pytest.mark.parametrize("name", sorted(FACTORIES))
def test_json_is_strict_and_reads_back(name, instances, tmp_path):
    result = instances[name]
    text = json.dumps(result.as_dict(), allow_nan=False)  # raises on NaN or infinity
    path = tmp_path / f"{name}.json"
    result.to_json(path)
    back = load(path)
    assert type(back) is type(result)
    assert json.dumps(back.as_dict(), allow_nan=False) == text


def test_every_result_class_is_walked(instances):
    reached = {type(part).__name__ for result in instances.values() for part in _nested(result)}
    assert set(RESULT_CLASSES) <= reached, set(RESULT_CLASSES) - reached


def test_load_refuses_what_is_not_a_result(tmp_path):
    path = tmp_path / "x.json"
    path.write_text('{"kind": "Nothing"}')
    with pytest.raises(ValueError, match="not a result of this toolkit"):
        load(path)
    path.write_text("not json")
    with pytest.raises(ValueError, match="is not JSON"):
        load(path)


def test_every_field_of_every_result_is_in_the_glossary():
    names = {f.name for cls in RESULT_CLASSES.values() for f in fields(cls)}
    assert names <= set(GLOSSARY), sorted(names - set(GLOSSARY))


#: Mappings whose keys are values, not names: amplitudes and model names.
KEYED_BY_VALUE = {"parting", "models"}
#: Mappings whose keys are the fields of a settings class, documented field by field
#: there (the glossary names the mapping).
SETTINGS_OBJECTS = {"walk_options"}


def json_keys(data, found: set | None = None) -> set:
    """Every key of a result's JSON (and of its nested objects), for the glossary."""
    found = set() if found is None else found
    if isinstance(data, dict):
        for key, value in data.items():
            found.add(key)
            if key in SETTINGS_OBJECTS:
                _check_settings_object(key, value)
            elif key not in KEYED_BY_VALUE:
                json_keys(value, found)
    elif isinstance(data, list):
        for item in data:
            json_keys(item, found)
    return found


def _check_settings_object(key: str, value: dict) -> None:
    from numerics import WalkOptions

    cls = {"walk_options": WalkOptions}[key]
    assert set(value) == {f.name for f in fields(cls)}, key
    assert cls.from_dict(value).as_dict() == value  # it reads back as it was written


@pytest.mark.parametrize("name", sorted(FACTORIES))
def test_every_json_key_is_in_the_glossary(name, instances):
    # Settings and the model included: one name per quantity, in the files too.
    keys = json_keys(instances[name].as_dict())
    assert keys <= set(GLOSSARY), sorted(keys - set(GLOSSARY))


def test_every_glossary_row_has_its_four_cells(monkeypatch):
    # A | in a meaning once cut the ds_max row short in the glossary (a review found it).
    import re

    import perturb.common._glossary as glossary

    monkeypatch.setitem(glossary.GLOSSARY, "piped", ("|z| of a vector", "1", ""))
    for line in glossary_table().splitlines():
        assert len(re.split(r"(?<!\\)\|", line)) == 6, line  # 4 cells between 5 bars


def test_a_result_file_says_where_it_comes_from(tmp_path):
    # The file carries its provenance; the object's as_dict does not (the same input
    # gives the same as_dict, whenever and wherever it runs).
    import json
    from importlib import metadata

    from numerics import load, simulate

    run = simulate([1000.0], 0.1, periods=20)
    run.to_json(tmp_path / "run.json")
    written = json.loads((tmp_path / "run.json").read_text(encoding="utf-8"))
    provenance = written.pop("provenance")
    assert written == json.loads(json.dumps(run.as_dict()))
    assert provenance["version"] == metadata.version("contact-resonances")
    assert set(provenance["libraries"]) == {"numpy", "scipy", "sympy", "numba"}
    assert provenance["written_utc"].endswith("+00:00")
    commit = provenance["commit"]
    assert commit is None or len(commit.split("+")[0]) == 40
    assert load(tmp_path / "run.json").provenance == provenance
    assert "provenance" not in run.as_dict() and run.provenance is None
    # Written again, a loaded result keeps where it was computed.
    back = load(tmp_path / "run.json")
    back.provenance = provenance | {"commit": "an-older-commit"}
    back.to_json(tmp_path / "again.json")
    again = json.loads((tmp_path / "again.json").read_text(encoding="utf-8"))["provenance"]
    assert again["commit"] == "an-older-commit" and again["version"] == provenance["version"]
