"""The planar chain in closed form: tip, Jacobian, J^T F, load stiffness, M(q) and the potential.

The chain is a clamped link of length L_0 along x followed by n links on revolute joints about
+y. Link i >= 1 has the world angle phi_i = q_1 + ... + q_i, so its axis is
(cos phi_i, 0, -sin phi_i) and

    p_tip = L_0 e_x + sum_i L_i (cos phi_i, 0, -sin phi_i).

With the lever arms c_m = sum_(i >= m) L_i cos phi_i and s_m = sum_(i >= m) L_i sin phi_i the
linear tip Jacobian has the rows dp_x/dq_m = -s_m, dp_z/dq_m = -c_m, so for a dead force F

    (J^T F)_m = -F_x s_m - F_z c_m,   d(J^T F)_j / dq_k = T_max(j,k),   T_m = -F_x c_m + F_z s_m.

Every function takes one pose (q of shape (n,)) or a stack (Q of shape (..., n)); lengths
(n+1,) serve every pose of a stack, or come stacked like the poses. These are the fit's inner
loop and the simulation's force terms; tests/test_planar.py checks them against Pinocchio.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

__all__ = [
    "tip_positions",
    "planar_tips",
    "tip_jacobians",
    "planar_tip",
    "generalised_force",
    "load_stiffness",
    "force_and_load_stiffness",
    "planar_mass_matrices",
    "ChainPotential",
]


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray | float:
    """Sum a * b over the last axis.

    Numpy's pairwise sum for one pose, einsum row by row for a stack: the orders of summation
    the single and stacked statics have always used (the fits' numbers do not move by a
    rounding).
    """
    if a.ndim == 1:
        return (a * b).sum()
    return np.einsum("bi,bi->b", a.reshape(-1, a.shape[-1]),
                     b.reshape(-1, b.shape[-1])).reshape(a.shape[:-1])


def _angles(Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cosines and sines of the link angles phi_i = q_1 + ... + q_i, shape of ``Q``."""
    phi = Q.cumsum(axis=-1)
    return np.cos(phi), np.sin(phi)


def _tip_xz(L0, links: np.ndarray, c: np.ndarray, s: np.ndarray):
    """Return the tip's x and z (m).

    From the clamped length ``L0``, the links (..., n) and the cosines and sines of their
    angles.
    """
    return L0 + _dot(links, c), -_dot(links, s)


