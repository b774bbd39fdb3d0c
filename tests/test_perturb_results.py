"""perturb's result objects keep the toolkit's contract (perturb/common/_results.py).

Strict JSON, a round trip through ``to_json`` and ``common.load``, the model and
settings as data, a short repr; the model itself and Eq. 2.6's numbers as data;
the command line writes files that ``common.load`` reads back.
"""

import json
import os
import subprocess
import sys
import time
from dataclasses import fields
from fractions import Fraction
from functools import partial as _partial
from pathlib import Path

import numpy as np
import pytest

from perturb import (
    EQ_2_6,
    PAPER,
    BackboneSeries,
    Branch,
    ContactModel,
    ContactParameters,
    Effects,
    Eq26,
    Eq26Numbers,
    Response,
    backbone_series,
    common,
    eq26_numbers,
    frequency_response,
)
from perturb.__main__ import main

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")
backbone_series = _partial(backbone_series, truncation="paper")

ROOT = Path(__file__).resolve().parents[1]


def same(a, b):
    """Equal values, arrays equal elementwise with NaN equal to NaN."""
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype.kind == b.dtype.kind and np.array_equal(
            a, b, equal_nan=a.dtype.kind == "f")
    if isinstance(a, list) and a and isinstance(a[0], common.Result):
        return len(a) == len(b) and all(same_result(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


def same_result(a, b):
    return type(a) is type(b) and all(
        same(getattr(a, f.name), getattr(b, f.name)) for f in fields(a))


def round_trip(obj, tmp_path):
    text = json.dumps(obj.as_dict(), allow_nan=False)  # strict JSON
    assert json.loads(text)["kind"] == type(obj).__name__
    path = tmp_path / "result.json"
    obj.to_json(path)
    return common.load(path)


@pytest.fixture(scope="module")
def response_with_nan():
    # At 0.30 Q, order 3, 1300 Hz has no root of orders 4 and 5 nearby: no estimate.
    response = frequency_response(np.array([700.0, 1300.0, 1400.0]), 0.30, 3)
    assert np.isnan(response.branches[0].error_estimate).any()
    return response


@pytest.mark.parametrize("make", [
    lambda: frequency_response(np.array([800.0, 1420.0]), 0.05, 6),
    lambda: frequency_response(np.array([500.0, 1485.0]), 0.0, 2),
])
def test_response_round_trips(make, tmp_path):
    response = make()
    back = round_trip(response, tmp_path)
    assert same_result(response, back)
    assert back.branches[0].valid.dtype == bool


def test_response_round_trips_with_nan(response_with_nan, tmp_path):
    back = round_trip(response_with_nan, tmp_path)
    assert same_result(response_with_nan, back)
    assert np.isnan(back.branches[0].error_estimate[1])
    assert not back.branches[0].valid[1]  # no estimate: not valid


@pytest.mark.parametrize("order", [0, 4, 16])
def test_backbone_round_trips(order, tmp_path):
    series = backbone_series(order)
    back = round_trip(series, tmp_path)
    assert same_result(series, back)
    assert all(isinstance(q, Fraction) for q in back.coefficients)
    assert back.frequency_ratio(0.2) == series.frequency_ratio(0.2)


def test_backbone_json_keeps_the_landed_keys():
    data = backbone_series(4).as_dict()
    assert data["order"] == 4 and data["amplitude"] == "first-harmonic"
    assert data["coefficients"] == ["1", "0", "-5/12", "0", "-485/1728"]


def test_backbone_from_bad_data_names_the_key():
    data = backbone_series(2).as_dict()
    data["coefficients"] = ["1", "zero"]
    with pytest.raises(ValueError, match="`coefficients`"):
        common.from_dict(data)


@pytest.mark.parametrize("make", [
    lambda: frequency_response(np.linspace(250.0, 1800.0, 311), 0.05, 6),
    lambda: backbone_series(16),
])
def test_model_settings_and_a_short_repr(make):
    obj = make()
    assert ContactModel.from_dict(obj.model) == ContactModel(PAPER, EQ_2_6)
    assert isinstance(obj.settings, dict) and obj.elapsed_s >= 0
    text = repr(obj)
    assert "\n" not in text and len(text) < 300 and "[" not in text
    assert str(obj).startswith(obj.summary())


def test_response_settings_and_table():
    response = frequency_response(np.array([1420.0]), 0.05, 6, omega_range=(0.5, 1.3),
                                  grid_points=60, samples=128, tolerance=0.02)
    assert response.settings == {"omega_range": [0.5, 1.3], "grid_points": 60,
                                 "samples": 128, "tolerance": 0.02}
    assert response.table().splitlines()[0].startswith("  branch 0: 1 points, 1 valid")


def test_every_field_is_in_the_glossary():
    for cls in (Response, Branch, BackboneSeries, Eq26Numbers):
        missing = [f.name for f in fields(cls) if f.name not in common.GLOSSARY]
        assert not missing, (cls.__name__, missing)


def test_model_as_data():
    model = ContactModel(ContactParameters(M=0.5), Effects(spring="taylor", taylor_degree=3))
    data = json.loads(json.dumps(model.as_dict(), allow_nan=False))
    assert data["parameters"]["M"] == 0.5 and data["effects"]["taylor_degree"] == 3
    assert ContactModel.from_dict(data) == model
    assert hash(ContactModel.from_dict(data)) == hash(model)
    assert ContactModel() != model


@pytest.mark.parametrize("edit, key", [
    (lambda d: d.pop("effects"), "effects"),
    (lambda d: d["parameters"].pop("M"), "'M'"),
    (lambda d: d["parameters"].update(mass=1.0), "'mass'"),
    (lambda d: d["effects"].update(friction=True), "'friction'"),
    (lambda d: d["effects"].update(spring="cubic"), "`spring`"),
    (lambda d: d.update(parameters=[1.0]), "`parameters`"),
])
def test_model_from_bad_data_names_the_key(edit, key):
    data = ContactModel().as_dict()
    edit(data)
    with pytest.raises(ValueError, match=key):
        ContactModel.from_dict(data)


def test_eq26_numbers_are_one_object():
    numbers = eq26_numbers()
    assert numbers is eq26_numbers(PAPER) is Eq26().numbers()  # cached per parameter set
    assert list(numbers.as_dict()) == ["y0_m", "f_n0_hz", "omega0_rad_s", "Q_n", "c_per_s",
                                       "h_per_m_s2", "damping_ratio", "G_per_P_a"]
    # Against the closed forms of Section 2 and Eq. 2.6.
    p = PAPER
    y0 = (p.M * p.g / (p.S * p.c_n)) ** (1 / p.m2)
    omega0 = np.sqrt(p.S * p.c_n * p.m2 * y0 ** (p.m2 - 1) / p.M)
    assert numbers.y0_m == pytest.approx(y0, rel=1e-14)
    assert numbers.omega0_rad_s == pytest.approx(omega0, rel=1e-14)
    assert numbers.c_per_s == pytest.approx(p.S * p.h_n * y0**p.l / (2 * p.M), rel=1e-14)
    assert numbers.h_per_m_s2 == pytest.approx(
        p.S * p.c_n * p.m2 * (p.m2 - 1) * y0 ** (p.m2 - 2) / (2 * p.M), rel=1e-14)
    assert numbers.G_per_P_a == pytest.approx(1 / p.M, rel=1e-15)
    assert numbers.Q_n == p.Q_n == p.M * p.g
    with pytest.raises(ValueError, match="`parameters`"):
        eq26_numbers({"M": 1.0})


def run_cli(*args, cwd=None):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "perturb", *args], capture_output=True,
                          text=True, check=False, cwd=cwd, env=env)


