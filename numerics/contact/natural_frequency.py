"""Fig. 4: the natural frequency of a steel body against its height.

A rigid steel body of height h_b stands on the paper's contact (face S). Its
mass is M = rho S h_b, with the density of steel taken from the paper's cube
(M = 0.2106 kg for a 30 mm cube), and its natural frequency is f_n0 of Eq. 2.6,
omega0^2 = M^-1 S c_n m2 y0^(m2-1), evaluated as a function of M.
"""

from __future__ import annotations

import time

import numpy as np
import sympy as sp

from perturb import PAPER, PAPER_CUBE_SIDE_M, PAPER_F_N0_HZ, ContactModel, ContactParameters, Eq26
from perturb import symbols as sym
from perturb.common import Result, check_int, lane_array, result

__all__ = ["HeightSweep", "natural_frequency_vs_height", "steel_density"]


@result
class HeightSweep(Result):
    """Natural frequency of the linearised contact against the body's height.

    Attributes
    ----------
    height_m, mass_kg, f_n0_hz : ndarray, shape (points,)
        Height h_b [m], mass M = rho S h_b [kg] and natural frequency [Hz].
    density_kg_m3 : float
        Density of the body, from the paper's cube.
    paper_height_m, paper_f_n0_hz : float
        The paper's body (the 30 mm cube) and the natural frequency it reports.
    model : dict
        The contact the bodies stand on (``ContactModel.as_dict()``); its
        ``M`` is the parameter set's, replaced by ``mass_kg`` point by point.
    settings : dict
        ``points``: the number of heights.
    elapsed_s : float
        Wall time [s].
    """

    height_m: np.ndarray
    mass_kg: np.ndarray
    f_n0_hz: np.ndarray
    density_kg_m3: float
    paper_height_m: float
    paper_f_n0_hz: float
    model: dict
    settings: dict
    elapsed_s: float = 0.0

    def summary(self) -> str:
        return (
            f"HeightSweep: {self.height_m.size} heights, h_b {self.height_m.min() * 1e3:g}.."
            f"{self.height_m.max() * 1e3:g} mm, f_n0 {self.f_n0_hz.max():.6g}.."
            f"{self.f_n0_hz.min():.6g} Hz, rho = {self.density_kg_m3:.6g} kg/m^3, "
            f"{self.elapsed_s:.3g} s"
        )


def steel_density() -> float:
    """rho = M / side^3 of the paper's steel cube [kg/m^3].

    Examples
    --------
    >>> round(steel_density(), 1)
    7800.0
    """
    return PAPER.M / PAPER_CUBE_SIDE_M**3


def _f_n0_of_mass(parameters: ContactParameters):
    """f_n0(M) [Hz], vectorised: Eq. 2.6's omega0 with every parameter but M fixed."""
    model = ContactModel(parameters)
    omega0_squared = Eq26(model).omega0_squared.subs(
        {symbol: value for symbol, value in model.values.items() if symbol != sym.M}
    )
    function = sp.lambdify(sym.M, sp.sqrt(omega0_squared) / (2 * sp.pi), modules="numpy")
    return lambda mass: function(np.asarray(mass, dtype=float))


def natural_frequency_vs_height(
    height_m=None, *, parameters: ContactParameters = PAPER, points: int = 100
) -> HeightSweep:
    """f_n0 of steel bodies of height h_b on the contact of ``parameters`` (Fig. 4).

    Parameters
    ----------
    height_m : array_like, optional
        Heights h_b [m] (> 0); by default ``points`` values from 5 mm to 150 mm.
    parameters : ContactParameters
        The contact (its S, c_n, m2, g); its M is replaced by rho S h_b.
    points : int
        Number of default heights, >= 2 (ignored when ``height_m`` is given).

    Returns
    -------
    HeightSweep

    Examples
    --------
    >>> sweep = natural_frequency_vs_height([0.01, 0.03, 0.1])
    >>> [round(f) for f in sweep.f_n0_hz]
    [1955, 1486, 1099]
    """
    start = time.perf_counter()
    if not isinstance(parameters, ContactParameters):
        raise ValueError(f"`parameters` must be ContactParameters, got {parameters!r}.")
    points = check_int("points", points, 2, 1_000_000, why="a curve of a million heights is "
                       "finer than any figure")
    if height_m is None:
        height_m = np.linspace(0.005, 0.15, points)
    heights = lane_array("height_m", height_m, positive=True)
    density = steel_density()
    mass = density * parameters.S * heights
    return HeightSweep(
        height_m=heights, mass_kg=mass, f_n0_hz=_f_n0_of_mass(parameters)(mass),
        density_kg_m3=density, paper_height_m=PAPER_CUBE_SIDE_M,
        paper_f_n0_hz=PAPER_F_N0_HZ, model=ContactModel(parameters).as_dict(),
        settings={"points": int(heights.size)}, elapsed_s=time.perf_counter() - start,
    )
