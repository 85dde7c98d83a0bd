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

import math

import numba
import numpy as np

from .planar_mass_kernel import mass_from_points, points_into
from .planar_statics_kernel import planar_newton_tip
from .planform_kernel import planform_properties, segment_springs
from .small_eigen import scaled_omega

__all__ = ["planar_chain", "planar_chain_evaluation"]

_IN1 = numba.types.Array(numba.float64, 1, "A", readonly=True)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_OUT2 = numba.types.Array(numba.float64, 2, "C")
_OUT3 = numba.types.Array(numba.float64, 3, "C")
_OUT4 = numba.types.Array(numba.float64, 4, "C")
_F8 = numba.float64
_OUT1 = numba.types.Array(numba.float64, 1, "C")
_FLAGS = numba.types.Array(numba.boolean, 1, "C")


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


@numba.njit(numba.types.void(_IN1, _IN1, _F8, _F8, _F8, _F8, _F8, _IN2, _IN2, _IN1, _IN2, _IN2,
                             _F8, numba.int64, _F8, _F8, _F8, _OUT3, _OUT2, _OUT1, _OUT3, _OUT4,
                             _OUT4, _OUT4, _OUT1, _OUT2, _OUT2, _FLAGS), cache=True)
def planar_chain_evaluation(xv, hw, length, rho_t, t3_12, t2_12, spring_scale, lengths, Q,
                            factors, forces, starts, rtol, max_iter, max_step, cond_limit,
                            safe_scale, props, K0, K, axes, joints, coms, M, omega, q, tips,
                            ok):  # pragma: no cover - compiled
    """:func:`planar_chain` of one design (B = 1) at one pose, its frequencies and equilibria.

    After :func:`planar_chain`: the springs ``K`` (n,) = ``factors`` K0, N m/rad; the pose's
    frequencies into ``omega`` (n,), rad/s, by :func:`.small_eigen.scaled_omega` (the lower
    triangle, as the fits' stack of one is read); for each load case c (``forces`` (c, 2),
    the tip force's x and z, N) the descent of :func:`.planar_statics_kernel.planar_newton_tip`
    from ``starts[c]`` (rad) into ``q[c]`` and ``tips[c]`` (m). ``ok`` (1 + c) says which
    answered: False leaves that part to the caller's checked path (the spectrum's guard, the
    numpy descent), as a case with no in-plane force is (not solved here).
    """
    planar_chain(xv, hw, length, rho_t, t3_12, t2_12, spring_scale, lengths, Q, props,
                 K0, axes, joints, coms, M)
    n = K.size
    s = np.empty(n)
    for j in range(n):
        K[j] = factors[j] * K0[0, j]
        s[j] = 1.0 / math.sqrt(K[j])
    ok[0] = scaled_omega(M[0, 0], s, np.empty(0), omega, False, True, cond_limit, safe_scale)
    for c in range(forces.shape[0]):
        ok[c + 1] = False
        if forces[c, 0] != 0.0 or forces[c, 1] != 0.0:
            for j in range(n):
                q[c, j] = starts[c, j]
            ok[c + 1] = planar_newton_tip(lengths[0], K, forces[c, 0], forces[c, 1], rtol,
                                          max_iter, max_step, q[c], tips[c])