@pytest.mark.parametrize("args, kind", [
    (["response", "--order", "3", "--pa-frac", "0.3", "--fmin", "700", "--fmax", "1400",
      "--points", "15"], "Response"),
    (["backbone", "--order", "8"], "BackboneSeries"),
])
def test_cli_writes_strict_json_that_loads(args, kind, tmp_path):
    out = tmp_path / "out.json"
    done = run_cli(*args, "--json", str(out), "--quiet")
    assert done.returncode == 0, done.stderr
    text = out.read_text(encoding="utf-8")
    json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in strict JSON"))
    back = common.load(out)
    assert type(back).__name__ == kind
    assert back.summary().split(",")[0] in done.stdout


def unwritable(tmp_path):
    if os.geteuid() == 0:  # root writes through permissions, but not into /proc
        return Path("/proc/out.json")
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o500)
    return folder / "out.json"


@pytest.mark.parametrize("command", [
    ["derive", "--order", "2", "--json"],
    ["derive", "--order", "2", "--latex"],
    ["backbone", "--order", "2", "--json"],
    ["response", "--pa-frac", "0.1", "--json"],
])
@pytest.mark.parametrize("where", ["folder", "missing parent", "unwritable"])
def test_cli_checks_output_paths_before_any_work(command, where, tmp_path, capsys):
    path = {"folder": lambda: tmp_path,
            "missing parent": lambda: tmp_path / "no" / "out.json",
            "unwritable": lambda: unwritable(tmp_path)}[where]()
    start = time.perf_counter()
    with pytest.raises(SystemExit) as stop:
        main([*command, str(path)])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert f"argument {command[-1]}" in err and "Traceback" not in err
    assert time.perf_counter() - start < 2
