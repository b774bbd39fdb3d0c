"""The paper's printed Eq. 2.8-2.10, A.1, A.2 against the engine, name by name.

The paper's equations are typed here as printed (with the conventions that
``perturb.printing.names`` documents) and evaluated with numpy: an independent,
hand-derived route to the same amplitudes, phases and b_n.
"""

from functools import partial as _partial

import numpy as np
import pytest
import sympy as sp

from perturb import eq26_numbers
from perturb.printing.names import PAPER_NAMES, paper_names
from perturb.series.compiled import compile_series

# Eq. 2.6's series, which these tests hold unchanged: the paper's truncation.
compile_series = _partial(compile_series, truncation="paper")

VALUES = eq26_numbers()
# (A0 [m], omega / omega0, Omega / omega0): off resonance, near the 1/2 and 1/3
# superharmonic and near the primary resonance.
POINTS = [(5e-8, 0.97, 0.31), (8e-8, 0.96, 0.49), (3e-8, 0.99, 0.335), (1e-7, 0.95, 0.94)]


def e(phase):
    return np.exp(1j * phase)


def paper(A0, w, W, c, h):
    """Eq. 2.8-A.2 as printed; returns the named quantities and the u_n harmonics."""
    T = {k: 1 / (w**2 - k**2 * W**2 + 2j * k * c * W) for k in range(1, 6)}
    H = {k: abs(T[k]) for k in T}
    th = {k: np.angle(T[k]) for k in T}
    p = {"A0": A0, "phi0": th[1]}
    phi0 = th[1]
    # Eq. 2.9
    p["A2"] = -h * A0**2 / (2 * w**2)
    p["A1"], p["phi1"] = -0.5 * h * A0**2 * H[2], th[2]
    A1, A2, phi1 = p["A1"], p["A2"], p["phi1"]
    # Eq. 2.10
    b2 = p["b2"] = 2 * h * A2 + h * A1 * np.cos(phi1)
    p["A3"], p["A4"] = b2 * A0 * H[1], -2 * h * A0 * A2 * H[1]
    A7 = p["A7"] = p["A3"] + p["A4"]
    A5 = p["A5"] = -h * A0 * A1 * H[1]
    A6 = p["A6"] = -h * A0 * A1 * H[3]
    phi2 = p["phi2"] = th[3]
    # Eq. A.1, right side by harmonic
    R0 = (
        b2 * A2
        - h * A0 * A7 * np.cos(phi0)
        - h * A0 * A5 * np.cos(phi0 + phi1)
        - 0.5 * h * A1**2
        - h * A2**2
    )
    R2 = (
        b2 * A1 * e(2 * phi0 + phi1)
        - h * A0 * A7 * e(3 * phi0)
        - h * A0 * A5 * e(3 * phi0 + phi1)
        - h * A0 * A6 * e(2 * phi0 + phi1 + phi2)
        - 2 * h * A1 * A2 * e(2 * phi0 + phi1)
    )
    R4 = -h * A0 * A6 * e(4 * phi0 + phi1 + phi2) - 0.5 * h * A1**2 * e(4 * phi0 + 2 * phi1)
    p["A8"], p["A9"], p["phi3"], p["A10"], p["phi4"] = (
        R0,
        abs(R2),
        np.angle(R2),
        abs(R4),
        np.angle(R4),
    )
    A11 = p["A11"] = R0 / w**2
    A12, A13 = p["A12"], p["A13"] = p["A9"] * H[2], p["A10"] * H[4]
    phi3, phi4, phi5 = p["phi3"], p["phi4"], th[4]
    p["phi5"] = phi5
    # Eq. A.2: b4 as printed, then the right side by harmonic
    p["b4"] = -(1 / A0) * (
        b2 * A7 * np.cos(phi0)
        + b2 * A5 * np.cos(phi0 + phi1)
        - 2 * h * A0 * A11 * np.cos(0)
        - h * A0 * A12 * np.cos(-2 * phi0 + phi1 + phi3)
        - h * A1 * A7 * np.cos(-phi0 + phi1)
        - h * A1 * A5 * np.cos(-phi0)
        - h * A1 * A6 * np.cos(phi2)
        - 2 * h * A2 * A7 * np.cos(phi0)
        - 2 * h * A2 * A5 * np.cos(phi0 + phi1)
    )
    R1 = (
        b2 * A7 * e(2 * phi0)
        + b2 * A5 * e(2 * phi0 + phi1)
        + p["b4"] * A0 * e(phi0)
        - 2 * h * A0 * A11 * e(phi0)
        - h * A0 * A12 * e(-phi0 + phi1 + phi3)
        - h * A1 * A7 * e(phi1)
        - h * A1 * A5 * e(0)
        - h * A1 * A6 * e(phi0 + phi2)
        - 2 * h * A2 * A7 * e(2 * phi0)
        - 2 * h * A2 * A5 * e(2 * phi0 + phi1)
    )
    R3 = (
        b2 * A6 * e(3 * phi0 + phi1 + phi2)
        - h * A0 * A12 * e(phi0 + phi1 + phi3)
        - h * A0 * A13 * e(-phi0 + phi4 + phi5)
        - h * A1 * A7 * e(4 * phi0 + phi1)
        - h * A1 * A5 * e(4 * phi0 + 2 * phi1)
        - 2 * h * A2 * A6 * e(3 * phi0 + phi1 + phi2)
    )
    R5 = -h * A0 * A13 * e(phi0 + phi4 + phi5) - h * A1 * A6 * e(5 * phi0 + 2 * phi1 + phi2)
    for name, R in (("6", R1), ("7", R3), ("8", R5)):
        p[f"phi{name}"] = np.angle(R)
    p["A14"], p["A15"], p["A16"] = abs(R1), abs(R3), abs(R5)
    p["A17"], p["A18"], p["A19"] = abs(R1) * H[1], abs(R3) * H[3], abs(R5) * H[5]
    p["phi9"] = th[5]
    p["b1"] = p["b3"] = 0.0
    harmonics = {
        (0, 1): A0 * e(phi0),
        (1, 0): A2,
        (1, 2): A1 * e(2 * phi0 + phi1),
        (2, 1): A7 * e(2 * phi0) + A5 * e(2 * phi0 + phi1),
        (2, 3): A6 * e(3 * phi0 + phi1 + phi2),
        (3, 0): A11,
        (3, 2): A12 * e(phi3 + phi1),
        (3, 4): A13 * e(phi4 + phi5),
        (4, 1): p["A17"] * e(p["phi6"] + phi0),
        (4, 3): p["A18"] * e(p["phi7"] + phi2),
        (4, 5): p["A19"] * e(p["phi8"] + p["phi9"]),
    }
    return p, harmonics


