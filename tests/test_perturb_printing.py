"""Printing of the series (text, LaTeX, JSON) and the command line."""

import json
import os
import subprocess
import sys
from functools import partial as _partial
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from perturb import compile_series, derive, eq26_numbers, latex_report, series_json, text_report
from perturb.__main__ import main

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
derive = _partial(derive, truncation="paper")
compile_series = _partial(compile_series, truncation="paper")

ROOT = Path(__file__).resolve().parents[1]


def run_cli(*args):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}  # this tree's code, whatever is installed
    return subprocess.run(
        [sys.executable, "-m", "perturb", *args], capture_output=True, text=True, check=False,
        env=env,
    )


def test_text_report_shows_the_papers_equations():
    text = text_report(derive(2))
    assert "u_1'' + 2*c*u_1' + omega**2*u_1 = b_1*u_0 - h*u_0**2" in text
    assert "b_1 = 0" in text
    assert "b_2 = 2*A_1_0*h + A_1_2*h*cos(2*phi_0_1 - phi_1_2)" in text


def test_latex_report_uses_paper_like_names():
    tex = latex_report(derive(2))
    assert r"\varphi_{0,1}" in tex and r"A_{1,2}" in tex
    assert tex.count(r"\begin{align*}") == tex.count(r"\end{align*}") == 5


def split_rows(tex, n):
    """The rows of order n's align block from its equation to b_n."""
    block = tex.split(rf"\paragraph{{$\varepsilon^{{{n}}}$}}")[1].split(r"\end{align*}")[0]
    rows = block.split("\\\\\n")
    end = next(i for i, row in enumerate(rows) if row.startswith(rf"b_{{{n}}} &="))
    return rows[1:end]


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_latex_split_of_the_right_side_reads_as_one_sum(n):
    # Regression: the harmonic-by-harmonic split was printed as continuation lines
    # without "=", which renders as the terms added a second time to the right side.
    series = derive(4)
    rows = split_rows(latex_report(series), n)
    assert len(rows) == len(series.harmonics(n))
    assert rows[0].startswith("&= ")  # the split is equal to the right side above it
    for row in rows[1:]:  # and each further harmonic continues that sum
        assert row.startswith(r"&\phantom{=}\quad ")
        assert row.split(r"\quad ", 1)[1][0] in "+-"
        assert "=" not in row.replace(r"\phantom{=}", "")


def test_json_expressions_read_back_and_match_the_compiled_values():
    """Evaluate each JSON amplitude/phase from the compiled lower-order values."""
    data = series_json(derive(4))
    values = eq26_numbers()
    c, h = values.c_per_s, values.h_per_m_s2
    A0, omega, Omega = 8e-8, 0.96 * values.omega0_rad_s, 0.49 * values.omega0_rad_s
    env = compile_series(4).evaluate(A0, omega, Omega, c, h)
    T1 = 1 / (omega**2 - Omega**2 + 2j * c * Omega)
    G = A0 / abs(T1)
    phi0 = np.angle(T1)
    known = {"c": c, "h": h, "omega": omega, "Omega": Omega, "G": G}
    for n in (2, 4):
        known[f"b_{n}"] = float(env[f"b_{n}"])
    for term in data["terms"]:
        n, k = term["order"], term["harmonic"]
        if k == 0:
            expected = complex(float(env[f"A_{n}_0"]))
        else:
            expected = complex(env[f"z_{n}_{k}"]) * np.exp(1j * k * phi0)
        amplitude = sp.sympify(term["amplitude"]).subs(known)
        phase = sp.sympify(term["phase"]).subs(known)
        got = complex(sp.N(amplitude * sp.exp(sp.I * phase)))
        assert abs(got - expected) <= 1e-9 * abs(expected), term["name"]
        # lower-order names for the next orders
        known[f"A_{n}_{k}"] = abs(expected) if k else expected.real
        known[f"phi_{n}_{k}"] = float(np.angle(expected))
    for n, b in data["b"].items():
        value = float(sp.sympify(b).subs(known))
        expected = 0.0 if int(n) % 2 else float(env[f"b_{n}"])
        assert abs(value - expected) <= 1e-9 * max(abs(expected), 1.0), n


