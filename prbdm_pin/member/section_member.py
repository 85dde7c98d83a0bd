"""Build a round member (rod or tube) or a table member: a :class:`Beam` with a section law."""

from __future__ import annotations

import numpy as np

from .checks import float_array
from .geometry import Beam
from .material import Material
from .round_section import RoundSection
from .section_table import SectionTable

__all__ = ["round_beam", "table_beam"]


def round_beam(x_m, outer_diameter_m, inner_diameter_m=None, material: Material | None = None,
               tip_force_N=None, name: str = "beam", description: str = "") -> Beam:
    """Return a clamped-free round member with diameters linear between stations.

    Parameters
    ----------
    x_m : array_like, shape (k,)
        Stations, m: 0 at the clamp, strictly increasing to L.
    outer_diameter_m : array_like, shape (k,)
        Outer diameter D at each station, m, > 0.
    inner_diameter_m : array_like, shape (k,), optional
        Inner diameter d at each station, m, in [0, D); None: a solid rod.
    material : Material, optional
        Default steel AISI 4340.
    tip_force_N : array_like, shape (3,), optional
        The load case at the tip, N; default none.
    name, description : str

    Returns
    -------
    Beam
        With ``section`` the :class:`RoundSection`, half-width the outer radius D / 2 and
        thickness the outer diameter D (m).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.round_beam([0.0, 1.0], [0.02, 0.02], [0.016, 0.016])  # a steel tube, m
    >>> area = np.pi / 4 * (0.02**2 - 0.016**2)  # m^2
    >>> round(beam.mass_kg, 5), round(7850.0 * area * 1.0, 5)  # kg, rho A L
    (0.88781, 0.88781)
    >>> EI = pp.section_properties(beam, 0.0).EI_y_Nm2  # N m^2
    >>> round(float(EI), 2), round(205e9 * np.pi / 64 * (0.02**4 - 0.016**4), 2)  # E I
    (950.58, 950.58)
    """
    section = RoundSection(outer_diameter_m, inner_diameter_m)
    D = section.outer_diameter_m
    x = float_array("x", x_m, "m")
    if x.size != D.size:  # named here, before the planform would report it as half_width
        from ..errors import BeamInputError

        raise BeamInputError(
            f"section.outer_diameter has {D.size} entries: must be aligned with x "
            f"({x.size} entries, one diameter per station)")
    steps = np.flatnonzero(np.diff(x) == 0.0)
    if steps.size:  # before the thickness law would call it a thickness jump
        from ..errors import BeamInputError

        i = int(steps[0]) + 1
        raise BeamInputError(
            f"x[{i}] = x[{i - 1}] = {x[i]} m: a round member has no width steps (the "
            "diameters are continuous); give each station once")
    thickness = float(D[0]) if np.all(D == D[0]) else D.copy()
    return Beam(x, 0.5 * D, thickness, Material() if material is None else material,
                np.zeros(3) if tip_force_N is None else tip_force_N, name, description,
                section=section)


def table_beam(x_m, section: SectionTable, material: Material | None = None, tip_force_N=None,
               name: str = "beam", description: str = "") -> Beam:
    """Return a clamped-free member known by its section table.

    Parameters
    ----------
    x_m : array_like, shape (k,)
        Stations, m: 0 at the clamp, strictly increasing to L.
    section : SectionTable
        The properties at the stations (N m^2, kg/m, kg m), linear between them.
    material : Material, optional
        Only its E converts E I_y to the area moment the paper-style springs use (no result
        depends on it); default steel AISI 4340.
    tip_force_N : array_like, shape (3,), optional
        The load case at the tip, N; default none.
    name, description : str

    Returns
    -------
    Beam
        With ``section`` the table; half-width and thickness those of the square of the same
        area moment E I_y / E (side (12 E I_y / E)^(1/4), m, clipped into the size range),
        for the size checks only.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> E, b, t, rho = 205e9, 0.05, 0.01, 7850.0  # Pa, m, m, kg/m^3: a steel strip
    >>> I_y, I_z = b * t**3 / 12, t * b**3 / 12  # m^4
    >>> table = pp.SectionTable(EI_y_Nm2=[E * I_y] * 2, EI_z_Nm2=[E * I_z] * 2,
    ...                         GJ_Nm2=[80e9 * b * t**3 / 3] * 2, rhoA_kg_m=[rho * b * t] * 2,
    ...                         rhoI_y_kg_m=[rho * I_y] * 2, rhoI_z_kg_m=[rho * I_z] * 2)
    >>> beam = pp.table_beam([0.0, 1.0], table)
    >>> round(beam.mass_kg, 4), round(rho * b * t * 1.0, 4)  # kg, rho b t L
    (3.925, 3.925)
    >>> strip = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> w_table = pp.build_model(beam, [0.5, 0.5], [2000.0]).natural_frequencies()
    >>> w_strip = pp.build_model(strip, [0.5, 0.5], [2000.0]).natural_frequencies()
    >>> w_table.round(2), w_strip.round(2)  # rad/s: the table of the strip, the strip
    (array([110.58]), array([110.58]))
    """
    from ..options.validate import SIZE_RANGE_M, check_type

    check_type("section", section, SectionTable)
    material = Material() if material is None else material
    check_type("material", material, Material)
    x = float_array("x", x_m, "m")
    if x.size != section.size:
        from ..errors import BeamInputError

        raise BeamInputError(
            f"section.EI_y_Nm2 has {section.size} entries: must be aligned with x "
            f"({x.size} entries, one per station)")
    # placeholders for the planform's size checks only: kept inside their range, so that a
    # soft or stiff table is never refused under the name "thickness" it does not have
    lo, hi = SIZE_RANGE_M
    top = min(hi, 10.0 * abs(float(x[-1]))) if x.size else hi  # the width ratio's bound: 20 L
    side = np.clip((12.0 * section.EI_y_Nm2 / material.E_Pa) ** 0.25, 2.0 * lo, max(top, 2 * lo))
    thickness = float(side[0]) if np.all(side == side[0]) else side
    return Beam(x, 0.5 * side, thickness, material,
                np.zeros(3) if tip_force_N is None else tip_force_N, name, description,
                section=section)
