"""perturb: the contact model as sympy expressions, and what is derived from it.

The physical model of Eq. 2.1-2.4 lives here once (``ContactModel``), with the
paper's parameter values as defaults (``PAPER``); Eq. 2.6 is derived from it
(``Eq26``).
"""

from ._effects import EQ_2_6, FULL, LINEAR, Effects
from ._eq26 import Eq26
from ._model import ContactModel
from ._parameters import (
    PAPER,
    PAPER_BAND_HZ,
    PAPER_F_N0_HZ,
    PAPER_PANEL_FRACTIONS,
    ContactParameters,
)
from . import _symbols as symbols

__all__ = [
    "ContactModel",
    "ContactParameters",
    "EQ_2_6",
    "Effects",
    "Eq26",
    "FULL",
    "LINEAR",
    "PAPER",
    "PAPER_BAND_HZ",
    "PAPER_F_N0_HZ",
    "PAPER_PANEL_FRACTIONS",
    "symbols",
]
