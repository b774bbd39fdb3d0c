"""The named symbols of the model (Eq. 2.1-2.6)."""

from __future__ import annotations

import sympy as sp

__all__ = ["PARAMETER_SYMBOLS", "S", "c_n", "m2", "h_n", "l", "M", "g", "P_a", "f_e"]
__all__ += ["y", "v", "t", "u"]

# Parameters of Eq. 2.1 and 2.2. Positive, so that sympy may simplify powers.
S, c_n, h_n, M, g, f_e = sp.symbols("S c_n h_n M g f_e", positive=True)
m2 = sp.Symbol("m2", positive=True)
l = sp.Symbol("l", nonnegative=True)
P_a = sp.Symbol("P_a", nonnegative=True)

# State and time: y is the displacement (downward, Fig. 1e), v = dy/dt, and
# u = y - y0 is the displacement about the static deflection (Eq. 2.6).
y, v, u = sp.symbols("y v u", real=True)
t = sp.Symbol("t", nonnegative=True)

#: Symbols of ContactParameters, by field name.
PARAMETER_SYMBOLS = {"S": S, "c_n": c_n, "m2": m2, "h_n": h_n, "l": l, "M": M, "g": g}
