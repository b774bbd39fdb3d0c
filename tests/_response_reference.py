"""The numpy route of the analytic response, the reference of the compiled one (issue 12).

``perturb/response/numpy_route.py`` is ``perturb.response.frequency`` as it was before the
frequency equation was compiled (commit f60ea91); ``reference_response`` runs
``frequency_response`` on it. ``tests/test_perturb_response.py`` holds the
compiled route to it (same branches, roots, validity), and
``tests/benchmarks/bench_perturb.py`` times the two in the same run.
"""

from __future__ import annotations

from functools import partial as _partial

from perturb import frequency_response
from perturb.response.frequency import Response

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
frequency_response = _partial(frequency_response, truncation="paper")


def reference_response(frequency_hz, pa_frac: float, order: int = 6, **options) -> Response:
    """``frequency_response`` by the numpy route."""
    return frequency_response(frequency_hz, pa_frac, order, engine="numpy", **options)
