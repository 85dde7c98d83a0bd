"""The section law along x of any member: stiffnesses and inertias per unit length.

One place answers "what is the section at x" for the three kinds of member, so every model
(links, springs, the 1D truths) reads the same numbers:

- the planform rectangle 2 w(x) x t(x) (``Beam.section`` None), from
  :mod:`~prbdm_pin.member.section`: I_y = b t^3 / 12, I_z = t b^3 / 12, the exact Saint-Venant J;
- a round section (:class:`~prbdm_pin.member.round_section.RoundSection`): I_y = I_z =
  pi (D^4 - d^4) / 64, J = 2 I_y (a circle does not warp);
- a section table (:class:`~prbdm_pin.member.section_table.SectionTable`): its stations'
  values, linear between them.

Axes as in :mod:`~prbdm_pin.member.section`: x along, y across the width, z through the
thickness; ``EI_y_Nm2`` is the out-of-plane bending stiffness (the planar chain's). The rotary
inertias per length are rho I_y (about y: the z^2 moment), rho I_z (about z: the y^2 moment)
and rho I_x (about the axis).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .round_section import RoundSection, round_area_m2, round_area_moment_m4
from .section import area_moment_y_m4, area_moment_z_m4, torsion_constant_m4

if TYPE_CHECKING:
    from .geometry import Beam

__all__ = ["SectionProperties", "section_properties"]


@dataclass(frozen=True, eq=False)
class SectionProperties:
    """Section stiffnesses and inertias per unit length at stations x (arrays, x's shape).

    Attributes
    ----------
    EI_y_Nm2, EI_z_Nm2 : ndarray
        Bending stiffness about y (out of plane) and about z (in plane), N m^2.
    GJ_Nm2 : ndarray
        Saint-Venant torsional stiffness, N m^2.
    rhoA_kg_m : ndarray
        Mass per unit length, kg/m.
    rhoI_x_kg_m, rhoI_y_kg_m, rhoI_z_kg_m : ndarray
        Rotary inertia per unit length about x (the axis), y and z, kg m.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> props = pp.section_properties(beam, [0.0, 0.5])
    >>> isinstance(props, pp.SectionProperties), props.EI_y_Nm2.shape
    (True, (2,))
    >>> props.rhoA_kg_m.round(4), round(7850.0 * 0.05 * 0.01, 4)  # kg/m, rho b t
    (array([3.925, 3.925]), 3.925)
    """

    EI_y_Nm2: np.ndarray
    EI_z_Nm2: np.ndarray
    GJ_Nm2: np.ndarray
    rhoA_kg_m: np.ndarray
    rhoI_x_kg_m: np.ndarray
    rhoI_y_kg_m: np.ndarray
    rhoI_z_kg_m: np.ndarray


def _round(section: RoundSection, xv: np.ndarray, x: np.ndarray, E: float, G: float,
           rho: float) -> SectionProperties:
    D = np.interp(x, xv, section.outer_diameter_m)
    d = np.interp(x, xv, section.inner_diameter_m)
    moment = round_area_moment_m4(D, d)
    return SectionProperties(
        EI_y_Nm2=E * moment, EI_z_Nm2=E * moment, GJ_Nm2=G * 2.0 * moment,
        rhoA_kg_m=rho * round_area_m2(D, d), rhoI_x_kg_m=rho * 2.0 * moment,
        rhoI_y_kg_m=rho * moment, rhoI_z_kg_m=rho * moment)


def _rectangle(beam: Beam, x: np.ndarray, side: str, E: float, G: float,
               rho: float) -> SectionProperties:
    b = 2.0 * np.asarray(beam.half_width_at(x, side), dtype=float)
    t = np.asarray(beam.thickness_at(x), dtype=float)
    Iy, Iz = area_moment_y_m4(b, t), area_moment_z_m4(b, t)
    return SectionProperties(
        EI_y_Nm2=E * Iy, EI_z_Nm2=E * Iz, GJ_Nm2=G * torsion_constant_m4(b, t),
        rhoA_kg_m=rho * b * t, rhoI_x_kg_m=rho * (Iy + Iz), rhoI_y_kg_m=rho * Iy,
        rhoI_z_kg_m=rho * Iz)


def section_properties(beam: Beam, x_m: np.ndarray | float,
                       side: str = "right") -> SectionProperties:
    """Return the section's stiffnesses and inertias per length at stations ``x_m``.

    Parameters
    ----------
    beam : Beam
        Any member: planform rectangle, round section or section table.
    x_m : array_like or float
        Stations along the axis, m, within [0, L].
    side : {"right", "left"}
        At a planform's width step, the tip-side or root-side section (as
        :meth:`Beam.half_width_at`); round and table laws are continuous.

    Returns
    -------
    SectionProperties
        Arrays of the shape of ``x_m``: N m^2 for stiffnesses, kg/m and kg m per length.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.05, 0.025], thickness_m=0.01)  # a taper
    >>> props = pp.section_properties(beam, [0.0, 0.5, 1.0])
    >>> (props.EI_y_Nm2 / 1e3).round(3)  # kN m^2
    array([1.708, 1.281, 0.854])
    >>> b = np.array([0.1, 0.075, 0.05])  # m, the width at the stations
    >>> (205e9 * b * 0.01**3 / 12 / 1e3).round(3)  # E b t^3 / 12, kN m^2
    array([1.708, 1.281, 0.854])
    >>> props.rhoA_kg_m.round(4), (7850.0 * b * 0.01).round(4)  # kg/m, rho b t
    (array([7.85  , 5.8875, 3.925 ]), array([7.85  , 5.8875, 3.925 ]))
    """
    from .geometry import Beam  # at call time: geometry imports this module

    if not isinstance(beam, Beam):
        from ..options.validate import check_type

        check_type("beam", beam, Beam)
    x = np.asarray(x_m, dtype=float)
    mat = beam.material
    section = beam.section
    if section is None:
        return _rectangle(beam, x, side, mat.E_Pa, mat.G_Pa, mat.rho_kg_m3)
    if isinstance(section, RoundSection):
        return _round(section, beam.x_m, x, mat.E_Pa, mat.G_Pa, mat.rho_kg_m3)
    return section.at(beam.x_m, x)  # a SectionTable: its own values, linear in x
