"""The size of a truth mesh before it is built: a mesh above ``limits().max_mesh_dofs`` is refused.

A planform with nanometre features (a vertex interval, a neck or a thickness of 1e-9 m) makes the
graded meshes of ``truth.mesh`` and ``truth.feature_mesh`` enormous: gigabytes and minutes
before any eigensolve. The plate's DOFs are estimated from its mesh-sizing rule (the x stations'
element counts, then the column points across each half-width), the solid's from a lower bound
(its element size never exceeds the level's base size), both without building anything large;
after meshing the exact count is checked again before any basis or matrix exists.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.limits import check_cap, limits
from .mesh import element_size, local_size, station_count, x_stations

__all__ = ["PLATE_DOFS_PER_EDGE", "PLATE_DOFS_PER_NODE", "check_dofs", "check_plate_budget",
           "check_solid_budget", "estimate_plate_dofs", "smallest_feature"]

# element DOFs: Argyris 6 per vertex (w, its gradient and Hessian) + 1 per edge; Morley 1 + 1
PLATE_DOFS_PER_NODE = {"argyris": 6, "morley": 1}
PLATE_DOFS_PER_EDGE = 1
# a triangulation has about 3 edges per node
_EDGES_PER_NODE = 3.0
# the solid's 27-node hexahedra, one through the thickness: 9 (vertices + edges + faces) of the
# quadrilateral mesh; each triangle of the feature mesh makes 3 quadrilaterals, and an
# equilateral triangle of side h covers sqrt(3) / 4 h^2
SOLID_DOFS_PER_AREA = 9.0 * 3.0 * 3.0 / (np.sqrt(3.0) / 4.0)


def smallest_feature(beam: Beam) -> str:
    """Return the beam's smallest in-plane feature, for messages."""
    dx = np.diff(beam.x_m)
    dx = dx[dx > 0.0]
    k = int(np.argmin(beam.half_width_m))
    return (f"shortest vertex interval {dx.min():.3g} m, narrowest half_width[{k}] = "
            f"{beam.half_width_m[k]:.3g} m, thickness {beam.thickness_m:.3g} m")


def _refuse(what: str, dofs: float, beam: Beam) -> None:
    try:
        check_cap(what, dofs, "max_mesh_dofs")
    except BeamInputError as exc:
        raise BeamInputError(f"{beam.name!r}: {exc}; the mesh follows the beam's smallest "
                             f"features ({smallest_feature(beam)})") from None


def estimate_plate_dofs(beam: Beam, level: int, element: str = "argyris") -> int:
    """DOFs of the plate mesh ``planform_tri_mesh(beam, level)`` estimated from its sizing rule.

    An underestimate (0.3-0.9 of the built mesh on the shipped and random beams: corner
    refinement and outline points come on top), so it never refuses a mesh within the cap; the
    built mesh's exact count is checked too. Costs O(vertices^2) and allocates nothing per
    station when the station count alone exceeds the cap.
    """
    h = element_size(beam, 0)
    per_node = PLATE_DOFS_PER_NODE[element] + PLATE_DOFS_PER_EDGE * _EDGES_PER_NODE
    n_st = station_count(beam, h, 0.3, narrow=True)
    # every station carries at least an axis node and an outline node on each side
    lower = 4**level * 3.0 * n_st * per_node
    if lower > limits().max_mesh_dofs:
        return int(min(lower, 1e18))
    xs = x_stations(beam, h, 0.3, narrow=True)
    sizes = local_size(beam, h, 0.3, xs, narrow=True)
    w = np.minimum(beam.half_width_at(xs, "left"), beam.half_width_at(xs, "right"))
    columns = np.maximum(1.0, np.ceil(w / sizes - 0.25)).sum()
    nodes_up = columns + xs.size  # column points + about one outline point per station
    nodes = 2.0 * nodes_up - xs.size  # mirrored; the axis is shared
    return int(4**level * nodes * per_node)


def check_plate_budget(beam: Beam, level: int, element: str = "argyris") -> None:
    """BeamInputError when the plate mesh at ``level`` would exceed ``max_mesh_dofs``."""
    dofs = estimate_plate_dofs(beam, level, element)
    if dofs > limits().max_mesh_dofs:
        _refuse(f"mesh DOFs (plate, level {level}, estimated before meshing)", dofs, beam)


def check_solid_budget(beam: Beam, level: int) -> None:
    """Refuse (BeamInputError) a solid mesh at ``level`` that must exceed ``max_mesh_dofs``.

    Its in-plane size is at most 2 L / (10 2^level) everywhere, which bounds its DOFs from
    below.
    """
    h = 2.0 * element_size(beam, level)
    dofs = SOLID_DOFS_PER_AREA * beam.planform_area_m2 / h**2
    if dofs > limits().max_mesh_dofs:
        _refuse(f"mesh DOFs (solid, level {level}, at least, estimated before meshing)", dofs,
                beam)


def check_dofs(model: str, level: int, dofs: int, beam: Beam) -> None:
    """BeamInputError when a built mesh has more than ``max_mesh_dofs`` DOFs."""
    if dofs > limits().max_mesh_dofs:
        _refuse(f"mesh DOFs ({model}, level {level})", dofs, beam)
