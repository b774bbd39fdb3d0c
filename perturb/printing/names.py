"""The paper's names (Eq. 2.8-2.10, A.1, A.2) in the engine's systematic names.

The engine writes u_n = sum_k A_n_k cos(k Omega t + phi_n_k) with A_n_k >= 0
(a mean A_n_0 is signed), F_n_k cos(k Omega t + psi_n_k) for harmonic k of the
order-n right side, and H_k exp(i theta_k) = 1/(omega^2 - k^2 Omega^2 + 2 i k c
Omega) for the transfer of harmonic k. The paper numbers its amplitudes A0-A19
and phases phi0-phi9 in the order they appear; read with the conventions below,
every printed equation of the paper agrees with the engine (checked
numerically in ``tests/test_perturb_paper_names.py``).

Conventions the paper uses without stating them
-----------------------------------------------
- phi1, phi2, phi5, phi9 are the transfer phases theta_2, theta_3, theta_4,
  theta_5, and phi0 (the phase of u0) is also theta_1, since u0 = G H_1
  cos(Omega t + theta_1). That is why u2 of Eq. 2.10 carries "2 phi0": the
  phase phi0 of its right side plus theta_1 = phi0 of the transfer.
- Amplitudes are signed: A1 = -h A0^2 H_2 / 2 < 0 (so that phi1 = theta_2),
  A2, A8, A11 are means, A7 = A3 + A4. A5 = -h A0 A1 H_1 and
  A6 = -h A0 A1 H_3 carry the sign of -A1 and are positive (h > 0): the mapping
  gives them as h A_0_1 A_1_2 H_1 and h A_0_1 A_1_2 H_3, products of
  non-negative factors.
- phi3, phi4, phi6, phi7, phi8 are phases of the right sides (psi_n_k), and
  A8-A10, A14-A16 their amplitudes (F_n_k).

Examples
--------
>>> PAPER_NAMES["A12"], PAPER_NAMES["phi3"]
('A_3_2', 'psi_3_2')
>>> sorted(paper_names(2))[:4]
['A0', 'A1', 'A2', 'A3']
"""

from __future__ import annotations

from ..series.series_symbols import check_order

__all__ = ["PAPER_NAMES", "PAPER_NAME_ORDERS", "PAPER_DIFFERENCES", "paper_names"]

#: Each name of the paper as a sympy-readable expression of the engine's names.
PAPER_NAMES: dict[str, str] = {
    # Eq. 2.8
    "A0": "A_0_1",
    "phi0": "phi_0_1",
    # Eq. 2.9: u1 = A1 cos(2 Omega t + 2 phi0 + phi1) + A2
    "A1": "-A_1_2",
    "phi1": "theta_2",
    "A2": "A_1_0",
    "b1": "b_1",
    # Eq. 2.10: u2 = A7 cos(Omega t + 2 phi0) + A5 cos(Omega t + 2 phi0 + phi1)
    #                + A6 cos(3 Omega t + 3 phi0 + phi1 + phi2)
    "b2": "b_2",
    "A3": "b_2*A_0_1*H_1",
    "A4": "-2*h*A_0_1*A_1_0*H_1",
    "A5": "h*A_0_1*A_1_2*H_1",
    "A6": "h*A_0_1*A_1_2*H_3",
    "A7": "(b_2 - 2*h*A_1_0)*A_0_1*H_1",
    "phi2": "theta_3",
    # Eq. A.1: right side A8 + A9 cos(2 Omega t + phi3) + A10 cos(4 Omega t + phi4);
    # u3 = A11 + A12 cos(2 Omega t + phi3 + phi1) + A13 cos(4 Omega t + phi4 + phi5)
    "b3": "b_3",
    "A8": "F_3_0",
    "A9": "F_3_2",
    "phi3": "psi_3_2",
    "A10": "F_3_4",
    "phi4": "psi_3_4",
    "A11": "A_3_0",
    "A12": "A_3_2",
    "A13": "A_3_4",
    "phi5": "theta_4",
    # Eq. A.2: right side A14 cos(Omega t + phi6) + A15 cos(3 Omega t + phi7)
    # + A16 cos(5 Omega t + phi8); u4 = A17 cos(Omega t + phi6 + phi0)
    # + A18 cos(3 Omega t + phi7 + phi2) + A19 cos(5 Omega t + phi8 + phi9)
    "b4": "b_4",
    "A14": "F_4_1",
    "phi6": "psi_4_1",
    "A15": "F_4_3",
    "phi7": "psi_4_3",
    "A16": "F_4_5",
    "phi8": "psi_4_5",
    "A17": "A_4_1",
    "A18": "A_4_3",
    "A19": "A_4_5",
    "phi9": "theta_5",
}

