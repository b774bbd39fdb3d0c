"""Where the simulator's answers are measured to hold: the excitation and the contact.

The property tests (``tests/test_properties.py``) run steady states over forces from
0 to 5 Q and frequencies from 1 Hz to 1 MHz on the paper's contact, and over contacts
with m2 from 1 to 3, l from 0 to 2 and a damping from 1e-3 to 10 times the paper's,
which gives static deflections y0 from 5e-14 to 4e-5 m and natural frequencies f_n0
from 140 Hz to 2.3 MHz. Every result there is sound. The damping is widened where
other tests check the answers: the scenes' other contacts (m2 = 1.5, l = 0.5 at the
paper's c_n and h_n: c / omega0 = 0.27; l = 0.5 alone: 38), in tests/test_scenes.py
and the example other-contact.toml, against the full model and the API. Far outside,
answers are not known to hold: above some 1e12 Hz a sweep reported "rest" states hovering above the
slideway, and at M = 1e300 App was lost to round-off and reported as settled.

``check_tested`` refuses a study outside these ranges with a ``ValueError`` that names
the quantity, its range and why; ``unchecked=True`` (``--unchecked`` on the command
line) goes past it, at the user's risk. f_e is taken relative to f_n0: 1 Hz to 1 MHz
at the paper's f_n0 of 1485.6 Hz.
"""

from __future__ import annotations

import numpy as np

from perturb import ContactModel, eq26_numbers

__all__ = ["check_tested", "TESTED"]

#: name -> (low, high, what it is): the ranges of the module's docstring.
TESTED: dict[str, tuple[float, float, str]] = {
    "f_e / f_n0": (6.7e-4, 673.2, "the excitation frequency over the natural one"),
    "pa_frac": (0.0, 5.0, "the force amplitude over the weight Q"),
    "m2": (1.0, 3.0, "the spring's exponent"),
    "l": (0.0, 2.0, "the damper's exponent"),
    "damping_ratio": (1.8e-5, 40.0, "c / omega0, from 1e-3 times the paper's 0.018 to a "
                      "contact damped far past critical"),
    "y0_m": (5e-14, 4e-5, "the static deflection [m]"),
    "f_n0_hz": (140.0, 2.3e6, "the natural frequency [Hz]"),
}

_WHY = ("where the toolkit's answers are measured to hold (tests/test_properties.py); "
        "unchecked=True (--unchecked; a scene's unchecked = true) goes past it")


def check_tested(frequency_hz, pa_frac, model: ContactModel, *,
                 unchecked: bool = False) -> None:
    """A ValueError unless the excitation (every f_e [Hz] and P_a / Q given) and the
    contact of ``model`` lie in ``TESTED``; nothing with ``unchecked``."""
    if unchecked:
        return
    numbers = eq26_numbers(model.parameters)
    values = {"m2": [model.parameters.m2], "l": [model.parameters.l],
              "y0_m": [numbers.y0_m], "f_n0_hz": [numbers.f_n0_hz],
              "damping_ratio": [numbers.damping_ratio],
              "f_e / f_n0": np.ravel(frequency_hz) / numbers.f_n0_hz,
              "pa_frac": np.ravel(pa_frac)}
    for name, given in values.items():
        low, high, what = TESTED[name]
        given = np.asarray(given, dtype=float)
        outside = given[~((given >= low) & (given <= high))]
        if outside.size:
            shown = f"{outside[0]:.4g}" + (f" (and {outside.size - 1} more)"
                                           if outside.size > 1 else "")
            extra = (f", {low * numbers.f_n0_hz:.4g} to {high * numbers.f_n0_hz:.4g} Hz for "
                     "this contact" if name == "f_e / f_n0" else "")
            raise ValueError(f"`{name}` ({what}) is {shown}, outside {low:g} to {high:g}"
                             f"{extra}: {_WHY}.")
