"""Joint springs checked against the beam they are built on."""

from __future__ import annotations

from ..errors import BeamInputError
from ..options.choices import LINK_FLOOR_FRACTION
from ..options.validate import SPRING_WINDOW

__all__ = ["check_springs"]


def check_springs(beam, stiffness_Nm_per_rad) -> None:
    """Check joint springs (N m/rad, validated) against what the beam can hold.

    A finite-segment spring E / int dx / I(x) over a span l lies between E I_min / L (the
    whole beam, its narrowest section) and E I_max / (1e-5 L) (the shortest link a model may
    have, its widest section); a fitted spring is that times a factor. A spring more than
    ``SPRING_WINDOW`` beyond either end is no joint of this beam (a unit slip, or a value meant
    for another model), and its products with the link inertias would leave double precision.
    """
    t3 = beam.thickness_m**3
    E, L = beam.material.E_Pa, beam.length_m
    EI_min = E * 2.0 * float(beam.half_width_m.min()) * t3 / 12.0
    EI_max = E * 2.0 * float(beam.half_width_m.max()) * t3 / 12.0
    lo = EI_min / L / SPRING_WINDOW
    hi = EI_max / (LINK_FLOOR_FRACTION * L) * SPRING_WINDOW
    for i, k in enumerate(stiffness_Nm_per_rad):
        if not lo <= k <= hi:
            raise BeamInputError(
                f"stiffness[{i}] = {float(k):.6g} N m/rad: outside {lo:.3g} ... {hi:.3g} N m/rad,"
                f" {SPRING_WINDOW:g} times beyond the finite-segment springs E I / l of this "
                f"beam (E I = {EI_min:.3g} ... {EI_max:.3g} N m^2, l = {LINK_FLOOR_FRACTION:g} L"
                f" ... L = {L:.6g} m); springs in N mm/rad, or of another model?")
