"""Which physical effects a model includes.

A reduced model is the paper's model with some effects switched off; a scene
names the effects it needs and the simulator builds only those.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from perturb.common import check_choice, check_int

__all__ = ["Effects", "FULL", "EQ_2_6", "LINEAR"]

SPRING_LAWS = ("power", "taylor", "linear")
DAMPING_LAWS = ("power", "linear")


#: The highest degree of a Taylor spring: its kernels are generated and compiled per
#: model, and the build grows fast with the degree (measured with a first ``simulate``
#: in an empty cache: degree 4 13 s, 12 15 s, 24 134 s).
MAX_TAYLOR_DEGREE = 16

@dataclass(frozen=True)
class Effects:
    """Switches of the contact model.

    Parameters
    ----------
    contact_loss : bool
        True: the contact force vanishes for y <= 0 (Eq. 2.1, "gapping").
        False: the contact law is continued for y < 0, as Eq. 2.6 does; this
        needs a polynomial law (Taylor or linear spring, or integer exponents).
    spring : {"power", "taylor", "linear"}
        The full power law ``-S c_n y^m2``; its Taylor polynomial about the
        static deflection y0 of degree ``taylor_degree`` (Eq. 2.5); or its
        linearisation about y0.
    taylor_degree : int
        Degree of the Taylor spring, at least 1 (used when spring="taylor").
    damping : {"power", "linear"}
        The full law ``-S h_n y^l ydot`` or its linearisation at y0 (Eq. 2.5).
    gravity : bool
        Whether the weight Q = M g presses the slider on the slideway.

    Examples
    --------
    >>> Effects(spring="taylor", taylor_degree=2).describe()
    'contact loss, taylor-2 spring, power damping, gravity'
    >>> Effects(spring="cubic")
    Traceback (most recent call last):
    ...
    ValueError: `spring` must be one of ('power', 'taylor', 'linear'), got 'cubic'.
    """

    contact_loss: bool = True
    spring: str = "power"
    taylor_degree: int = 2
    damping: str = "power"
    gravity: bool = True

    def __post_init__(self) -> None:
        check_choice("spring", self.spring, SPRING_LAWS)
        check_choice("damping", self.damping, DAMPING_LAWS)
        object.__setattr__(self, "taylor_degree", check_int(
            "taylor_degree", self.taylor_degree, maximum=MAX_TAYLOR_DEGREE,
            why="a new model's kernels take longer to build with each degree (measured: "
                "degree 12 15 s, 24 134 s)"))
        for name in ("contact_loss", "gravity"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"`{name}` must be True or False, got {getattr(self, name)!r}.")

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    def describe(self) -> str:
        spring = f"taylor-{self.taylor_degree}" if self.spring == "taylor" else self.spring
        parts = [
            "contact loss" if self.contact_loss else "no contact loss",
            f"{spring} spring",
            f"{self.damping} damping",
            "gravity" if self.gravity else "no gravity",
        ]
        return ", ".join(parts)


#: Eq. 2.1-2.4: every effect on.
FULL = Effects()
#: Eq. 2.6: quadratic Taylor spring, linearised damping, no contact loss.
EQ_2_6 = Effects(contact_loss=False, spring="taylor", taylor_degree=2, damping="linear")
#: The linearised model about y0: a damped linear oscillator.
LINEAR = Effects(contact_loss=False, spring="linear", damping="linear")
