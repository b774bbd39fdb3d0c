"""The generated right-hand side against a hand-written Eq. 2.4."""

import numpy as np
import pytest

from numerics.kernels import compiled_kernels
from perturb import EQ_2_6, ContactModel, ContactParameters, eq26_numbers


def eq_2_4_by_hand(p: ContactParameters, y, v, force):
    """Eq. 2.1-2.4, typed independently of perturb: gapping at y <= 0."""
    deflection = np.maximum(y, 0.0)
    in_contact = y > 0
    spring = np.where(in_contact, -p.S * p.c_n * deflection**p.m2, 0.0)
    damping = np.where(in_contact, -p.S * p.h_n * deflection**p.l * v, 0.0)
    terms = np.stack([spring, damping, np.full_like(y, p.M * p.g), force])
    return terms.sum(axis=0) / p.M, np.abs(terms).sum(axis=0) / p.M


def random_states(rng, model, n=1000):
    y0 = eq26_numbers(model.parameters).y0_m
    y = rng.uniform(-3 * y0, 4 * y0, n)
    v = rng.uniform(-1, 1, n) * 2 * np.pi * 1500 * y0 * 3
    force = rng.uniform(-1, 1, n) * model.parameters.Q_n
    return y, v, force


@pytest.mark.parametrize(
    "parameters",
    [ContactParameters(), ContactParameters(m2=1.5, l=0.5)],
    ids=["paper", "m2=1.5,l=0.5"],
)
def test_generated_rhs_equals_hand_written_eq_2_4(parameters, rng):
    model = ContactModel(parameters)
    y, v, force = random_states(rng, model)
    assert (y < 0).sum() > 100
    got = compiled_kernels(model).acceleration_batch(y, v, force)
    expected, scale = eq_2_4_by_hand(parameters, y, v, force)
    assert np.all(np.isfinite(got))
    worst = np.max(np.abs(got - expected) / scale)
    assert worst < 1e-12, f"largest relative deviation {worst:.3g}"


def test_generated_eq26_rhs_equals_hand_written_eq26(rng):
    model = ContactModel(effects=EQ_2_6)
    k = eq26_numbers()
    y, v, force = random_states(rng, model)
    u = y - eq26_numbers(model.parameters).y0_m
    terms = np.stack([-2 * k.c_per_s * v, -k.omega0_rad_s**2 * u, -k.h_per_m_s2 * u**2,
                      k.G_per_P_a * force])
    got = compiled_kernels(model).acceleration_batch(y, v, force)
    worst = np.max(np.abs(got - terms.sum(axis=0)) / np.abs(terms).sum(axis=0))
    assert worst < 1e-12, f"largest relative deviation {worst:.3g}"
