"""The model's figures, as `python -m numerics info` prints them."""

from __future__ import annotations

from perturb import ContactModel, Eq26

__all__ = ["model_info", "format_info"]

_DESCRIPTIONS = {
    "y0_m": "static contact deflection y0",
    "f_n0_hz": "natural frequency f_n0 of the linearised system",
    "omega0_rad_s": "omega0 = 2 pi f_n0",
    "Q_n": "weight of the slider Q = M g",
    "c_per_s": "c of Eq. 2.6 (2c = S h_n y0^l / M)",
    "h_per_m_s2": "eps*h of Eq. 2.6 (quadratic stiffness over M)",
    "damping_ratio": "c / omega0",
}


def model_info(model: ContactModel | None = None) -> dict[str, float]:
    """The figures of Eq. 2.6 for the model (the paper's by default)."""
    return Eq26(model).numeric()  # cached per parameter set by perturb


def format_info(info: dict[str, float]) -> str:
    """One aligned line per figure, with what it means."""
    return "\n".join(
        f"{key:<14} {value:>14.7g}   {_DESCRIPTIONS.get(key, '')}" for key, value in info.items()
    )
