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
