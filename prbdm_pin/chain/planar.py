"""The planar chain in closed form: tip, Jacobian, J^T F, load stiffness, M(q) and the potential.

M(q) is computed in :mod:`prbdm_pin.chain.planar_mass` and exported here too.

The chain is a clamped link of length L_0 along x followed by n links on revolute joints about
+y. Link i >= 1 has the world angle phi_i = q_1 + ... + q_i, so its axis is
(cos phi_i, 0, -sin phi_i) and

    p_tip = L_0 e_x + sum_i L_i (cos phi_i, 0, -sin phi_i).

With the lever arms c_m = sum_(i >= m) L_i cos phi_i and s_m = sum_(i >= m) L_i sin phi_i the
linear tip Jacobian has the rows dp_x/dq_m = -s_m, dp_z/dq_m = -c_m, so for a dead force F

    (J^T F)_m = -F_x s_m - F_z c_m,   d(J^T F)_j / dq_k = T_max(j,k),   T_m = -F_x c_m + F_z s_m.

Every function takes one pose (q of shape (n,)) or a stack (Q of shape (..., n)); lengths
(n+1,) serve every pose of a stack, or come stacked like the poses. These are the fit's inner
loop and the simulation's force terms; tests/chain/test_planar.py checks them against Pinocchio.
"""

from __future__ import annotations

import math

import numpy as np

# M(q) lives in its own module (:mod:`.planar_mass`); importers of the planar chain find it here
from .planar_mass import chain_points, max_index, planar_mass_matrices

__all__ = [
    "tip_positions",
    "planar_tips",
    "tip_jacobians",
    "planar_tip",
    "generalised_force",
    "load_stiffness",
    "force_and_load_stiffness",
    "planar_mass_matrices",
    "chain_points",
    "tip_terms",
    "chains_at_pose",
    "ChainPotential",
]


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray | float:
    """Sum a * b over the last axis.

    Numpy's pairwise sum for one pose, einsum row by row for a stack: the orders of summation
    the single and stacked statics have always used (the fits' numbers do not move by a
    rounding).
    """
    if a.ndim == 1:
        return np.add.reduce(a * b)  # ndarray.sum's pairwise sum without its Python wrapper
    return np.einsum("bi,bi->b", a.reshape(-1, a.shape[-1]),
                     b.reshape(-1, b.shape[-1])).reshape(a.shape[:-1])


def _angles(Q: np.ndarray) -> np.ndarray:
    """Cosines and sines of the link angles phi_i = q_1 + ... + q_i, stacked: (2,) + Q.shape.

    Cosines and sines side by side, so the callers treat both in one numpy call (a call costs
    as much as the arithmetic of a short chain; np.add.accumulate is cumsum without its
    wrapper).
    """
    phi = np.add.accumulate(Q, axis=-1)
    cs = np.empty((2,) + phi.shape)
    np.cos(phi, out=cs[0])
    np.sin(phi, out=cs[1])
    return cs


def _tip_xz(L0, links: np.ndarray, cs: np.ndarray):
    """Return the tip's x and z (m).

    From the clamped length ``L0``, the links (..., n) and the cosines and sines of their
    angles (:func:`_angles`).
    """
    if links.ndim == 1:  # both rows' pairwise sums in one reduction, as _dot sums one row
        x, z = np.add.reduce(links * cs, axis=-1).tolist()
    else:
        x, z = _dot(links, cs[0]), _dot(links, cs[1])
    return L0 + x, -z


