"""Compiled accelerations of B planar chains at their own states (numba), one design per row.

The batched simulation's right-hand side spends its time here: per design, the closed forms of
:mod:`.planar_batch` (M(q), the Coriolis/centrifugal forces h, J^T F) and a Cholesky solve of
M a = tau - h + J^T F, in one compiled loop over the designs (numpy over the batch axis made
some thirty array calls per evaluation, each a pass over the batch). numba is imported by this
module only, which :mod:`prbdm_pin.simulation.batch_rhs` imports on first use.

With p_k the joints and c_i the centres of mass (xz-plane, z flipped as in
:mod:`.planar_mass`), the entries of M for j <= k are computed about joint k, free of the
cancellation of absolute coordinates:

    M_jk = S_k + (p_k - p_j) . T_k,  S_k = sum_(i >= k) m_i |c_i - p_k|^2 + I_i,
                                      T_k = sum_(i >= k) m_i (c_i - p_k).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["batch_accelerations"]


@numba.njit(cache=True, error_model="numpy")
def _batch(L, mass, off, iyy, Q, V, tau, F, out):  # pragma: no cover - compiled
    # one flat loop, scratch allocated once: a helper taking row views per design cost as much
    # as the arithmetic (each view is reference-counted)
    B, n = Q.shape
    M = np.empty((n, n))
    px, pz, cx, cz = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    co, si, ax, az, w2, rhs = (np.empty(n), np.empty(n), np.empty(n), np.empty(n),
                               np.empty(n), np.empty(n))
    for b in range(B):
        phi = 0.0
        w = 0.0
        for i in range(n):
            phi += Q[b, i]
            co[i] = math.cos(phi)
            si[i] = math.sin(phi)
            w += V[b, i]
            w2[i] = w * w
        px[0], pz[0], jx, jz = L[b, 0], 0.0, 0.0, 0.0
        for i in range(n):
            if i > 0:
                px[i] = px[i - 1] + L[b, i] * co[i - 1]
                pz[i] = pz[i - 1] + L[b, i] * si[i - 1]
                jx -= L[b, i] * w2[i - 1] * co[i - 1]
                jz -= L[b, i] * w2[i - 1] * si[i - 1]
            cx[i] = px[i] + off[b, i] * co[i]
            cz[i] = pz[i] + off[b, i] * si[i]
            # the centre of mass's acceleration at zero joint accelerations, times its mass
            ax[i] = mass[b, i] * (jx - off[b, i] * w2[i] * co[i])
            az[i] = mass[b, i] * (jz - off[b, i] * w2[i] * si[i])
        # from the tip down: h_j = sum_(i >= j) (c_i - p_j) x m_i a_i; J^T F by lever arms
        t_cxa, t_ax, t_az, rc, rs = 0.0, 0.0, 0.0, 0.0, 0.0
        fx, fz = F[b, 0], F[b, 2]
        for j in range(n - 1, -1, -1):
            t_cxa += cx[j] * az[j] - cz[j] * ax[j]
            t_ax += ax[j]
            t_az += az[j]
            rc += L[b, j + 1] * co[j]
            rs += L[b, j + 1] * si[j]
            rhs[j] = tau[b, j] - (t_cxa - (px[j] * t_az - pz[j] * t_ax)) - fx * rs - fz * rc
        for k in range(n):
            s, tx, tz = 0.0, 0.0, 0.0
            for i in range(k, n):
                dx, dz = cx[i] - px[k], cz[i] - pz[k]
                s += mass[b, i] * (dx * dx + dz * dz) + iyy[b, i]
                tx += mass[b, i] * dx
                tz += mass[b, i] * dz
            for j in range(k + 1):
                M[k, j] = s + (px[k] - px[j]) * tx + (pz[k] - pz[j]) * tz
        # Cholesky M = G G^T in the lower triangle, then the two triangular solves
        for j in range(n):
            d = M[j, j]
            for p in range(j):
                d -= M[j, p] * M[j, p]
            d = math.sqrt(d)
            M[j, j] = d
            for i in range(j + 1, n):
                e = M[i, j]
                for p in range(j):
                    e -= M[i, p] * M[j, p]
                M[i, j] = e / d
        for i in range(n):
            e = rhs[i]
            for p in range(i):
                e -= M[i, p] * out[b, p]
            out[b, i] = e / M[i, i]
        for i in range(n - 1, -1, -1):
            e = out[b, i]
            for p in range(i + 1, n):
                e -= M[p, i] * out[b, p]
            out[b, i] = e / M[i, i]


def batch_accelerations(links, Q: np.ndarray, V: np.ndarray, tau_Nm: np.ndarray,
                        force_N: np.ndarray | None) -> np.ndarray:
    """Joint accelerations (B, n), rad/s^2, of B planar chains at their own states.

    a = M(q)^-1 (tau - h(q, v) + J(q)^T F) per design.

    Parameters
    ----------
    links : PlanarLinks
        The designs (:func:`prbdm_pin.chain.planar_batch.stack_links`).
    Q, V : ndarray, shape (B, n)
        Joint angles (rad) and rates (rad/s).
    tau_Nm : ndarray, shape (B, n)
        Joint torques of the springs, damping and inputs, N m.
    force_N : ndarray, shape (B, 3), or None
        World-frame tip forces, N.

    Returns
    -------
    ndarray, shape (B, n)
    """
    B = Q.shape[0]
    F = np.zeros((B, 3)) if force_N is None else np.ascontiguousarray(
        np.broadcast_to(force_N, (B, 3)), dtype=float)
    out = np.empty_like(Q)
    _batch(links.lengths_m, links.mass_kg, links.com_offset_m, links.inertia_yy_kg_m2,
           np.ascontiguousarray(Q), np.ascontiguousarray(V), np.ascontiguousarray(tau_Nm), F,
           out)
    return out
