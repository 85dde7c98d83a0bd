"""Joint springs checked against the beam they are built on."""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..member.section import area_moment_z_m4, torsion_constant_m4
from ..member.section_law import section_properties
from ..options.choices import LINK_FLOOR_FRACTION
from ..options.validate import SPRING_WINDOW

__all__ = ["check_springs", "check_spatial_springs"]


def check_springs(beam, stiffness_Nm_per_rad) -> None:
    """Check joint springs (N m/rad, validated) against what the beam can hold.

    A finite-segment spring E / int dx / I(x) over a span l lies between E I_min / L (the
    whole beam, its narrowest section) and E I_max / (1e-5 L) (the shortest link a model may
    have, its widest section); a fitted spring is that times a factor. A spring more than
    ``SPRING_WINDOW`` beyond either end is no joint of this beam (a unit slip, or a value meant
    for another model), and its products with the link inertias would leave double precision.
    """
    E, L = beam.material.E_Pa, beam.length_m
    if beam.section is not None:  # the section law at the stations (linear D, d: its extremes)
        EI = E * beam.area_moment_at(beam.x_m)
        EI_min, EI_max = float(EI.min()), float(EI.max())
    elif beam.thickness_law_m is None:
        t3 = beam.thickness_m**3
        EI_min = E * 2.0 * float(beam.half_width_m.min()) * t3 / 12.0
        EI_max = E * 2.0 * float(beam.half_width_m.max()) * t3 / 12.0
    else:  # the sections at the stations bound the window (it is SPRING_WINDOW wide anyway)
        EI = E * 2.0 * beam.half_width_m * beam.thickness_law_m**3 / 12.0
        EI_min, EI_max = float(EI.min()), float(EI.max())
    lo = EI_min / L / SPRING_WINDOW
    hi = EI_max / (LINK_FLOOR_FRACTION * L) * SPRING_WINDOW
    for i, k in enumerate(stiffness_Nm_per_rad):
        if not lo <= k <= hi:
            raise BeamInputError(
                f"stiffness[{i}] = {float(k):.6g} N m/rad: outside {lo:.3g} ... {hi:.3g} N m/rad,"
                f" {SPRING_WINDOW:g} times beyond the finite-segment springs E I / l of this "
                f"beam (E I = {EI_min:.3g} ... {EI_max:.3g} N m^2, l = {LINK_FLOOR_FRACTION:g} L"
                f" ... L = {L:.6g} m); springs in N mm/rad, or of another model?")


def check_spatial_springs(beam, stiffness_Nm_per_rad, axes) -> None:
    """Check a spatial chain's springs (N m/rad, node-major), each against its own axis.

    Each spring must lie within ``SPRING_WINDOW`` of the window its axis's section stiffness
    gives (E I_y, E I_z or G J over the span from the shortest link to the whole member), as
    :func:`check_springs` does for bending about y.
    """
    E, G, L = beam.material.E_Pa, beam.material.G_Pa, beam.length_m
    if beam.section is not None:  # the section law at the stations: its extremes
        sp = section_properties(beam, beam.x_m)
        section = {"y": sp.EI_y_Nm2, "z": sp.EI_z_Nm2, "x": sp.GJ_Nm2}
    else:
        b = 2.0 * beam.half_width_m
        t = beam.uniform_thickness_m("the spring checks")
        section = {
            "y": E * b * t**3 / 12.0,
            "z": E * area_moment_z_m4(b, t),
            "x": G * torsion_constant_m4(b, t),
        }
    order = axes.joint_order
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    for i, ki in enumerate(k):
        a = order[i % len(order)]
        s_min, s_max = float(np.min(section[a])), float(np.max(section[a]))
        lo = s_min / L / SPRING_WINDOW
        hi = s_max / (LINK_FLOOR_FRACTION * L) * SPRING_WINDOW
        if not lo <= ki <= hi:
            what = {"y": "E I_y", "z": "E I_z", "x": "G J"}[a]
            raise BeamInputError(
                f"stiffness[{i}] = {float(ki):.6g} N m/rad (joint {i // len(order) + 1}, axis "
                f"{a}): outside {lo:.3g} ... {hi:.3g} N m/rad, {SPRING_WINDOW:g} times beyond "
                f"the finite-segment springs {what} / l of this beam ({what} = {s_min:.3g} ... "
                f"{s_max:.3g} N m^2); springs in N mm/rad, or in another order (node-major: "
                f"{', '.join(order)} at each joint)?")
