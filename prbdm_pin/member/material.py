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
