"""`python -m numerics info`: the numbers of Eq. 2.6, against their closed forms."""

import json
import math
import subprocess
import sys

import pytest

# The paper's values (Section 2), typed as it states them.
S, C_N, M2, H_N, L, M, G = 0.0009, 4.52693e16, 2.0, 3.5e11, 1.0, 0.2106, 9.81

#: The landed keys of `info --json` (keys may be added, never removed or renamed).
LANDED = {"y0_m", "f_n0_hz", "omega0_rad_s", "Q_n", "c_per_s", "h_per_m_s2", "damping_ratio"}


def closed_forms(S=S, C_N=C_N, M2=M2, H_N=H_N, L=L, M=M, G=G) -> dict[str, float]:
    """Eq. 2.6's numbers by hand: y0 = (M g / (S c_n))^(1/m2), omega0^2 = S c_n m2
    y0^(m2-1) / M, 2c = S h_n y0^l / M, eps h = S c_n m2 (m2-1) y0^(m2-2) / (2 M);
    at the paper's values unless others are given."""
    y0 = (M * G / (S * C_N)) ** (1 / M2)
    omega0 = math.sqrt(S * C_N * M2 * y0 ** (M2 - 1) / M)
    c = S * H_N * y0**L / (2 * M)
    return {
        "y0_m": y0,
        "f_n0_hz": omega0 / (2 * math.pi),
        "omega0_rad_s": omega0,
        "Q_n": M * G,
        "c_per_s": c,
        "h_per_m_s2": S * C_N * M2 * (M2 - 1) * y0 ** (M2 - 2) / (2 * M),
        "damping_ratio": c / omega0,
        "G_per_P_a": 1 / M,
    }


def test_info_prints_and_writes_the_closed_forms(tmp_path):
    target = tmp_path / "info.json"
    done = subprocess.run([sys.executable, "-m", "numerics", "info", "--json", str(target)],
                          check=True, capture_output=True, text=True)
    info = json.loads(target.read_text(encoding="utf-8"))
    assert info.pop("provenance")["libraries"]["sympy"]  # where the numbers come from
    expected = closed_forms()
    assert LANDED <= set(info) <= set(expected)
    for key, value in info.items():
        assert value == pytest.approx(expected[key], rel=1e-13), key
        assert key in done.stdout
    # The natural frequency the paper reports (Section 3, rounded to 1485 Hz).
    assert info["f_n0_hz"] == pytest.approx(1485.0, abs=1.0)