#: The order of the equation that introduces each name.
PAPER_NAME_ORDERS: dict[str, int] = {
    name: order
    for order, names in enumerate(
        [
            ("A0", "phi0"),
            ("A1", "phi1", "A2", "b1"),
            ("b2", "A3", "A4", "A5", "A6", "A7", "phi2"),
            ("b3", "A8", "A9", "phi3", "A10", "phi4", "A11", "A12", "A13", "phi5"),
            ("b4", "A14", "phi6", "A15", "phi7", "A16", "phi8", "A17", "A18", "A19", "phi9"),
        ]
    )
    for name in names
}

#: Where the printed paper differs from the derivation, and why.
PAPER_DIFFERENCES: tuple[dict[str, str], ...] = (
    {
        "where": "Eq. 2.10, u2",
        "printed": "... + A6 cos(6 pi f_e t + 3 phi0 + phi1 + phi2)"
        " = A7 cos(2 pi f_e t + 2 phi0) + ...",
        "derived": "u2 = A7 cos(Omega t + 2 phi0) + A5 cos(Omega t + 2 phi0 + phi1)"
        " + A6 cos(3 Omega t + 3 phi0 + phi1 + phi2), with A7 = A3 + A4",
        "reason": "The '=' joins the sum of four terms to its regrouped form in the "
        "middle of a line; the regrouped u2 is right.",
    },
    {
        "where": "Eq. 2.10, u2 and Eq. A.2, u4 (phases of the fundamental)",
        "printed": "cos(2 pi f_e t + 2 phi0), cos(2 pi f_e t + phi6 + phi0)",
        "derived": "cos(Omega t + phi0 + theta_1) and cos(Omega t + psi_4_1 + theta_1)",
        "reason": "The transfer of the fundamental adds its phase theta_1, which the "
        "paper writes phi0: right only because u0 = G H_1 cos(Omega t + theta_1), so "
        "that phi0 = theta_1. Read as a free phase of u0, the printed phases are wrong.",
    },
    {
        "where": "Eq. 2.9, u1, and everything after it",
        "printed": "u1 = A1 cos(4 pi f_e t + 2 phi0 + phi1) + A2",
        "derived": "A1 = -h A0^2 H_2 / 2 (negative), phi1 = theta_2; equivalently "
        "|A1| cos(2 Omega t + 2 phi0 + theta_2 + pi)",
        "reason": "The paper's amplitudes are signed and phi1, phi2, phi5, phi9 are "
        "transfer phases (b2 = 2 h A2 + h A1 cos(phi1) needs exactly that); the engine "
        "keeps A_n_k >= 0 and puts the sign into the phase.",
    },
    {
        "where": "Eq. 2.9-A.2, b1 and b3",
        "printed": "b1 = 0, b3 = 0 (stated for the orders shown)",
        "derived": "b_n = 0 for every odd n",
        "reason": "At odd orders the right side holds only even harmonics (a "
        "quadratic non-linearity alternates the parity of harmonics between "
        "orders), so there is no fundamental for b_n to cancel.",
    },
)


def paper_names(order: int) -> dict[str, str]:
    """The paper's names introduced up to ``order`` (the paper stops at 4).

    Examples
    --------
    >>> paper_names(0)
    {'A0': 'A_0_1', 'phi0': 'phi_0_1'}
    """
    order = check_order(order)
    return {name: PAPER_NAMES[name] for name, n in PAPER_NAME_ORDERS.items() if n <= order}
