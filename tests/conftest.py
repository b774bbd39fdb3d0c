"""Shared fixtures: the paper's model and its figures."""

import numpy as np
import pytest

from perturb import PAPER, ContactModel, eq26_numbers


@pytest.fixture(scope="session")
def paper_figures():
    return eq26_numbers().as_dict()


@pytest.fixture(scope="session")
def weight():
    return PAPER.Q_n


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture(scope="session")
def full_model():
    return ContactModel()
