"""The series of any contact: how often `valid` is wrong, and what the consistent series costs.

- **False "valid" flags**, on a grid of contacts and amplitudes that no test uses:
  m2 = 1.25, 1.75, 2.25, 2.75; l = 0.25, 0.75 (y0 and c the paper's: c_n and h_n
  rescaled); P_a = 0.02 and 0.05 Q; nine frequencies from 0.8 to 1.1 f_n0. Each valid
  root of the order-8 series on a stable-type branch (the first and, on a bent peak,
  the last: the middle one is the unstable orbit, which RK4 does not settle on) is held
  against the RK4 steady state of the full model reached from the series' own orbit;
  a valid root more than its tolerance (1 %) off is a false flag. Both truncations.
- **The paper's contact** at 0.05 Q on the bent primary peak: App of Eq. 2.6's series
  and of the consistent one beside RK4 of the full model (what d_1 u u' changes).
- **Cost.** A new process's first consistent response of order 8 at a new m2 (no
  series derived or compiled) beside Eq. 2.6's series of the same order from an empty
  cache (derived, lambdified); 10,000 frequencies at order 6, the consistent series'
  compiled kernels beside Eq. 2.6's, medians in turns, beside the scheme's numba kernel
  (the route of "auto" until the compiled kernels are built) and the scheme in numpy;
  and the one-time build of the compiled kernels of a contact with every k_j and d_j
  beside the paper's contact (h and d_1).
"""

from __future__ import annotations

import itertools
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from unittest import mock

import numpy as np

from numerics import steady_states
from perturb import (
    PAPER,
    ContactModel,
    ContactParameters,
    eq26_numbers,
    frequency_response,
    series_orbits,
)
from perturb.response import frequency as frequency_module

from ._timing import header, interleaved_medians, median_time, row

_REPOSITORY = Path(__file__).resolve().parents[2]
Y0 = eq26_numbers(PAPER).y0_m


def contact(m2: float, l: float) -> ContactParameters:
    """A power-law contact with the paper's y0 (c_n rescaled) and c (h_n rescaled)."""
    return ContactParameters(m2=m2, l=l, c_n=PAPER.Q_n / (PAPER.S * Y0**m2),
                             h_n=PAPER.h_n * Y0 ** (1 - l))


def _flags(truncation: str) -> tuple[int, int, float]:
    """(valid roots checked, false flags, largest error of a valid root) on the grid."""
    checked = false = 0
    worst = 0.0
    for m2, l, pa_frac in itertools.product((1.25, 1.75, 2.25, 2.75), (0.25, 0.75),
                                            (0.02, 0.05)):
        parameters = contact(m2, l)
        f_n0 = eq26_numbers(parameters).f_n0_hz
        response = frequency_response(np.linspace(0.8 * f_n0, 1.1 * f_n0, 9), pa_frac, 8,
                                      parameters=parameters, truncation=truncation)
        stable = response.branches[:1] + response.branches[2:][-1:]
        for branch in stable:
            orbit = series_orbits(branch, 8, parameters, truncation=truncation)
            found = steady_states(branch.frequency_hz, pa_frac * parameters.Q_n,
                                  model=ContactModel(parameters), y_init_m=orbit.y_start_m,
                                  v_init_m_s=orbit.v_start_m_s, app_guess_m=branch.app_m)
            kept = branch.valid & found.settled & (found.period == 1)
            error = np.abs(branch.app_m / found.app_m - 1)[kept]
            checked += int(kept.sum())
            false += int((error > 0.01).sum())
            worst = max(worst, float(error.max(initial=0.0)))
    return checked, false, worst


def bench_paper_contact() -> None:
    """What d_1 u u' changes on the paper's own contact (docs/perturb.md's table)."""
    header("the paper's contact, 0.05 Q, order 8, upper branch: App against RK4 (full model)")
    frequency = np.array([1400.0, 1420.0, 1440.0])
    for truncation in ("paper", "consistent"):
        top = frequency_response(frequency, 0.05, 8, truncation=truncation).branches[0]
        orbit = series_orbits(top, 8, PAPER, truncation=truncation)
        found = steady_states(top.frequency_hz, 0.05 * PAPER.Q_n, model=ContactModel(PAPER),
                              y_init_m=orbit.y_start_m, v_init_m_s=orbit.v_start_m_s,
                              app_guess_m=top.app_m)
        for f, app, rk4 in zip(top.frequency_hz, top.app_m, found.app_m):
            row(f"{truncation}, {f:.0f} Hz: App/App_RK4 - 1 (RK4 App [nm])", app / rk4 - 1,
                rk4 * 1e9, "", ratio=False)


