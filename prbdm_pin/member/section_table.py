"""A section table: a member known by its section properties at stations, linear between them.

For composite members or any member whose section is known only by its stiffnesses and
inertias. Every property is per station of ``Beam.x_m`` and linear between stations, so the
links' integrals (degree <= 3 with the moments in x) are exact by Gauss quadrature and the
springs' compliance ∫ dx / E I (E I linear) by the geometrically cut rule of
:mod:`~prbdm_pin.chain.stiffness_law`.

The table replaces the material's E, G and rho: the member's material stays (a default steel
when not given) only to convert the table's E I_y into the area moment E I_y / E that the
paper-style springs multiply by E again, so its value does not change any result.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..errors import BeamInputError, InputTypeError
from .checks import float_array

__all__ = ["SectionTable", "TABLE_FIELDS", "TABLE_REQUIRED", "check_table_member"]

# field -> (beam-JSON key, unit)
TABLE_FIELDS = {
    "EI_y_Nm2": "N m^2", "EI_z_Nm2": "N m^2", "GJ_Nm2": "N m^2", "rhoA_kg_m": "kg/m",
    "rhoI_x_kg_m": "kg m", "rhoI_y_kg_m": "kg m", "rhoI_z_kg_m": "kg m",
}
# rho I_x defaults to rho I_y + rho I_z (the perpendicular-axis theorem: exact for any section)
TABLE_REQUIRED = ("EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "rhoA_kg_m", "rhoI_y_kg_m", "rhoI_z_kg_m")


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class SectionTable:
    """Section properties at the stations ``Beam.x_m``, linear between them.

    Attributes
    ----------
    EI_y_Nm2, EI_z_Nm2 : ndarray, shape (k,)
        Bending stiffness about y (out of plane, the planar chain's) and z (in plane), N m^2.
    GJ_Nm2 : ndarray, shape (k,)
        Torsional stiffness, N m^2.
    rhoA_kg_m : ndarray, shape (k,)
        Mass per length, kg/m.
    rhoI_y_kg_m, rhoI_z_kg_m : ndarray, shape (k,)
        Rotary inertia per length about y and z, kg m (>= 0).
    rhoI_x_kg_m : ndarray, shape (k,), optional
        About the axis, kg m; None: rho I_y + rho I_z.

    Every entry is finite, stiffnesses and mass > 0; every list has one entry per station.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> E, b, t, rho = 205e9, 0.05, 0.01, 7850.0  # Pa, m, m, kg/m^3: a steel strip
    >>> I_y, I_z = b * t**3 / 12, t * b**3 / 12  # m^4
    >>> table = pp.SectionTable(EI_y_Nm2=[E * I_y] * 2, EI_z_Nm2=[E * I_z] * 2,
    ...                         GJ_Nm2=[80e9 * b * t**3 / 3] * 2, rhoA_kg_m=[rho * b * t] * 2,
    ...                         rhoI_y_kg_m=[rho * I_y] * 2, rhoI_z_kg_m=[rho * I_z] * 2)
    >>> table.size, round(float(table.EI_y_Nm2[0]), 2)  # stations, N m^2
    (2, 854.17)
    >>> round(float(table.rhoI_x_kg_m[0]), 8), round(rho * (I_y + I_z), 8)  # rho (I_y + I_z)
    (0.00085042, 0.00085042)
    """

    EI_y_Nm2: np.ndarray
    EI_z_Nm2: np.ndarray
    GJ_Nm2: np.ndarray
    rhoA_kg_m: np.ndarray
    rhoI_y_kg_m: np.ndarray
    rhoI_z_kg_m: np.ndarray
    rhoI_x_kg_m: np.ndarray | None = None

    kind = "table"

    def __post_init__(self) -> None:
        """Validate every list; an error names the field and the station index."""
        if self.rhoI_x_kg_m is None:
            y = float_array("section.rhoI_y_kg_m", self.rhoI_y_kg_m, "kg m")
            z = float_array("section.rhoI_z_kg_m", self.rhoI_z_kg_m, "kg m")
            if y.size == z.size:
                object.__setattr__(self, "rhoI_x_kg_m", y + z)
        size = None
        for f in fields(self):
            name = f"section.{f.name}"
            if getattr(self, f.name) is None:
                raise InputTypeError(f"{name} = None: must be a list of numbers")
            a = float_array(name, getattr(self, f.name), TABLE_FIELDS[f.name])
            if size is None:
                size = a.size
            elif a.size != size:
                raise BeamInputError(f"{name} has {a.size} entries: must match section.EI_y_Nm2 "
                                     f"({size} entries, one per station of x)")
            rotary = f.name.startswith("rhoI")
            bad = np.flatnonzero(a < 0.0 if rotary else a <= 0.0)
            if bad.size:
                i = int(bad[0])
                raise BeamInputError(f"{name}[{i}] = {a[i]} {TABLE_FIELDS[f.name]} (station {i}): "
                                     f"must be {'>= 0' if rotary else '> 0'}")
            object.__setattr__(self, f.name, _readonly(a))
        if not np.all(self.rhoI_x_kg_m > 0.0):
            i = int(np.flatnonzero(self.rhoI_x_kg_m <= 0.0)[0])
            raise BeamInputError(f"section.rhoI_x_kg_m[{i}] = {self.rhoI_x_kg_m[i]} kg m "
                                 f"(station {i}): must be > 0 (the links' roll inertia)")

    @property
    def size(self) -> int:
        """Number of stations."""
        return int(self.EI_y_Nm2.size)

    def at(self, xv: np.ndarray, x: np.ndarray):
        """Return the :class:`~prbdm_pin.member.section_law.SectionProperties` at ``x`` (m).

        ``xv`` are the stations (m), the table linear between them.
        """
        from .section_law import SectionProperties

        return SectionProperties(**{f.name: np.interp(x, xv, getattr(self, f.name))
                                    for f in fields(self)})

    def to_dict(self) -> dict:
        """Return the beam-JSON ``"section"`` mapping (units in the keys)."""
        out = {"kind": "table"}
        out.update({f.name: [float(v) for v in getattr(self, f.name)] for f in fields(self)})
        return out


def check_table_member(x: np.ndarray, section) -> None:
    """Check a table member: the table aligned with the stations ``x`` (m), no width step."""
    if section.size != x.size:
        raise BeamInputError(
            f"section.EI_y_Nm2 has {section.size} entries: must be aligned with x "
            f"({x.size} entries, one per station)")
    if np.any(np.diff(x) == 0.0):
        i = int(np.flatnonzero(np.diff(x) == 0.0)[0]) + 1
        raise BeamInputError(
            f"x[{i}] = x[{i - 1}] = {x[i]} m: a section table has no steps (its properties "
            "are linear between stations); give each station once")
