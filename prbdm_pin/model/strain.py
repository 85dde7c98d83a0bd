"""Surface strain at a station: the bending moment there over EI, times half the thickness.

``strain@X`` (microstrain) is the bending strain of the beam's faces at the station ``x`` (m
from the root), from the bending moment M(x) about the section's y axis:

    strain(x) = -M(x) t / (2 E I(x)) * 1e6

with t the thickness, E I(x) the beam's bending stiffness there (the width's right-hand value
at a width step) and M in the sense of the joint angles (a positive M turns the joints
positive, the tip toward -z). Sign: positive for a bending that makes ``tip_z`` positive
(concave toward +z): it is the strain of the -z face (stretched) and minus that of the +z
face (shortened by as much): a gauge on the +z face reads its negative.

The moment along the chain (the definition):

- at joint j it is the elastic moment the joint's spring carries, k_j q_j (the y spring of a
  spatial node): the joint's lumped compliance stands for the beam's curvature around it;
- at the root (x = 0) it is the moment the root transmits, from the root reaction
  (:mod:`prbdm_pin.model.reaction`): M(0) = -R_my, R_m the support's moment on the member
  about the root, its base-frame y component (the root section's axis);
- at the tip (x = L) it is the applied tip moment's component about the tip section's y axis
  (the dead ``tip_moment_*`` inputs; 0 without them);
- between those nodes it is interpolated linearly in x.

Exactness and limits: in statics under loads at the tip (forces, moments) the moment of the
outboard loads about the cut is linear in x between load points, and the chain's springs carry
exactly that moment at the joints (k_j q_j is the moment of the outboard loads about joint j's
axis), so the interpolation is exact: M(x) = F_z (x - L) for a tip force F_z on the straight
member. A distributed load (the weight, the inertia in a vibration) makes M(x) curved between
the joints: the interpolation is its chord, off by about q l^2 / 8 (q the load per length, l
the link) inside a link and exact at the nodes. In a motion the root moment is the whole
transmitted moment (elastic; the root has no damper) while the joints' is the spring's alone
(their dampers' torque k-proportional or modal, carried by the chain but not a strain), and a
pose-dependent stiffness schedule is read at the model's constant springs.
"""

from __future__ import annotations

import numpy as np

from .stations import check_station

__all__ = ["MICROSTRAIN", "strain_terms"]

MICROSTRAIN = 1e6  # per unit strain


def strain_terms(model, x_m: float, field: str) -> tuple[float, float, tuple, float]:
    """Return the strain's composition at station ``x_m`` (m).

    (scale, root weight, ((coordinate, weight), ...), tip weight): strain = scale * (root
    weight * M(0) + sum weight * k q[coordinate] + tip weight * M(L)), scale = -1e6 t / (2 E I)
    in microstrain per N m; the coordinates index the model's velocity vector (the hub first).

    Raises BeamInputError naming ``field`` for a station off the member or a model without its
    beam (no E I, no thickness).
    """
    from ..errors import BeamInputError

    if model.beam is None:
        raise BeamInputError(f"{field}: this model carries no beam (read from a URDF), so no "
                             "E I or thickness to make a strain of")
    x = check_station(model, x_m, field)
    lengths = np.asarray(model.lengths_m, dtype=float)
    L = float(lengths.sum())
    nodes = np.concatenate([[0.0], np.cumsum(lengths)[:-1], [L]])
    i = int(np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2))
    wb = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    weights = {i: 1.0 - wb, i + 1: wb}
    beam = model.beam
    EI = float(beam.material.E_Pa * beam.area_moment_at(x))
    scale = -MICROSTRAIN * float(beam.thickness_at(x)) / (2.0 * EI)
    y_springs = model.axis_index("y") + int(model.hub is not None)
    n = nodes.size - 1  # node n is the tip
    joints = tuple((int(y_springs[k - 1]), w) for k, w in weights.items() if 0 < k < n and w)
    return scale, weights.get(0, 0.0), joints, weights.get(n, 0.0)