def _lever_arms(links: np.ndarray, cs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(c_m, s_m) = sums over i >= m of L_i cos phi_i and L_i sin phi_i, shape (..., n)."""
    r = np.add.accumulate((cs * links)[..., ::-1], axis=-1)[..., ::-1]
    return r[0], r[1]


def _force_terms(rc: np.ndarray, rs: np.ndarray, fx: float, fz: float, stiffness: bool):
    """J^T F and (when ``stiffness``, else None) d(J^T F)/dq of the force (fx, ., fz), N."""
    jtf = -fx * rs - fz * rc
    if not stiffness:
        return jtf, None
    T = -fx * rc + fz * rs
    idx = max_index(T.shape[-1])
    # T[idx] for one chain: indexing after an Ellipsis costs more than the arithmetic here
    return jtf, T[idx] if T.ndim == 1 else T[..., idx]


def _chain(lengths_m: np.ndarray, Q: np.ndarray):
    """Q as floats, and the lengths split into L_0 and the links, broadcast to the poses."""
    Q = np.asarray(Q, dtype=float)
    L = np.asarray(lengths_m, dtype=float)
    shape = Q.shape[:-1] + (Q.shape[-1] + 1,)
    if L.shape != shape:  # broadcast_to costs as much as the kinematics of a short chain
        L = np.broadcast_to(L, shape)
    # L[0] for one chain: a scalar, cheaper to compute with than the 0-d array of L[..., 0]
    return Q, L[0] if L.ndim == 1 else L[..., 0], L[..., 1:]


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
    out[..., 0], out[..., 2] = _tip_xz(L0, links, _angles(Q))
    return out


# the name the fits import: stacked chains, one row per design or pose
planar_tips = tip_positions


def tip_jacobians(lengths_m: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """World-aligned linear tip Jacobians (m/rad) at ``Q`` (rad, (..., n)), shape (..., 3, n)."""
    Q, _, links = _chain(lengths_m, Q)
    return _jacobians(*_lever_arms(links, _angles(Q)))


def planar_tip(lengths_m: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tip position (m, (3,)) and linear tip Jacobian (m/rad, (3, n)) of one pose ``q`` (rad)."""
    q, L0, links = _chain(lengths_m, q)
    cs = _angles(q)
    p = np.zeros(q.shape[:-1] + (3,))
    p[..., 0], p[..., 2] = _tip_xz(L0, links, cs)
    return p, _jacobians(*_lever_arms(links, cs))


def tip_terms(lengths_m: np.ndarray, q: np.ndarray, force_N: np.ndarray):
    """Return what the derivatives of an equilibrium need at one pose, from one angle evaluation.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    q : ndarray, shape (n,)
        Joint angles, rad.
    force_N : ndarray, shape (3,)
        Dead tip force in the world frame, N.

    Returns
    -------
    tip_m : ndarray, shape (3,)
        Tip position, m.
    jacobian : ndarray, shape (3, n)
        Linear tip Jacobian, m/rad.
    load_stiffness : ndarray, shape (n, n)
        d(J^T F)/dq (:func:`load_stiffness`), N m/rad.
    cos_phi, sin_phi : ndarray, shape (n,)
        Cosines and sines of the link angles phi_i = q_1 + ... + q_i.
    """
    q, L0, links = _chain(lengths_m, q)
    cs = _angles(q)
    rc, rs = _lever_arms(links, cs)
    p = np.zeros(3)
    p[0], p[2] = _tip_xz(L0, links, cs)
    T = _force_terms(rc, rs, float(force_N[0]), float(force_N[2]), True)[1]
    return p, _jacobians(rc, rs), T, cs[0], cs[1]


def chains_at_pose(lengths_m: np.ndarray, q: np.ndarray, force_N: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Return the tip heights (c,) m and J^T F (c, n) N m of c chains at one pose.

    ``lengths_m`` (c, n+1) stacks the chains (m), ``q`` (n,) is their common pose (rad) and
    ``force_N`` (3,) a dead world tip force (N). The angles are computed once for all chains
    (a trajectory gradient's moved chains share the state); the tip height is minus the first
    sine lever arm, -sum L_i sin phi_i. No input checks.
    """
    cs = _angles(np.asarray(q, dtype=float))
    rc, rs = _lever_arms(np.asarray(lengths_m, dtype=float)[:, 1:], cs[:, None, :])
    return -rs[:, 0], _force_terms(rc, rs, float(force_N[0]), float(force_N[2]), False)[0]


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
    rc, rs = _lever_arms(links, _angles(q))
    return _force_terms(rc, rs, float(force_N[0]), float(force_N[2]), stiffness)


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
        self.L0 = lengths[0] if lengths.ndim == 1 else lengths[..., 0]  # as in _chain
        self.links = lengths[..., 1:]
        self.k = np.asarray(stiffness_Nm_per_rad, dtype=float)
        self.fx, self.fz = float(force_N[0]), float(force_N[2])
        self.K = np.diag(self.k) if self.k.ndim == 1 else None

    def _rows(self, rows):
        if rows is None:
            return self.L0, self.links, self.k
        return self.L0[rows], self.links[rows], self.k[rows]

    def angles(self, q: np.ndarray) -> np.ndarray:
        """Return the cosines and sines of the link angles at ``q`` (rad), shape (2,) + q.shape.

        What :meth:`value` and :meth:`derivatives` at the same ``q`` share (``cs``).
        """
        return _angles(q)

    def value(self, q: np.ndarray, lam: float = 1.0, rows: np.ndarray | None = None,
              cs: np.ndarray | None = None):
        """Return V at ``q`` (rad) under the load fraction ``lam``, J.

        A float for one chain, shape (r,) for the chains ``rows``. ``cs``: :meth:`angles` of
        ``q`` when already computed.
        """
        L0, links, k = self._rows(rows)
        x, z = _tip_xz(L0, links, _angles(q) if cs is None else cs)
        work = self.fx * x + self.fz * z
        if q.ndim == 1:
            return 0.5 * float(q @ (k * q)) - lam * float(work)
        return 0.5 * _dot(k * q, q) - lam * work

    def derivatives(self, q: np.ndarray, lam: float = 1.0, rows: np.ndarray | None = None,
                    hessian: bool = True, cs: np.ndarray | None = None):
        """Return the gradient, the Hessian and the residual scale at ``q`` (rad).

        The gradient is in N m, the Hessian in N m/rad (None unless ``hessian``), and the
        residual scale max(||K q||, ||lam J^T F||) of the convergence test in N m. ``cs``:
        :meth:`angles` of ``q`` when already computed.
        """
        _, links, k = self._rows(rows)
        rc, rs = _lever_arms(links, _angles(q) if cs is None else cs)
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
