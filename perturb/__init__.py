"""perturb: the contact model as sympy expressions, and what is derived from it.

The physical model of Eq. 2.1-2.4 lives here once (``ContactModel``), with the
paper's parameter values as defaults (``PAPER``); Eq. 2.6 is derived from it
(``Eq26``), and its numbers at a parameter set are one object
(``Eq26Numbers``, from ``eq26_numbers``). The perturbation series of Eq. 2.6 is derived to any order
(``derive``), printed (``text_report``, ``latex_report``, ``series_json``; step by step
in the paper's names: ``derivation_text``, ``derivation_latex``),
compiled (``compile_series``) and solved for the frequency response
(``frequency_response``); ``backbone_series`` gives the free backbone exactly.
"""

from . import _series_symbols as series_symbols
from . import _symbols as symbols
from ._backbone_series import BackboneSeries, backbone_series
from ._compiled import CompiledSeries, compile_series
from ._derivation import derivation_latex, derivation_text
from ._effects import EQ_2_6, FULL, LINEAR, Effects
from ._eq26 import Eq26, Eq26Numbers, eq26_numbers
from ._lindstedt import Series, derive
from ._model import ContactModel
from ._paper_names import PAPER_DIFFERENCES, PAPER_NAMES, paper_names
from ._parameters import (
    PAPER,
    PAPER_BAND_HZ,
    PAPER_COEXISTENCE,
    PAPER_CUBE_SIDE_M,
    PAPER_F_N0_HZ,
    PAPER_HYSTERESIS_POINT,
    PAPER_PANEL_FRACTIONS,
    ContactParameters,
    parameters_with,
)
from ._printing import latex_report, series_json, text_report
from ._response import Branch, Response, frequency_response

__all__ = [
    "BackboneSeries",
    "Branch",
    "CompiledSeries",
    "ContactModel",
    "ContactParameters",
    "EQ_2_6",
    "Effects",
    "Eq26",
    "Eq26Numbers",
    "FULL",
    "LINEAR",
    "PAPER",
    "PAPER_BAND_HZ",
    "PAPER_COEXISTENCE",
    "PAPER_CUBE_SIDE_M",
    "PAPER_DIFFERENCES",
    "PAPER_F_N0_HZ",
    "PAPER_HYSTERESIS_POINT",
    "PAPER_NAMES",
    "PAPER_PANEL_FRACTIONS",
    "Response",
    "Series",
    "backbone_series",
    "compile_series",
    "derivation_latex",
    "derivation_text",
    "derive",
    "eq26_numbers",
    "frequency_response",
    "latex_report",
    "paper_names",
    "parameters_with",
    "series_json",
    "series_symbols",
    "symbols",
    "text_report",
]
