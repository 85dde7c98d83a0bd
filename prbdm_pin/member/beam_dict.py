"""The beam-JSON mapping of a :class:`~prbdm_pin.member.geometry.Beam` (SI units)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .geometry import Beam

__all__ = ["beam_to_dict"]


def beam_to_dict(beam: Beam) -> dict[str, Any]:
    """Return the beam-JSON mapping of ``beam`` (SI units)."""
    m = beam.material
    out = {
        "name": beam.name,
        "description": beam.description,
        "length": beam.length_m,
        "x": [float(v) for v in beam.x_m],
        "half_width": [float(v) for v in beam.half_width_m],
        "thickness": (beam.thickness_m if beam.thickness_law_m is None
                      else [float(v) for v in beam.thickness_law_m]),
        "material": {"name": m.name, "E": m.E_Pa, "rho": m.rho_kg_m3, "nu": m.nu},
        "tip_force": [float(v) for v in beam.tip_force_N],
    }
    if beam.section is not None:  # the section replaces the planform's half_width, thickness
        del out["half_width"], out["thickness"]
        out["section"] = beam.section.to_dict()
    return out

