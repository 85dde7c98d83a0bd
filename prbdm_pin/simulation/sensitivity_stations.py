"""The stations' columns of a trajectory gradient's design derivative, compiled (numba).

The columns are central differences of the vector field between the two chains with a joint
station moved by -h and +h (the step: :mod:`.sensitivity_field`), all moved chains in one
compiled call per stage instead of one ``pin.aba`` call per chain and stage (at 5 stations
those ten calls and their Python overhead were about a third of an all-groups gradient's CPU).
Two evaluators:

- :class:`PlanarMovedChains`, for the chains ``build_model`` gives (clamped, planar, no
  gravity, centres of mass on the links' axes): the moved chains' accelerations and tip
  heights by the batched simulation's planar closed forms
  (:mod:`prbdm_pin.chain.planar_batch_kernel`), differenced;
- :class:`MovedChains`, for any other serial chain: a(s) solves r(s, a) = tau(s) - M(s) a -
  h(s) = 0, so da/ds_j = M^-1 dr/ds_j at the nominal a, with dr/ds_j the central difference
  of r on the general kernel (:mod:`prbdm_pin.kernel.dynamics`: kinematics, CRBA, RNEA,
  J^T F) and M^-1 the nominal chain's from Pinocchio's ABA derivatives (no factorisation of
  the moved chains).

Both are the same derivative to the difference's truncation, O(h^2) (about 1e-10 of the
accelerations); the tests check both against central differences of Pinocchio's ABA on
rebuilt models.

Imported only by a gradient with stations (numba loads with it).
"""

from __future__ import annotations

import math

import numba
import numpy as np

# the batched simulation's compiled planar accelerations, called from compiled code here
from ..chain.planar_batch_kernel import block_rates, mass_rows, param_rows, scratch_rows
from ..kernel.build import chain_kernel
from ..kernel.dynamics import body_inertias, crba, kinematics, rnea_bias, tip_force_torque
from .sensitivity_kernel import joint_torque

__all__ = ["MovedChains", "PlanarMovedChains"]


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
            r_out[i, r] = joint_torque(r, q, v, u, k, beta, c, B[i])
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


@numba.njit(cache=True)
def _planar_station_columns(P, ou, K, Bm, L, q, v, u, beta, c, x, out, S, ft, ut, T, z_out,
                            two_h, Fp, dzp, col):
    """Write the stations' columns from the moved chains' accelerations, planar closed forms.

    One column per moved chain (lo_1, hi_1, lo_2, ...) of the batched kernel's constants ``P``
    (:func:`~prbdm_pin.chain.planar_batch_kernel.param_rows`, the torques other than the
    springs' as inputs of unit map at row ``ou``), of the springs ``K``, inputs maps ``Bm`` and
    link lengths ``L`` (rows alike); ``x``, ``out``, ``S``, ``z_out`` scratch, ``ft``, ``ut``,
    ``T`` zeros. The columns are the central differences of the accelerations and tip heights
    between each station's pair.
    """
    n = q.size
    for i in range(x.shape[1]):
        phi, z = 0.0, 0.0
        for r in range(n):
            x[r, i] = q[r]
            x[n + r, i] = v[r]
            s = -(beta * K[i, r] + c[r]) * v[r]
            for j in range(u.size):
                s += Bm[i, r, j] * u[j]
            P[ou + r, i] = s
            phi += q[r]
            z -= L[i, r + 1] * math.sin(phi)
        z_out[i] = z
    block_rates(P, n, n, False, False, ft, ut, T, x, out, S)
    for j in range(two_h.size):
        dzp[col + j] = (z_out[2 * j + 1] - z_out[2 * j]) / two_h[j]
        for r in range(n):
            Fp[r, col + j] = (out[n + r, 2 * j + 1] - out[n + r, 2 * j]) / two_h[j]


class PlanarMovedChains:
    """The moved chains of every station in the planar closed forms, and their workspace.

    The planar chains the package builds (clamped, no gravity, centres of mass on the links'
    axes: :func:`prbdm_pin.chain.planar_batch.design_links`) take the batched simulation's
    compiled accelerations (:mod:`prbdm_pin.chain.planar_batch_kernel`: the closed-form M, h
    and J^T F and an L D L^T solve, the chains as SIMD lanes), a fraction of the arithmetic of
    the general kernel's kinematics, CRBA and RNEA per chain.

    Parameters
    ----------
    links : PlanarLinks
        The moved chains (lo_1, hi_1, lo_2, ...).
    B : ndarray (c, n, m)
        Their inputs maps.
    k : ndarray (n,)
        The joint springs, N m/rad.
    force : ndarray (3,)
        The tip force, N.
    two_h : ndarray (n_s,)
        Twice each station's step, m.
    """

    def __init__(self, links, B, k, force, two_h):
        c, n = links.mass_kg.shape
        self.L = np.ascontiguousarray(links.lengths_m, dtype=float)
        self.K = np.tile(np.asarray(k, dtype=float), (c, 1))
        self.B = np.ascontiguousarray(B, dtype=float).reshape(c, n, -1)
        rows = param_rows(n, n, False, False)
        P = np.zeros((rows["end"], c))
        Ma, Mb = mass_rows(links)
        for name, a in (("L", links.lengths_m), ("mass", links.mass_kg),
                        ("off", links.com_offset_m), ("Ma", Ma), ("Mb", Mb), ("k", self.K)):
            P[rows[name]:rows[name] + a.shape[1]] = a.T
        P[rows["F"]:rows["F"] + 3] = np.asarray(force, dtype=float)[:, None]
        P[rows["B0"]:rows["B0"] + n * n] = np.eye(n).reshape(n * n, 1)
        self.P, self.ou = P, rows["u0"]
        self.two_h = np.array(two_h, dtype=float)
        self.x, self.out = np.empty((2 * n, c)), np.empty((2 * n, c))
        self.S, self.z = np.empty((scratch_rows(n, n), c)), np.empty(c)
        self.zeros = (np.zeros(3), np.zeros(n), np.zeros((3, n)))

    def columns(self, q, v, u, k, beta, c, force, loaded, acc, Minv, Fp, dzp, col: int
                ) -> None:
        """Fill the stations' columns as :meth:`MovedChains.columns` does.

        ``k`` and ``force`` were fixed at construction, ``loaded`` is read from the force
        (zero rows add nothing) and ``acc``, ``Minv`` are not needed.
        """
        _planar_station_columns(self.P, self.ou, self.K, self.B, self.L, q, v, u, float(beta), c,
                                self.x, self.out, self.S, *self.zeros, self.z, self.two_h, Fp,
                                dzp, col)
