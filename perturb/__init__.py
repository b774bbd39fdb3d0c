"""perturb: the contact model as sympy expressions, and what is derived from it.

The physical model of Eq. 2.1-2.4 lives here once (``ContactModel``), with the
paper's parameter values as defaults (``PAPER``); Eq. 2.6 is derived from it
(``Eq26``), and its numbers at a parameter set are one object (``Eq26Numbers``,
from ``eq26_numbers``, kept on disk once derived). The perturbation series of
Eq. 2.6 is derived to any order (``derive``), printed (``text_report``,
``latex_report``, ``series_json``; step by step in the paper's names:
``derivation_text``, ``derivation_latex``), compiled (``compile_series``) and
solved for the frequency response (``frequency_response``, whose orbits
``series_orbits`` gives as the simulator's states); ``backbone_series``
gives the free backbone exactly.
"""

from perturb.common import lazy_names

# Light names, imported with the package: none of them imports sympy.
from ._effects import EQ_2_6, FULL, LINEAR, Effects
from ._model import ContactModel
from ._numbers import Eq26Numbers, eq26_numbers
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

# The symbolic names, imported at first use (PEP 562): sympy takes 0.3 s to import,
# and a command whose numbers and kernels are cached needs none of them.
_LAZY = {
    "series_symbols": ("._series_symbols", None),
    "symbols": ("._symbols", None),
    "BackboneSeries": ("._backbone_series", "BackboneSeries"),
    "backbone_series": ("._backbone_series", "backbone_series"),
    "CompiledSeries": ("._compiled", "CompiledSeries"),
    "compile_series": ("._formulas", "compile_series"),
    "derivation_latex": ("._derivation", "derivation_latex"),
    "derivation_text": ("._derivation", "derivation_text"),
    "Eq26": ("._eq26", "Eq26"),
    "Series": ("._lindstedt", "Series"),
    "derive": ("._lindstedt", "derive"),
    "PAPER_DIFFERENCES": ("._paper_names", "PAPER_DIFFERENCES"),
    "PAPER_NAMES": ("._paper_names", "PAPER_NAMES"),
    "paper_names": ("._paper_names", "paper_names"),
    "latex_report": ("._printing", "latex_report"),
    "series_json": ("._printing", "series_json"),
    "text_report": ("._printing", "text_report"),
    "Branch": ("._response", "Branch"),
    "Response": ("._response", "Response"),
    "frequency_response": ("._response", "frequency_response"),
    "SeriesOrbits": ("._series_orbit", "SeriesOrbits"),
    "series_orbits": ("._series_orbit", "series_orbits"),
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())


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
    "SeriesOrbits",
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
    "series_orbits",
    "series_symbols",
    "symbols",
    "text_report",
]
