"""Compiled accelerations of B planar chains at their own states (numba), one design per row.

The batched simulation's right-hand side spends its time here: per design, the closed forms of
:mod:`.planar_batch` (M(q), the Coriolis/centrifugal forces h, J^T F) and a Cholesky solve of
M a = tau - K q - C v - h + J^T F, in one compiled loop over the designs (numpy over the batch
axis made some thirty array calls per evaluation, each a pass over the batch). numba (chosen
over JAX: a small dependency that compiles these loops as they are written, with an on-disk
cache, and no derivatives are asked of the batch) is imported by this module only, which
:mod:`prbdm_pin.simulation.batch_rhs` imports on first use; one signature, cached.

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

from .small_cholesky import cholesky_solve

__all__ = ["batch_state_rates"]


@numba.njit(cache=True, error_model="numpy")
def _batch(L, mass, off, iyy, Y, springs, C, tau, F, out):  # pragma: no cover - compiled
    # one flat loop, scratch allocated once: a helper taking row views per design cost as much
    # as the arithmetic (each view is reference-counted)
    B, n = Y.shape[0], Y.shape[1] // 2
    damped = C.shape[0] > 0
    M, G = np.empty((n, n)), np.empty((n, n))
    px, pz, cx, cz = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    co, si, ax, az, w2, rhs = (np.empty(n), np.empty(n), np.empty(n), np.empty(n),
                               np.empty(n), np.empty(n))
    for b in range(B):
        phi = 0.0
        w = 0.0
        for i in range(n):
            phi += Y[b, i]
            co[i] = math.cos(phi)
            si[i] = math.sin(phi)
            w += Y[b, n + i]
            w2[i] = w * w
            out[b, i] = Y[b, n + i]
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
            e = tau[b, j] - springs[b, j] * Y[b, j]
            if damped:
                for p in range(n):
                    e -= C[b, j, p] * Y[b, n + p]
            rhs[j] = e - (t_cxa - (px[j] * t_az - pz[j] * t_ax)) - fx * rs - fz * rc
        for k in range(n):
            s, tx, tz = 0.0, 0.0, 0.0
            for i in range(k, n):
                dx, dz = cx[i] - px[k], cz[i] - pz[k]
                s += mass[b, i] * (dx * dx + dz * dz) + iyy[b, i]
                tx += mass[b, i] * dx
                tz += mass[b, i] * dz
            for j in range(k + 1):
                M[k, j] = s + (px[k] - px[j]) * tx + (pz[k] - pz[j]) * tz
        # M = G G^T (lower triangle), then the two triangular solves
        if not cholesky_solve(M, G, rhs, out[b, n:]):
            out[b, n:] = np.nan  # not positive definite: the integrator's error check sees it


def batch_state_rates(links, Y: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                      damping_Nms_per_rad: np.ndarray | None, tau_Nm: np.ndarray | None,
                      force_N: np.ndarray | None) -> np.ndarray:
    """Return the rates (v, a) (B, 2n) of B planar chains at their own states Y = (q, v).

    a = M(q)^-1 (tau - K q - C v - h(q, v) + J(q)^T F) per design.

    Parameters
    ----------
    links : PlanarLinks
        The designs (:func:`prbdm_pin.chain.planar_batch.design_links`).
    Y : ndarray, shape (B, 2n)
        Joint angles (rad) and rates (rad/s).
    stiffness_Nm_per_rad : ndarray, shape (B, n)
        Joint springs K (diagonal), N m/rad.
    damping_Nms_per_rad : ndarray, shape (B, n, n), or None
        Damping matrices C, N m s/rad.
    tau_Nm : ndarray, shape (B, n), or None
        Other joint torques (the inputs'), N m.
    force_N : ndarray, shape (B, 3) or (3,), or None
        World-frame tip forces, N.

    Returns
    -------
    ndarray, shape (B, 2n)
    """
    B, n2 = Y.shape
    F = _ZERO3 if force_N is None else force_N
    if F.shape != (B, 3):
        F = np.broadcast_to(F, (B, 3)).copy()
    C = _NO_DAMPING if damping_Nms_per_rad is None else damping_Nms_per_rad
    tau = np.zeros((B, n2 // 2)) if tau_Nm is None else tau_Nm
    out = np.empty((B, n2))
    _batch(links.lengths_m, links.mass_kg, links.com_offset_m, links.inertia_yy_kg_m2,
           np.ascontiguousarray(Y), stiffness_Nm_per_rad, C, tau, F, out)
    return out


_ZERO3 = np.zeros(3)
_NO_DAMPING = np.zeros((0, 0, 0))
