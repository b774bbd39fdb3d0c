"""The physical model of Eq. 2.1-2.4 as sympy expressions.

This is the one source of truth: the simulator in ``numerics`` and Eq. 2.6 are
both generated from the expressions built here. sympy is imported by the first
symbolic question, not with the class: a command whose numbers and kernels are
cached on disk (``cache.py``) builds, compares and records models without it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from functools import cache, cached_property, lru_cache
from typing import TYPE_CHECKING

from perturb.common import check_keys

from .effects import FULL, Effects
from .parameters import PAPER, ContactParameters

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["ContactModel", "exact_number"]


def exact_number(value: float) -> sp.Expr:
    """A sympy number for a parameter value: exact for integer and decimal exponents."""
    import sympy as sp

    rational = sp.Rational(repr(float(value)))
    return sp.Integer(rational) if rational.q == 1 else rational


@cache
def _static_deflection() -> sp.Expr:
    """y0 solving S c_n y0^m2 = M g, in closed form (sympy.solve gives the same
    expression in 0.3 s; tests/test_startup.py substitutes it back)."""
    from .symbols import M, S, c_n, g, m2

    return (M * g / (S * c_n)) ** (1 / m2)


class ContactModel:
    """The slider on a rough contact, with switchable effects (Eq. 2.1-2.4).

    Parameters
    ----------
    parameters : ContactParameters
        Values of S, c_n, m2, h_n, l, M, g (the paper's by default).
    effects : Effects
        Which laws and effects the model includes (all of the paper's by default).

    Examples
    --------
    >>> model = ContactModel()
    >>> model.static_deflection
    (M*g/(S*c_n))**(1/m2)
    >>> round(model.evaluate(model.static_deflection) * 1e9, 1)  # nm
    225.2

    As data (how a result carries the model that made it), and back:

    >>> data = ContactModel(effects=Effects(gravity=False)).as_dict()
    >>> data["effects"]["gravity"], data["parameters"]["M"]
    (False, 0.2106)
    >>> ContactModel.from_dict(data) == ContactModel(effects=Effects(gravity=False))
    True
    """

    def __init__(
        self, parameters: ContactParameters = PAPER, effects: Effects = FULL
    ) -> None:
        if not isinstance(parameters, ContactParameters):
            raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
        if not isinstance(effects, Effects):
            raise ValueError(f"`effects` must be Effects, got {effects!r}.")
        self.parameters = parameters
        self.effects = effects
        if not effects.contact_loss and not self._law_is_polynomial():
            raise ValueError(
                "`effects.contact_loss=False` continues the contact law for y < 0, "
                "which needs a polynomial law: use spring='taylor' or 'linear' and "
                "damping='linear', or integer exponents; got "
                f"m2={parameters.m2!r}, l={parameters.l!r}, effects={effects!r}."
            )

    def _law_is_polynomial(self) -> bool:
        spring_ok = self.effects.spring != "power" or float(self.parameters.m2).is_integer()
        damping_ok = self.effects.damping != "power" or float(self.parameters.l).is_integer()
        return spring_ok and damping_ok

    # -- parameter values -------------------------------------------------
    @cached_property
    def values(self) -> dict[sp.Symbol, sp.Expr]:
        """Substitution of the parameter symbols by the parameter values."""
        import sympy as sp

        from .symbols import PARAMETER_SYMBOLS

        return {
            PARAMETER_SYMBOLS[name]: (
                exact_number(value) if name in ("m2", "l") else sp.Float(value, 17)
            )
            for name, value in self.parameters.as_dict().items()
        }

    def evaluate(self, expr: sp.Expr) -> float:
        """Evaluate an expression of the parameter symbols at the parameter values."""
        import sympy as sp

        return float(sp.N(sp.sympify(expr).subs(self.values), 17))

    # -- Eq. 2.1: the contact laws ----------------------------------------
    @property
    def static_deflection(self) -> sp.Expr:
        """y0 = delta0, where the spring carries the weight: S c_n y0^m2 = M g."""
        return _static_deflection()

    @staticmethod
    def power_spring(deflection: sp.Expr) -> sp.Expr:
        """F_s = -S c_n delta^m2 (Eq. 2.1)."""
        from .symbols import S, c_n, m2

        return -S * c_n * deflection**m2

    @staticmethod
    def power_damping(deflection: sp.Expr, velocity: sp.Expr) -> sp.Expr:
        """F_d = -S h_n delta^l ydot (Eq. 2.1)."""
        from .symbols import S, h_n, l

        return -S * h_n * deflection**l * velocity

    def spring_law(self, deflection: sp.Expr) -> sp.Expr:
        """The spring force in contact, for the chosen spring law (Eq. 2.1, 2.5)."""
        from .symbols import y

        if self.effects.spring == "power":
            return self.power_spring(deflection)
        degree = 1 if self.effects.spring == "linear" else self.effects.taylor_degree
        return self.taylor_polynomial(self.power_spring, degree).subs(y, deflection)

    def taylor_polynomial(self, law, degree: int) -> sp.Expr:
        """Taylor polynomial of ``law(y)`` about y0, in y, to ``degree`` (Eq. 2.5)."""
        import sympy as sp

        from .symbols import y

        y0 = self.static_deflection
        return sum(
            sp.simplify(sp.diff(law(y), y, k).subs(y, y0) / sp.factorial(k)) * (y - y0) ** k
            for k in range(degree + 1)
        )

    def damping_law(self, deflection: sp.Expr, velocity: sp.Expr) -> sp.Expr:
        """The damping force in contact: full, or linearised at y0 (Eq. 2.5)."""
        if self.effects.damping == "power":
            return self.power_damping(deflection, velocity)
        return self.power_damping(self.static_deflection, velocity)

    def contact_force(self) -> sp.Expr:
        """The reaction R = F_s + F_d, gated at y = 0 when contact can be lost."""
        import sympy as sp

        from .symbols import v, y

        law = self.spring_law(y) + self.damping_law(y, v)
        if not self.effects.contact_loss:
            return law
        return sp.Piecewise((law, y > 0), (0, True))

    # -- Eq. 2.2-2.4 --------------------------------------------------------
    @property
    def gravity_force(self) -> sp.Expr:
        """Q = M g (Eq. 2.2), or 0 when gravity is switched off."""
        import sympy as sp

        from .symbols import M, g

        return M * g if self.effects.gravity else sp.Integer(0)

    @property
    def drive(self) -> sp.Expr:
        """P = P_a cos(2 pi f_e t) (Eq. 2.2)."""
        import sympy as sp

        from .symbols import P_a, f_e, t

        return P_a * sp.cos(2 * sp.pi * f_e * t)

    def acceleration(self, force: sp.Expr | None = None) -> sp.Expr:
        """ydot-dot = (F_k + F_d + P) / M (Eq. 2.3, 2.4).

        ``force`` replaces the drive P (the simulator tabulates it).
        """
        from .symbols import M

        drive = self.drive if force is None else force
        return (self.contact_force() + self.gravity_force + drive) / M

    def numeric_acceleration(self, force: sp.Expr) -> sp.Expr:
        """The acceleration with every parameter replaced by its value."""
        return self.acceleration(force).subs(self.values)

    # -- as data ------------------------------------------------------------
    def as_dict(self) -> dict:
        """``{"parameters": {...}, "effects": {...}, "y0_m": ..., "f_n0_hz": ..., ...}``:
        the model as plain JSON-ready values, with the numbers of Eq. 2.6 it implies
        (``Eq26Numbers``: derived, for a reader of the file; ``from_dict`` ignores them)."""
        record = _model_record(self.parameters, self.effects)  # cached: every result asks
        return {**record, "parameters": dict(record["parameters"]),
                "effects": dict(record["effects"])}

    @classmethod
    def from_dict(cls, data: Mapping) -> ContactModel:
        """The model that ``as_dict`` described; a ValueError names a missing or unknown key."""
        from .numbers import Eq26Numbers

        if isinstance(data, Mapping):  # the numbers of Eq. 2.6 are derived: not read back
            derived = {f.name for f in dataclasses.fields(Eq26Numbers)}
            data = {key: value for key, value in data.items() if key not in derived}
        data = check_keys("model", data, ("parameters", "effects"))
        parameters = ContactParameters.from_dict(data["parameters"])
        effects = Effects(**check_keys("effects", data["effects"], Effects.names()))
        return cls(parameters, effects)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ContactModel):
            return NotImplemented
        return (self.parameters, self.effects) == (other.parameters, other.effects)

    def __hash__(self) -> int:
        return hash((self.parameters, self.effects))

    def __repr__(self) -> str:
        values = "paper values" if self.parameters == PAPER else repr(self.parameters)
        return f"ContactModel({values}; {self.effects.describe()})"


@lru_cache(maxsize=64)
def _model_record(parameters: ContactParameters, effects: Effects) -> dict:
    from .numbers import eq26_numbers

    return {"parameters": parameters.as_dict(), "effects": dataclasses.asdict(effects),
            **eq26_numbers(parameters).as_dict()}
