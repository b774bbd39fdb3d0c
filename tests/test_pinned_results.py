"""The results that a change of the code's layout must not move, pinned to the bit.

A redesign that moves code between modules changes no number: the Fig. 2 + 3 job
(ten amplitudes, up and down, 311 frequencies) gives the same JSON, its time aside.
It is pinned on the Python route, which every process has; the compiled sweep is held
to that route by tests/test_sweep_compiled.py (the states and App to the bit, the
Floquet multipliers, and the error estimates through them, to a few ulp: each route
takes the eigenvalues by its own arithmetic). A change meant to move a number updates
the pin here, and says why in its commit.
"""

import hashlib
import json

import numpy as np

from numerics import sweep
from perturb import PAPER_BAND_HZ, PAPER_PANEL_FRACTIONS

#: SHA-256 of the job's ``as_dict()`` without ``elapsed_s``, keys sorted.
FIG2_FIG3_JOB = "3716aeb22010b6a7b0dae0bd6c9c46108bd6d54546251be1ee59e63c37429a6f"


def _digest(result) -> str:
    data = result.as_dict()
    data.pop("elapsed_s")
    text = json.dumps(data, sort_keys=True, allow_nan=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def test_the_fig2_fig3_job_is_pinned_to_the_bit():
    job = sweep(np.linspace(*PAPER_BAND_HZ, 311), PAPER_PANEL_FRACTIONS, engine="python")
    assert _digest(job) == FIG2_FIG3_JOB


#: SHA-256 of ``make paper``'s claims (id, verdict, the numbers measured; every float to
#: 10 significant digits, so that the two routes of the sweep, which agree to a few
#: ulp, give one digest whichever the cache holds), keys sorted.
PAPER_CLAIMS = "50d76df8b5fd7cd5f81f9ada8f8b7beacdacb512dc11cb6feebb7c73e6f1fbe9"


def _rounded(value):
    if isinstance(value, float):
        return float(f"{value:.10g}")
    if isinstance(value, dict):
        return {key: _rounded(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_rounded(item) for item in value]
    return value


def claims_digest(report: dict) -> str:
    claims = [{"id": c["id"], "passed": c["passed"], "measured": _rounded(c["measured"])}
              for c in report["claims"]]
    text = json.dumps(claims, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


def test_the_paper_claims_are_pinned(tmp_path):
    # `make paper` whole (some 15 s once the kernels are cached): its eleven claims and
    # every number they measured.
    import subprocess
    import sys

    subprocess.run([sys.executable, "-m", "paper_checks", "--out", str(tmp_path), "--quiet"],
                   check=True, capture_output=True)
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert claims_digest(report) == PAPER_CLAIMS
