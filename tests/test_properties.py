"""Property tests (issue 10): over wide ranges of the excitation and of every parameter,
every result is finite or carries a failure status with a message; never NaN in a
settled result, never a hang.

The excitation is varied on the paper's model (its kernels are compiled once); the
contact's parameters are varied in a slow test, since each parameter set compiles
its own kernels (about 5 s each).
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from numerics import Status, steady_states
from perturb import PAPER, ContactModel, ContactParameters

#: Forces from none to five times the weight; frequencies from 1 Hz to 1 MHz.
FORCE = st.floats(0.0, 5.0)
FREQUENCY = st.floats(0.0, 6.0).map(lambda decade: 10.0**decade)


def _sound(found) -> None:
    settled = found.status == Status.SUCCESS
    assert np.all(np.isfinite(found.app_m[settled])), found
    assert np.all(np.isfinite(found.ymin_m[settled]) & np.isfinite(found.ymax_m[settled]))
    for status, message in zip(found.status, found.message):
        assert (status == Status.SUCCESS) == (message == ""), (status, message)
    assert set(found.status.tolist()) <= {int(s) for s in Status}


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pa_frac=FORCE, frequency_hz=FREQUENCY)
def test_every_excitation_ends_sound(pa_frac, frequency_hz):
    _sound(steady_states(frequency_hz, pa_frac * PAPER.Q_n, refinements=1))


@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pa_frac=FORCE, frequency_hz=FREQUENCY, m2=st.floats(1.0, 3.0), l=st.floats(0.0, 2.0),
       damping=st.floats(-3.0, 1.0).map(lambda decade: 10.0**decade))
def test_every_contact_ends_sound(pa_frac, frequency_hz, m2, l, damping):
    # `damping` scales c of Eq. 2.6, 2c = S h_n y0^l / M: h_n is chosen for this m2 and l
    # from y0 = (M g / (S c_n))^(1/m2) (Eq. 2.1 at rest), so that l alone does not
    # change the damping by orders of magnitude.
    p = PAPER
    y0, y0_paper = (p.Q_n / (p.S * p.c_n)) ** (1 / m2), (p.Q_n / (p.S * p.c_n)) ** (1 / p.m2)
    h_n = p.h_n * damping * y0_paper**p.l / y0**l
    model = ContactModel(ContactParameters(m2=m2, l=l, h_n=h_n))
    _sound(steady_states(frequency_hz, pa_frac * PAPER.Q_n, model=model, refinements=1))