def _lever_arms(links: np.ndarray, c: np.ndarray, s: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """(c_m, s_m) = sums over i >= m of L_i cos phi_i and L_i sin phi_i, shape (..., n)."""
    # both in one pass: a numpy call costs as much as the arithmetic of a short chain
    rc, rs = (np.array([c, s]) * links)[..., ::-1].cumsum(axis=-1)[..., ::-1]
    return rc, rs


@lru_cache(maxsize=64)
def _upper(n: int) -> np.ndarray:
    """max(j, k) for j, k < n: the lever arm an entry of the load stiffness takes."""
    idx = np.arange(n)
    out = np.maximum(idx[:, None], idx[None, :])
    out.setflags(write=False)
    return out


def _force_terms(rc: np.ndarray, rs: np.ndarray, fx: float, fz: float, stiffness: bool):
    """J^T F and (when ``stiffness``, else None) d(J^T F)/dq of the force (fx, ., fz), N."""
    jtf = -fx * rs - fz * rc
    if not stiffness:
        return jtf, None
    return jtf, (-fx * rc + fz * rs)[..., _upper(rc.shape[-1])]


def _chain(lengths_m: np.ndarray, Q: np.ndarray):
    """Q as floats, and the lengths split into L_0 and the links, broadcast to the poses."""
    Q = np.asarray(Q, dtype=float)
    L = np.asarray(lengths_m, dtype=float)
    shape = Q.shape[:-1] + (Q.shape[-1] + 1,)
    if L.shape != shape:  # broadcast_to costs as much as the kinematics of a short chain
        L = np.broadcast_to(L, shape)
    return Q, L[..., 0], L[..., 1:]


def _jacobians(rc: np.ndarray, rs: np.ndarray) -> np.ndarray:
    J = np.zeros(rc.shape[:-1] + (3, rc.shape[-1]))
    J[..., 0, :] = -rs
    J[..., 2, :] = -rc
    return J


def tip_positions(lengths_m: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Tip positions (m, world) at joint angles ``Q`` (rad, (..., n)), shape (..., 3).

    ``lengths_m`` (n+1,) or stacked like ``Q`` (..., n+1), m. No input checks.
    """
    Q, L0, links = _chain(lengths_m, Q)
    out = np.zeros(Q.shape[:-1] + (3,))
    out[..., 0], out[..., 2] = _tip_xz(L0, links, *_angles(Q))
    return out


# the name the fits import: stacked chains, one row per design or pose
planar_tips = tip_positions


def tip_jacobians(lengths_m: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """World-aligned linear tip Jacobians (m/rad) at ``Q`` (rad, (..., n)), shape (..., 3, n)."""
    Q, _, links = _chain(lengths_m, Q)
    return _jacobians(*_lever_arms(links, *_angles(Q)))


def planar_tip(lengths_m: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tip position (m, (3,)) and linear tip Jacobian (m/rad, (3, n)) of one pose ``q`` (rad)."""
    q, L0, links = _chain(lengths_m, q)
    c, s = _angles(q)
    p = np.zeros(q.shape[:-1] + (3,))
    p[..., 0], p[..., 2] = _tip_xz(L0, links, c, s)
    return p, _jacobians(*_lever_arms(links, c, s))


def generalised_force(lengths_m: np.ndarray, q: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Compute J(q)^T F, the joint torques of a dead tip force, N m.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    q : ndarray, shape (n,) or (..., n)
        Joint angles, rad.
    force_N : ndarray, shape (3,)
        Dead tip force in the world frame, N.

    Returns
    -------
    ndarray, shape of ``q``
        The joint torques, N m.
    """
    return force_and_load_stiffness(lengths_m, q, force_N, stiffness=False)[0]


def load_stiffness(lengths_m: np.ndarray, q: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Compute the load stiffness d(J^T F)/dq, N m/rad.

    The stiffness a dead tip force adds to the joint springs with the sign of a force (the
    potential's Hessian is diag(K) minus it); symmetric, shape (n, n), or (..., n, n) for
    stacked ``q``. Parameters as :func:`generalised_force`.
    """
    return force_and_load_stiffness(lengths_m, q, force_N)[1]


def force_and_load_stiffness(
    lengths_m: np.ndarray, q: np.ndarray, force_N: np.ndarray, stiffness: bool = True
) -> tuple[np.ndarray, np.ndarray | None]:
    """Compute :func:`generalised_force` and :func:`load_stiffness` from one angle evaluation.

    The load stiffness is None unless ``stiffness``.
    """
    q, _, links = _chain(lengths_m, q)
    rc, rs = _lever_arms(links, *_angles(q))
    return _force_terms(rc, rs, float(force_N[0]), float(force_N[2]), stiffness)


def planar_mass_matrices(
    lengths_m: np.ndarray,
    mass_kg: np.ndarray,
    com_offset_m: np.ndarray,
    inertia_yy_kg_m2: np.ndarray,
    Q: np.ndarray,
) -> np.ndarray:
    """Closed-form mass matrices of the planar chain at the poses in the rows of ``Q``.

    The fit's inner loop uses this instead of building a ``pinocchio.Model`` for every trial
    design (the model build cost ~10x the rest of an evaluation); the product, and every fit
    result, use Pinocchio's CRBA. tests/test_planar.py checks it against ``pin.crba``.
    No input checks: the caller passes valid arrays.

    Link i >= 1 (mass m_i, centre of mass d_i from its joint along its axis, inertia I_i about
    the centre of mass and the y axis) swings about joints 1..i, so
    ``M_jk = sum_(i >= max(j, k)) m_i r_ij . r_ik + I_i`` with ``r_ij`` the vector from joint j
    to the centre of mass of link i in the xz-plane (link 0 is clamped and adds nothing).

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    mass_kg, com_offset_m, inertia_yy_kg_m2 : ndarray, shape (n+1,)
        Link masses (kg), centre-of-mass distances from the link's start along its axis (m),
        and inertias about the centre of mass around y (kg m^2); entry 0 (the clamped link) is
        not used.
    Q : ndarray, shape (m, n)
        Joint angles, rad.

    Returns
    -------
    ndarray, shape (m, n, n), kg m^2; (B, m, n, n) when the link arrays are stacks (B, n+1)
    of designs.
    """
    Q = np.asarray(Q, dtype=float)
    m, n = Q.shape
    L, mass, off, Iyy = (np.asarray(v, dtype=float).reshape(-1, n + 1)
                         for v in (lengths_m, mass_kg, com_offset_m, inertia_yy_kg_m2))
    B = L.shape[0]
    phi = np.zeros((m, n + 1))
    Q.cumsum(axis=1, out=phi[:, 1:])
    c, sn = np.cos(phi), np.sin(phi)  # link axes (the sign of z does not matter here)
    jx = (L[:, None, :-1] * c[:, :-1]).cumsum(axis=2)  # (B, m, n): joint j + 1
    jz = (L[:, None, :-1] * sn[:, :-1]).cumsum(axis=2)
    cx = jx + off[:, None, 1:] * c[:, 1:]  # (B, m, n): centre of mass of link i + 1
    cz = jz + off[:, None, 1:] * sn[:, 1:]
    # rows (i, x) of R hold sqrt(m_i) r_ij; link i moves with joint j only when j <= i
    w = (np.sqrt(mass[:, 1:])[:, :, None] * np.tri(n))[:, None]
    R = np.empty((B, m, 2 * n, n))
    np.multiply(cx[..., :, None] - jx[..., None, :], w, out=R[:, :, :n])
    np.multiply(cz[..., :, None] - jz[..., None, :], w, out=R[:, :, n:])
    M = R.swapaxes(-1, -2) @ R
    tail = Iyy[:, :0:-1].cumsum(axis=1)[:, ::-1]  # sum over links i >= j of I_i
    idx = np.arange(n)
    M += tail[:, None, np.maximum.outer(idx, idx)]
    if np.ndim(lengths_m) == 1:
        return M[0]
    return M


class ChainPotential:
    """The potential V(q) = 1/2 q^T K q - lam F . p_tip(q) of one chain or of B chains.

    Its exact gradient is K q - lam J^T F and its Hessian diag(K) - lam d(J^T F)/dq.

    ``lengths_m`` (n+1,) with ``stiffness_Nm_per_rad`` (n,) for one chain (q of shape (n,)), or
    (B, n+1) with (B, n) for B chains, whose methods take the poses of the chains ``rows``
    (q of shape (len(rows), n)). ``force_N`` is the dead tip force (3,), N, world.
    """

    def __init__(self, lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                 force_N: np.ndarray) -> None:
        lengths = np.asarray(lengths_m, dtype=float)
        self.L0, self.links = lengths[..., 0], lengths[..., 1:]
        self.k = np.asarray(stiffness_Nm_per_rad, dtype=float)
        self.fx, self.fz = float(force_N[0]), float(force_N[2])
        self.K = np.diag(self.k) if self.k.ndim == 1 else None

    def _rows(self, rows):
        if rows is None:
            return self.L0, self.links, self.k
        return self.L0[rows], self.links[rows], self.k[rows]

    def value(self, q: np.ndarray, lam: float = 1.0, rows: np.ndarray | None = None):
        """Return V at ``q`` (rad) under the load fraction ``lam``, J.

        A float for one chain, shape (r,) for the chains ``rows``.
        """
        L0, links, k = self._rows(rows)
        x, z = _tip_xz(L0, links, *_angles(q))
        work = self.fx * x + self.fz * z
        if q.ndim == 1:
            return 0.5 * float(q @ (k * q)) - lam * float(work)
        return 0.5 * _dot(k * q, q) - lam * work

    def derivatives(self, q: np.ndarray, lam: float = 1.0, rows: np.ndarray | None = None,
                    hessian: bool = True):
        """Return the gradient, the Hessian and the residual scale at ``q`` (rad).

        The gradient is in N m, the Hessian in N m/rad (None unless ``hessian``), and the
        residual scale max(||K q||, ||lam J^T F||) of the convergence test in N m.
        """
        _, links, k = self._rows(rows)
        rc, rs = _lever_arms(links, *_angles(q))
        jtf, T = _force_terms(rc, rs, lam * self.fx, lam * self.fz, hessian)
        kq = k * q
        g = kq - jtf
        if q.ndim == 1:
            scale = max(math.sqrt(kq @ kq), math.sqrt(jtf @ jtf), 1e-300)
            return g, None if T is None else self.K - T, scale
        scale = np.maximum(np.maximum(np.linalg.norm(kq, axis=1), np.linalg.norm(jtf, axis=1)),
                           1e-300)
        if T is None:
            return g, None, scale
        H = -T
        # the diagonal as a view: fancy-index assignment costs more than the rest for small n
        np.einsum("...ii->...i", H)[...] += k
        return g, H, scale
