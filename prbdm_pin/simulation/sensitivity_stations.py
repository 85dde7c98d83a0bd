"""The stations' columns of a trajectory gradient's design derivative, compiled (numba).

The field's derivative by a joint station s_j is the central difference of its accelerations
and tip height between the two chains with the station moved by -h and +h (the formula and
its step: :mod:`.sensitivity_field`). Here every moved chain's forward dynamics runs in one
compiled call on the chain kernel (:mod:`prbdm_pin.kernel.dynamics`, CRBA, RNEA and Cholesky,
checked against Pinocchio's ABA to 1e-12 in its tests) instead of one Pinocchio call per
chain and stage: at 5 stations the ten ``pin.aba`` calls and their Python overhead were about
a third of an all-groups gradient's CPU.

Imported only by a gradient with stations (numba loads with it).
"""

from __future__ import annotations

import numba
import numpy as np

from ..chain.small_cholesky import cholesky_solve
from ..kernel.build import chain_kernel
from ..kernel.dynamics import body_inertias, crba, kinematics, rnea_bias, tip_force_torque

__all__ = ["MovedChains"]


@numba.njit(cache=True)
def _station_columns(jtype, jaxis, Rp, pp, mass, com, Ic, tj, tp, grav, B, two_h,
                     Rw, ow, S, mc, IO, cm, cmc, cIO, V, A, F, M, L, h, tau, a,
                     q, v, u, k, beta, c, force, loaded, a_out, z_out, Fp, dzp, col):
    """Write the stations' columns of d a/dp into Fp[:, col:] and of dz/dp into dzp[col:].

    The moved chains are stacked on the first axis of the kernel arrays (lo_1, hi_1, lo_2,
    ...); the others are one chain's workspace, reused chain after chain. Returns False when
    a moved chain's mass matrix is not positive definite.
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
            tau[r] = s
        if loaded:
            tip_force_torque(t, tp[i], Rw, ow, S, force, tau)
        crba(mass[i], S, mc, IO, cm, cmc, cIO, F, M)
        rnea_bias(mass[i], grav, S, mc, IO, v, V, A, F, h)
        for r in range(n):
            tau[r] -= h[r]
        if not cholesky_solve(M, L, tau, a):
            return False
        for r in range(n):
            a_out[i, r] = a[r]
    for j in range(two_h.size):
        dzp[col + j] = (z_out[2 * j + 1] - z_out[2 * j]) / two_h[j]
        for r in range(n):
            Fp[r, col + j] = (a_out[2 * j + 1, r] - a_out[2 * j, r]) / two_h[j]
    return True


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
        self.work = first.new_data().arrays()
        self.a = np.empty((len(kernels), first.n))
        self.z = np.empty(len(kernels))

    def columns(self, q, v, u, k, beta, c, force, loaded, Fp, dzp, col: int) -> None:
        """Fill the stations' columns (from ``col``) of Fp (n, P) and dzp (P,) at (q, v, u)."""
        ok = _station_columns(*self.stack, self.tip_joint, self.tip_point, self.gravity,
                              self.B, self.two_h, *self.work, q, v, u, k, float(beta), c,
                              force, bool(loaded), self.a, self.z, Fp, dzp, col)
        if not ok:
            raise FloatingPointError("a moved chain's mass matrix is not positive definite")
