"""`python -m numerics info`."""

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