def bench_flags() -> None:
    header("valid flags of order 8 against RK4 of the full model, 16 contacts x 9 f_e")
    for truncation in ("consistent", "paper"):
        checked, false, worst = _flags(truncation)
        row(f"{truncation}: valid roots checked", checked)
        row(f"{truncation}: false valid flags (> 1 % off)", false)
        row(f"{truncation}: largest |App/App_RK4 - 1| of a valid root", worst)


_FIRST = ("import time; import numpy as np; t = time.perf_counter(); "
          "from perturb import ContactParameters, frequency_response; "
          "frequency_response(np.array([1400.0]), 0.05, 8, parameters=ContactParameters("
          "m2={m2!r}), truncation={truncation!r}); print(time.perf_counter() - t)")


def _first_response(truncation: str, m2: float, cache: str) -> float:
    return _new_process_seconds(_FIRST.format(m2=m2, truncation=truncation), cache)


def _new_process_seconds(code: str, cache: str) -> float:
    """The seconds that ``code`` prints last, run in a new process with ``cache``."""
    env = os.environ | {"CONTACT_RESONANCES_CACHE": cache}
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=_REPOSITORY,
                         capture_output=True, text=True, check=True)
    return float(out.stdout.split()[-1])


def bench_cost() -> None:
    header("the consistent series: first response of a new process, and 10,000 frequencies")
    with tempfile.TemporaryDirectory() as cache:
        # Both with the model's numbers in the cache: the series is what is timed.
        _first_response("paper", 1.37, cache)
        consistent = _first_response("consistent", 1.37, cache)
    with tempfile.TemporaryDirectory() as cache:
        _first_response("consistent", 1.37, cache)  # fills the numbers, derives nothing
        for path in Path(cache).rglob("formulas_*"):
            path.unlink()
        paper = _first_response("paper", 1.37, cache)
    row("order 8, new m2, consistent, new process [s] vs Eq. 2.6's (derives)", consistent,
        paper, "s", higher_is_better=False)
    frequencies = np.linspace(250.0, 1800.0, 10_000)
    # Both compiled routes built (once per cache) before the clock.
    for truncation in ("paper", "consistent"):
        frequency_response(frequencies[:4], 0.05, 6, truncation=truncation, engine="compiled")
    ours, theirs = interleaved_medians(
        lambda: frequency_response(frequencies, 0.05, 6, engine="compiled"),
        lambda: frequency_response(frequencies, 0.05, 6, truncation="paper",
                                   engine="compiled"), repeats=3)
    row("10,000 f_e, order 6, consistent, compiled [s] vs Eq. 2.6's compiled", ours, theirs,
        "s", higher_is_better=False)
    # The route of "auto" before the compiled kernels are built: the numpy root search on
    # the scheme's numba kernel; and the scheme in numpy.
    with mock.patch.object(frequency_module, "series_kernels_built", lambda *args: False):
        kernel_route = median_time(lambda: frequency_response(frequencies, 0.05, 6),
                                   repeats=3)
    row("  the same, compiled [s] vs the scheme's kernel (auto, not built)", ours,
        kernel_route, "s", higher_is_better=False)
    numpy_route = median_time(lambda: frequency_response(frequencies, 0.05, 6,
                                                         engine="numpy"), repeats=1)
    row("  the same, compiled [s] vs the scheme in numpy (one run)", ours, numpy_route, "s",
        higher_is_better=False)
    with tempfile.TemporaryDirectory() as cache:
        build = _build_seconds(cache)
    row("  building the compiled kernels of order 6, m2 = 1.5, l = 0.5 [s] (once per "
        "cache) vs the paper's contact's", *build, "s", higher_is_better=False)


_BUILD = ("import time; import numpy as np; from perturb import ContactParameters, "
          "frequency_response; t = time.perf_counter(); "
          "frequency_response(np.array([1400.0]), 0.05, 6, parameters=ContactParameters("
          "m2={m2!r}, l={l!r}), engine='compiled'); print(time.perf_counter() - t)")


def _build_seconds(cache: str) -> tuple[float, float]:
    """A new process's first compiled consistent response of order 6 at m2 = 1.5, l = 0.5
    (every k_j and d_j) and at the paper's contact (h and d_1), in an empty cache."""
    contacts = (1.5, 0.5), (2.0, 1.0)
    every, paper = (_new_process_seconds(_BUILD.format(m2=m2, l=l), cache) for m2, l in contacts)
    return every, paper


def main() -> None:
    bench_paper_contact()
    bench_flags()
    bench_cost()


if __name__ == "__main__":
    main()
