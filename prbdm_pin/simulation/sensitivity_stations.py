"""The stations' columns of a trajectory gradient's design derivative, compiled (numba).

The accelerations a(s) solve r(s, a) = tau(s) - M(s) a - h(s) = 0, so their derivative by a
joint station s_j is da/ds_j = M^-1 dr/ds_j at the nominal a, and dr/ds_j is taken as the
central difference of r between the two chains with the station moved by -h and +h (the step:
:mod:`.sensitivity_field`), the tip height's derivative likewise. r needs no factorisation
of the moved chains' mass matrices: M^-1 is the nominal one, from Pinocchio's ABA
derivatives. Every moved chain runs in one compiled call on the chain kernel
(:mod:`prbdm_pin.kernel.dynamics`: kinematics, CRBA, RNEA, J^T F, checked against Pinocchio
in its tests) instead of one ``pin.aba`` call per chain and stage: at 5 stations those ten
calls and their Python overhead were about a third of an all-groups gradient's CPU.

Imported only by a gradient with stations (numba loads with it).
"""

from __future__ import annotations

import numba
import numpy as np

from ..kernel.build import chain_kernel
from ..kernel.dynamics import body_inertias, crba, kinematics, rnea_bias, tip_force_torque

__all__ = ["MovedChains"]


@numba.njit(cache=True)
def _station_columns(jtype, jaxis, Rp, pp, mass, com, Ic, tj, tp, grav, B, two_h,
                     Rw, ow, S, mc, IO, cm, cmc, cIO, V, A, F, M, h, q, v, u, k, beta, c,
                     force, loaded, acc, Minv, r_out, z_out, Fp, dzp, col):
    """Write the stations' columns of d a/dp into Fp[:, col:] and of dz/dp into dzp[col:].

    The moved chains are stacked on the first axis of the kernel arrays (lo_1, hi_1, lo_2,
    ...); the others are one chain's workspace, reused chain after chain. ``acc`` (n,) and
    ``Minv`` (n, n) are the nominal chain's accelerations and inverse mass matrix at (q, v).
    """
    n = q.size
    for i in range(jtype.shape[0]):
        kinematics(jtype[i], jaxis[i], Rp[i], pp[i], q, Rw, ow, S)
        body_inertias(mass[i], com[i], Ic[i], Rw, ow, mc, IO)
        t = tj[i]
        # tip height: the world z of the tip point (the tip frame's rotation plays no part)
        z_out[i] = ow[t, 2] + Rw[t, 2, 0] * tp[i, 0] + Rw[t, 2, 1] * tp[i, 1] \
            + Rw[t, 2, 2] * tp[i, 2]
        for r in range(n):
            s = -k[r] * (q[r] + beta * v[r]) - c[r] * v[r]
            for j in range(u.size):
                s += B[i, r, j] * u[j]
            r_out[i, r] = s
        if loaded:
            tip_force_torque(t, tp[i], Rw, ow, S, force, r_out[i])
        # the residual tau - M a - h of the moved chain at the nominal accelerations
        crba(mass[i], S, mc, IO, cm, cmc, cIO, F, M)
        rnea_bias(mass[i], grav, S, mc, IO, v, V, A, F, h)
        for r in range(n):
            s = r_out[i, r] - h[r]
            for m in range(n):
                s -= M[r, m] * acc[m]
            r_out[i, r] = s
    for j in range(two_h.size):
        dzp[col + j] = (z_out[2 * j + 1] - z_out[2 * j]) / two_h[j]
        for r in range(n):
            s = 0.0
            for m in range(n):
                s += Minv[r, m] * (r_out[2 * j + 1, m] - r_out[2 * j, m])
            Fp[r, col + j] = s / two_h[j]


class MovedChains:
    """The moved chains of every station as stacked kernel arrays, and their workspace.

    Parameters
    ----------
    chains : sequence of (pin.Model, int, ndarray (n, m))
        Per moved chain (lo_1, hi_1, lo_2, ...): its Pinocchio model, tip frame id and inputs
        map B.
    two_h : ndarray (n_s,)
        Twice each station's step, m.
    """

    def __init__(self, chains, two_h: np.ndarray):
        kernels = [chain_kernel(pm, tip) for pm, tip, _ in chains]
        first = kernels[0]
        self.stack = tuple(np.ascontiguousarray(np.stack(a)) for a in zip(
            *[(kn.joint_type, kn.joint_axis, kn.parent_rotation, kn.parent_translation_m,
               kn.mass_kg, kn.com_m, kn.inertia_kg_m2) for kn in kernels], strict=True))
        self.tip_joint = np.array([kn.tip_joint for kn in kernels], dtype=np.int64)
        self.tip_point = np.array([kn.tip_translation_m for kn in kernels])
        self.gravity = np.ascontiguousarray(first.gravity_m_s2, dtype=float)
        self.B = np.ascontiguousarray(np.array([b for _, _, b in chains], dtype=float))
        self.two_h = np.ascontiguousarray(two_h, dtype=float)
        w = first.new_data()
        self.work = (w.rotation, w.origin_m, w.motion_subspace, w.first_moment_kg_m,
                     w.inertia_origin_kg_m2, w.composite_mass_kg, w.composite_first_moment_kg_m,
                     w.composite_inertia_kg_m2, w.velocity, w.acceleration, w.force,
                     w.mass_matrix, w.bias)
        self.a = np.empty((len(kernels), first.n))
        self.z = np.empty(len(kernels))

    def columns(self, q, v, u, k, beta, c, force, loaded, acc, Minv, Fp, dzp, col: int
                ) -> None:
        """Fill the stations' columns (from ``col``) of Fp (n, P) and dzp (P,) at (q, v, u).

        ``acc`` (n,) and ``Minv`` (n, n): the nominal chain's accelerations and M^-1 there.
        """
        _station_columns(*self.stack, self.tip_joint, self.tip_point, self.gravity, self.B,
                         self.two_h, *self.work, q, v, u, k, float(beta), c, force,
                         bool(loaded), acc, Minv, self.a, self.z, Fp, dzp, col)