def engine(A0, w, W, c, h):
    """The engine's named values (absolute phases, phi0 = theta_1)."""
    formulas = compile_series(4)
    env = formulas.evaluate(A0, w, W, c, h)
    T = {k: 1 / (w**2 - k**2 * W**2 + 2j * k * c * W) for k in range(0, 6)}
    phi0 = np.angle(T[1])
    named = {"h": h, "b_1": 0.0, "b_3": 0.0, "b_2": env["b_2"], "b_4": env["b_4"]}
    harmonics = {}
    for n, k in formulas.keys:
        if k == 0:
            harmonics[(n, 0)] = float(env[f"A_{n}_0"])
            named[f"A_{n}_0"], named[f"F_{n}_0"] = harmonics[(n, 0)], harmonics[(n, 0)] * w**2
            continue
        z = complex(env[f"z_{n}_{k}"]) * e(k * phi0)
        harmonics[(n, k)] = z
        named[f"A_{n}_{k}"], named[f"phi_{n}_{k}"] = abs(z), np.angle(z)
        named[f"F_{n}_{k}"], named[f"psi_{n}_{k}"] = abs(z / T[k]), np.angle(z / T[k])
    for k in range(1, 6):
        named[f"H_{k}"], named[f"theta_{k}"] = abs(T[k]), np.angle(T[k])
    return named, harmonics


@pytest.mark.parametrize("point", POINTS)
def test_printed_harmonics_agree_with_engine(point):
    A0, w, W = point[0], point[1] * VALUES.omega0_rad_s, point[2] * VALUES.omega0_rad_s
    _, printed = paper(A0, w, W, VALUES.c_per_s, VALUES.h_per_m_s2)
    _, derived = engine(A0, w, W, VALUES.c_per_s, VALUES.h_per_m_s2)
    assert set(printed) == set(derived)
    for key in printed:
        scale = max(abs(derived[key]), 1e-300)
        assert abs(printed[key] - derived[key]) <= 1e-9 * scale, key


@pytest.mark.parametrize("point", POINTS)
def test_paper_names_map_onto_engine_names(point):
    A0, w, W = point[0], point[1] * VALUES.omega0_rad_s, point[2] * VALUES.omega0_rad_s
    printed, _ = paper(A0, w, W, VALUES.c_per_s, VALUES.h_per_m_s2)
    named, _ = engine(A0, w, W, VALUES.c_per_s, VALUES.h_per_m_s2)
    for name, expression in PAPER_NAMES.items():
        expr = sp.sympify(expression)
        value = complex(expr.subs({sp.Symbol(str(s)): named[str(s)] for s in expr.free_symbols}))
        if name.startswith("phi"):
            assert abs(np.exp(1j * value.real) - np.exp(1j * printed[name])) < 1e-9, name
        else:
            assert abs(value - printed[name]) <= 1e-9 * max(abs(printed[name]), 1e-300), name


def test_every_name_of_the_paper_is_mapped():
    names = {f"A{i}" for i in range(20)} | {f"phi{i}" for i in range(10)}
    names |= {f"b{i}" for i in range(1, 5)}
    assert set(paper_names(4)) == names
