"""Shared fixtures: the paper's model and its figures."""

import numpy as np
import pytest

from perturb import PAPER, ContactModel, Eq26


@pytest.fixture(scope="session")
def paper_figures():
    return Eq26().numeric()


@pytest.fixture(scope="session")
def weight():
    return PAPER.weight_n


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture(scope="session")
def full_model():
    return ContactModel()
