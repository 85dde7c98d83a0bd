"""The beam material: linear elastic and isotropic, and the default steel AISI 4340."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import BeamInputError
from ..io.jsonfile import field_str
from ..options.checks import check_float
from ..options.validate import check_modulus
from .checks import finite_positive

__all__ = ["Material", "STEEL_4340"]


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material.

    Attributes
    ----------
    name : str
    E_Pa : float
        Young's modulus in Pa, in [1e6, 1e13] (``validate.E_RANGE_PA``: a modulus outside is a
        unit slip, E in GPa or MPa, and the error says so).
    rho_kg_m3 : float
        Density in kg/m^3.
    nu : float
        Poisson's ratio (dimensionless, in (-1, 0.5)).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> steel = pp.Material()
    >>> steel.E_Pa, steel.rho_kg_m3, steel.nu  # Pa, kg/m^3, -
    (205000000000.0, 7850.0, 0.28)
    >>> alu = pp.Material(name="aluminium 6061", E_Pa=69e9, rho_kg_m3=2700.0, nu=0.33)
    >>> round(alu.E_Pa / alu.rho_kg_m3 / 1e6, 2)  # specific modulus, MN m/kg
    25.56
    >>> pp.Material(E_Pa=205.0)  # a modulus in GPa is refused
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: material.E = 205 Pa: outside the plausible ...
    """

    name: str = "steel AISI 4340"
    E_Pa: float = 205e9
    rho_kg_m3: float = 7850.0
    nu: float = 0.28

    def __post_init__(self) -> None:
        """Validate the name and the constants; an error names the field and the value."""
        # a control character makes the URDF/MJCF that carry the name unreadable XML
        field_str("material.name", self.name)
        check_modulus("material.E", self.E_Pa)  # in E_RANGE_PA: E in GPa is named
        finite_positive("material.rho", self.rho_kg_m3)
        if not -1.0 < check_float("material.nu", self.nu) < 0.5:
            raise BeamInputError(f"material.nu = {self.nu}: must be in (-1, 0.5)")

    @property
    def G_Pa(self) -> float:
        """Shear modulus in Pa."""
        return self.E_Pa / (2.0 * (1.0 + self.nu))


STEEL_4340 = Material()
