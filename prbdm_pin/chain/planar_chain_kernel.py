"""A planar chain of a member of one thickness built in one compiled call (numba).

What a fit evaluation asks of each trial design (:class:`prbdm_pin.fitting.joint.JointResiduals`):
the links' properties (:func:`.planform_kernel.planform_properties`), the finite-segment
springs (:func:`.planform_kernel.segment_springs`), the chain's points at the poses
(:func:`.planar_mass_kernel.points_into`) and its mass matrices there
(:func:`.planar_mass_kernel.mass_from_points`), the same compiled functions called in turn from
compiled code: the same numbers, without four Python wrappers' checks, allocations and
dispatches (about as much time as the arithmetic itself). Imported on first use only.
"""

from __future__ import annotations

import numba

from .planar_mass_kernel import mass_from_points, points_into
from .planform_kernel import planform_properties, segment_springs

__all__ = ["planar_chain"]

_IN1 = numba.types.Array(numba.float64, 1, "A", readonly=True)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_OUT2 = numba.types.Array(numba.float64, 2, "C")
_OUT3 = numba.types.Array(numba.float64, 3, "C")
_OUT4 = numba.types.Array(numba.float64, 4, "C")
_F8 = numba.float64


@numba.njit(numba.types.void(_IN1, _IN1, _F8, _F8, _F8, _F8, _F8, _IN2, _IN2, _OUT3, _OUT2,
                             _OUT3, _OUT4, _OUT4, _OUT4), cache=True)
def planar_chain(xv, hw, length, rho_t, t3_12, t2_12, spring_scale, lengths, Q, props, K0,
                 axes, joints, coms, M):  # pragma: no cover - compiled
    """Fill the properties, springs, points and mass matrices of B designs at the poses Q.

    ``xv`` .. ``t2_12``, ``lengths`` (B, n+1) and ``props`` (12, B, n+1) as
    :func:`.planform_kernel.planform_properties`; ``spring_scale`` and ``K0`` (B, n) as
    :func:`.planform_kernel.segment_springs`; ``Q`` (m, n) rad, ``axes`` (m, 2, n+1),
    ``joints`` and ``coms`` (B, m, 2, n) as :func:`.planar_mass_kernel.points_into`; ``M``
    (B, m, n, n), kg m^2, the mass matrices.
    """
    planform_properties(xv, hw, length, rho_t, t3_12, t2_12, lengths, props)
    segment_springs(xv, hw, spring_scale, lengths, K0)
    points_into(lengths, props[10], Q, axes, joints, coms)
    mass_from_points(joints, coms, props[3], props[11], M)
