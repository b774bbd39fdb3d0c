"""The largest series order each piece of work takes without being asked twice.

The work of a series grows with its order, and faster for a law that is no polynomial
(its consistent series gains terms at every order) than for one that is. Above the
orders here, each measured to take about a minute or less on the 2-core machine, a
function raises a ``ValueError`` and a command exits 2, both naming the order, the
limit and what was measured, unless ``allow_slow=True`` (``--allow-slow``) says to go
on. The limits are not the end of what is correct: a series of any order is right; it
is only slow.
"""

from __future__ import annotations

from perturb.common import check_int

from ..model.parameters import ContactParameters
from .truncation import Truncation, truncation_for

__all__ = ["check_slow_order", "SLOW_ORDERS"]

#: (work, kind of series) -> (largest order taken without allow_slow, what was measured).
#: "polynomial law": Eq. 2.6's series, or the consistent series of an integer m2 and l;
#: "power law": the consistent series of a non-integer m2 or l.
SLOW_ORDERS: dict[tuple[str, str], tuple[int, str]] = {
    ("derive", "polynomial law"): (24, "python -m perturb derive --order N: order 16 7 s, "
                               "20 17 s, 24 26 s"),
    ("derive", "power law"): (6, "python -m perturb derive --order N --set m2=1.5 --set "
                              "l=0.5: order 5 3.7 s, 6 10.7 s, some 2.5x an order"),
    ("backbone", "polynomial law"): (100, "python -m perturb backbone --order 100: 23 s"),
    ("backbone", "power law"): (50, "python -m perturb backbone --order N --set m2=1.5: "
                                "order 40 11 s, 60 80 s"),
    ("response", "polynomial law"): (24, "python -m perturb response --order N --truncation "
                                 "paper, 5 frequencies: order 14 4.5 s, 18 9.3 s, 22 14 s"),
    ("response", "power law"): (24, "the same at m2 = 1.5, l = 0.5: order 20 1.5 s (the "
                                "scheme; its coefficients k_j leave the floats near j = 40)"),
}


def check_slow_order(order: object, work: str, truncation: str | Truncation = "consistent",
                     parameters: ContactParameters | None = None, *,
                     allow_slow: bool = False) -> int:
    """``order`` as an int, or a ValueError: below 0, or above the limit of ``work``
    ("derive", "backbone" or "response") for this truncation and contact without
    ``allow_slow``.

    Examples
    --------
    >>> check_slow_order(8, "response")
    8
    >>> check_slow_order(30, "response")
    Traceback (most recent call last):
    ...
    ValueError: `order` 30 is above 24, the largest that response takes at once for a \
polynomial law (measured: python -m perturb response --order N --truncation paper, 5 \
frequencies: order 14 4.5 s, 18 9.3 s, 22 14 s); it is slow, not wrong: \
allow_slow=True (--allow-slow) goes on.
    """
    order = check_int("order", order, minimum=0)  # (no sympy: a warm response needs none)
    kind = _kind(work, truncation, parameters)
    limit, measured = SLOW_ORDERS[work, kind]
    if order > limit and not allow_slow:
        raise ValueError(f"`order` {order} is above {limit}, the largest that {work} takes at "
                         f"once for a {kind} (measured: {measured}); it is slow, not "
                         "wrong: allow_slow=True (--allow-slow) goes on.")
    return order


def _kind(work: str, truncation: str | Truncation,
          parameters: ContactParameters | None) -> str:
    """"power law" where the series gains terms at every order: a consistent series of a
    non-integer m2 or l (for the backbone, which has no damping, m2 alone)."""
    kept = truncation_for(truncation, parameters or ContactParameters())
    degrees = (kept.spring_degree,) if work == "backbone" else (
        kept.spring_degree, kept.damping_degree)
    return "power law" if None in degrees else "polynomial law"