def test_cli_derive_writes_json_and_latex(tmp_path):
    out_json, out_tex = tmp_path / "d.json", tmp_path / "d.tex"
    done = run_cli("derive", "--order", "4", "--json", str(out_json), "--latex", str(out_tex),
                   "--truncation", "paper")
    assert done.returncode == 0, done.stderr
    assert "-- eps^4" in done.stdout
    # Issue 10: each stage that ran is timed on its own (the derivation alone used to
    # be reported as the whole, while printing took most of the time).
    stages = done.stderr.strip().splitlines()[-1]
    assert all(f"{stage} " in stages
               for stage in ("derivation", "closed forms and text", "LaTeX", "JSON")), stages
    data = json.loads(out_json.read_text())
    assert set(data) == {"order", "b", "terms", "paper_names", "provenance"}
    assert data["order"] == 4 and set(data["b"]) == {"1", "2", "3", "4"}
    assert set(data["terms"][0]) == {"name", "order", "harmonic", "amplitude", "phase"}
    assert len(data["paper_names"]) == 34 and data["paper_names"]["A7"]
    assert out_tex.read_text().startswith("% Perturbation series")


def test_cli_backbone_json(tmp_path):
    out = tmp_path / "b.json"
    done = run_cli("backbone", "--order", "16", "--json", str(out), "--quiet",
                   "--truncation", "paper")
    assert done.returncode == 0 and done.stderr == ""
    data = json.loads(out.read_text())
    assert data["order"] == 16 and data["amplitude"] == "first-harmonic"
    assert data["coefficients"][:3] == ["1", "0", "-5/12"] and len(data["coefficients"]) == 17


def test_cli_response_json(tmp_path):
    out = tmp_path / "r.json"
    done = run_cli(
        "response",
        "--order",
        "4",
        "--pa-frac",
        "0.05",
        "--fmin",
        "250",
        "--fmax",
        "1800",
        "--points",
        "32",
        "--json",
        str(out),
        "--quiet",
    )
    assert done.returncode == 0, done.stderr
    data = json.loads(out.read_text())
    assert data["order"] == 4 and data["pa_frac"] == 0.05
    assert len(data["branches"][0]["frequency_hz"]) == 32


@pytest.mark.parametrize(
    "args, message",
    [
        (["derive", "--order", "-1"], "argument --order: must be an integer >= 0, got '-1'"),
        (["backbone", "--order", "2.5"], "argument --order: must be an integer, got '2.5'"),
        (["response", "--pa-frac", "-0.1"], "argument --pa-frac: must be a finite number >= 0"),
        (["response", "--pa-frac", "nan"], "argument --pa-frac: must be finite"),
        (["response", "--pa-frac", "0.1", "--fmin", "0"], "argument --fmin: must be a finite"),
        (["response", "--pa-frac", "0.1", "--fmin", "900", "--fmax", "800"],
         "argument --fmax: must be above --fmin"),
        (["response", "--pa-frac", "0.1", "--points", "0"],
         "argument --points: must be an integer >= 1, got '0'"),
    ],
)
def test_cli_rejects_bad_input(args, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(args)
    assert stop.value.code == 2 and message in capsys.readouterr().err


def test_cli_derive_pretty(capsys):
    assert main(["--quiet", "derive", "--order", "2", "--pretty", "--truncation", "paper"]) == 0
    out = capsys.readouterr()
    assert "b₂ = 2⋅A₁ ₀⋅h + A₁ ₂⋅h⋅cos(2⋅φ₀ ₁ - φ₁ ₂)" in out.out and out.err == ""
