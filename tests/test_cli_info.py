"""`python -m numerics info` and `python -m paper_checks`."""

import json
import subprocess
import sys

import pytest

KEYS = {"y0_m", "f_n0_hz", "omega0_rad_s", "Q_n", "c_per_s", "h_per_m_s2", "damping_ratio"}


def test_info_prints_and_writes_the_model(tmp_path, paper_figures, weight):
    target = tmp_path / "info.json"
    done = subprocess.run([sys.executable, "-m", "numerics", "info", "--json", str(target)],
                          check=True, capture_output=True, text=True)
    info = json.loads(target.read_text())
    assert set(info) == KEYS
    assert info == pytest.approx(paper_figures, rel=1e-15)
    assert info["Q_n"] == pytest.approx(weight)
    assert info["damping_ratio"] == pytest.approx(info["c_per_s"] / info["omega0_rad_s"])
    for key in KEYS:
        assert key in done.stdout


def test_paper_checks_quick_writes_the_report(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "paper_checks", "--quick", "--out", str(tmp_path)],
        capture_output=True, text=True)
    report = json.loads((tmp_path / "report.json").read_text())
    assert len(report["claims"]) == 11 and all(
        {"id", "statement", "passed", "measured"} <= set(c) for c in report["claims"])
    failed = [c["id"] for c in report["claims"] if not c["passed"]]
    assert not failed and done.returncode == 0, (failed, done.stdout)
    text = (tmp_path / "report.md").read_text()
    for figure in report["figures"].values():
        assert (tmp_path / figure).stat().st_size > 10_000 and f"]({figure})" in text
