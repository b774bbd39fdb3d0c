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

from .model.contact_model import ContactModel

# Light names, imported with the package: none of them imports sympy.
from .model.effects import EQ_2_6, FULL, LINEAR, Effects
from .model.numbers import Eq26Numbers, eq26_numbers
from .model.parameters import (
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
    "__version__": (".common._version", "VERSION"),
    "series_symbols": (".series.series_symbols", None),
    "symbols": (".model.symbols", None),
    "BackboneSeries": (".series.free_backbone", "BackboneSeries"),
    "backbone_series": (".series.free_backbone", "backbone_series"),
    "CompiledSeries": (".series.compiled", "CompiledSeries"),
    "compile_series": (".series.formulas", "compile_series"),
    "derivation_latex": (".printing.derivation", "derivation_latex"),
    "derivation_text": (".printing.derivation", "derivation_text"),
    "Eq26": (".model.eq26", "Eq26"),
    "Series": (".series.lindstedt", "Series"),
    "derive": (".series.lindstedt", "derive"),
    "PAPER_DIFFERENCES": (".printing.names", "PAPER_DIFFERENCES"),
    "PAPER_NAMES": (".printing.names", "PAPER_NAMES"),
    "paper_names": (".printing.names", "paper_names"),
    "latex_report": (".printing.report", "latex_report"),
    "series_json": (".printing.report", "series_json"),
    "text_report": (".printing.report", "text_report"),
    "Branch": (".response.frequency", "Branch"),
    "Response": (".response.frequency", "Response"),
    "frequency_response": (".response.frequency", "frequency_response"),
    "SeriesOrbits": (".response.orbit", "SeriesOrbits"),
    "series_orbits": (".response.orbit", "series_orbits"),
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
