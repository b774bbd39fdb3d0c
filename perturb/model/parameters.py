"""The paper's numbers, in one place.

Every value that the paper states (Section 2 and the figure captions) is
defined here and nowhere else; the rest of the toolkit imports it.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

from perturb.common import check_keys, check_positive, check_real

__all__ = [
    "ContactParameters",
    "PAPER",
    "parameters_with",
    "PAPER_BAND_HZ",
    "PAPER_COEXISTENCE",
    "PAPER_CUBE_SIDE_M",
    "PAPER_F_N0_HZ",
    "PAPER_HYSTERESIS_POINT",
    "PAPER_PANEL_FRACTIONS",
]


@dataclass(frozen=True)
class ContactParameters:
    """Physical parameters of the slider on its rough contact (Eq. 2.1, 2.2).

    Parameters
    ----------
    S : float
        Nominal contact area [m^2].
    c_n : float
        Contact stiffness coefficient [N/m^(m2+2)].
    m2 : float
        Exponent of the spring law, ``F_s = -S c_n y^m2``; at least 1.
    h_n : float
        Contact damping coefficient [N s/m^(l+3)].
    l : float
        Exponent of the damping law, ``F_d = -S h_n y^l ydot``; at least 0.
    M : float
        Mass of the slider [kg].
    g : float
        Acceleration of gravity [m/s^2].

    Examples
    --------
    >>> ContactParameters(M=0.5).M
    0.5
    >>> ContactParameters(m2=0.5)
    Traceback (most recent call last):
    ...
    ValueError: `m2` must be >= 1, got 0.5.
    """

    S: float = 0.0009
    c_n: float = 4.52693e16
    m2: float = 2.0
    h_n: float = 3.5e11
    l: float = 1.0
    M: float = 0.2106
    g: float = 9.81

    def __post_init__(self) -> None:
        for name in ("S", "c_n", "h_n", "M", "g"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        m2 = check_real("m2", self.m2)
        if m2 < 1:
            raise ValueError(f"`m2` must be >= 1, got {self.m2!r}.")
        object.__setattr__(self, "m2", m2)
        object.__setattr__(self, "l", check_positive("l", self.l, allow_zero=True))

    @property
    def Q_n(self) -> float:
        """The slider's weight Q = M g [N] (Eq. 2.2)."""
        return self.M * self.g

    def as_dict(self) -> dict[str, float]:
        """The seven values by name, in the order of the fields."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data) -> ContactParameters:
        """The parameters that ``as_dict`` gave; a missing or unknown key is a ValueError.

        Examples
        --------
        >>> ContactParameters.from_dict(PAPER.as_dict()) == PAPER
        True
        >>> ContactParameters.from_dict({"S": 1.0})
        Traceback (most recent call last):
        ...
        ValueError: `parameters` must have exactly the keys ('S', 'c_n', 'm2', 'h_n', 'l', \
'M', 'g'); missing ['c_n', 'm2', 'h_n', 'l', 'M', 'g'], unknown [].
        """
        return cls(**check_keys("parameters", data, cls.names()))

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


#: The parameter values adopted in the paper (Section 2).
PAPER = ContactParameters()


def parameters_with(overrides, base: ContactParameters = PAPER) -> ContactParameters:
    """``base`` (the paper's values) with some values replaced by name.

    This is how a scene's ``[model]`` table and a command's ``--set NAME=VALUE``
    reach the model; an unknown name is a ValueError listing the valid ones.

    Examples
    --------
    >>> parameters_with({"m2": 1.5, "l": 0.5}).m2
    1.5
    >>> parameters_with({"mass": 1.0})
    Traceback (most recent call last):
    ...
    ValueError: unknown model parameter 'mass'; the parameters are S, c_n, m2, h_n, l, M, g.
    """
    values = base.as_dict()
    for name, value in dict(overrides).items():
        if name not in values:
            raise ValueError(f"unknown model parameter {name!r}; the parameters are "
                             f"{', '.join(values)}.")
        values[name] = value
    return ContactParameters(**values)

#: The natural frequency the paper reports (Section 3) [Hz].
PAPER_F_N0_HZ = 1485.0

#: Force amplitudes of Fig. 2 and 3, panels a..j, as fractions of Q.
PAPER_PANEL_FRACTIONS = (0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50)

#: Side of the paper's steel cube [m] (Section 2: "a cube made of steel, whose
#: width, length and height are 30 mm"); M is its mass, S its face. Fig. 4 takes
#: the steel's density from it, rho = M / side^3.
PAPER_CUBE_SIDE_M = 0.03

#: The frequency band of Fig. 2 and 3 [Hz].
PAPER_BAND_HZ = (250.0, 1800.0)

#: Section 3.3: where the paper reports coexisting solutions, as (f_e [Hz], P_a / Q):
#: the primary and the 1/2 superharmonic at 740 Hz, 0.15Q; the primary, the 1/2 and
#: the 1/3 superharmonic at 490 Hz, 0.50Q.
PAPER_COEXISTENCE = {"740 Hz, 0.15Q": (740.0, 0.15), "490 Hz, 0.50Q": (490.0, 0.50)}

#: Fig. 5: the hysteresis loop of the contact at f_e = 1600 Hz, P_a = 0.40Q.
PAPER_HYSTERESIS_POINT = (1600.0, 0.40)
