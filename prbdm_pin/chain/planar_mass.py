"""The planar chain's mass matrices M(q) in closed form, and the points they are made of.

The chain is that of :mod:`prbdm_pin.chain.planar`: a clamped link 0 along x, then n links on
revolute joints about +y. The fit's inner loop computes M(q) here instead of building a
``pinocchio.Model`` for every trial design; tests/chain/test_planar.py checks it against
``pin.crba``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["max_index", "chain_points", "planar_mass_matrices"]


@lru_cache(maxsize=64)
def max_index(n: int) -> np.ndarray:
    """Return max(j, k) for j, k < n (read-only, cached).

    The lever arm an entry of the load stiffness takes, and the first link an entry of M(q)
    sums from.
    """
    idx = np.arange(n)
    out = np.maximum(idx[:, None], idx[None, :])
    out.setflags(write=False)
    return out


_MASS_FROM_POINTS = None


def planar_mass_matrices(
    lengths_m: np.ndarray,
    mass_kg: np.ndarray,
    com_offset_m: np.ndarray,
    inertia_yy_kg_m2: np.ndarray,
    Q: np.ndarray,
    points: tuple | None = None,
) -> np.ndarray:
    """Closed-form mass matrices of the planar chain at the poses in the rows of ``Q``.

    The fit's inner loop uses this instead of building a ``pinocchio.Model`` for every trial
    design (the model build cost ~10x the rest of an evaluation); the product, and every fit
    result, use Pinocchio's CRBA. tests/chain/test_planar.py checks it against ``pin.crba``.
    No input checks: the caller passes valid arrays.

    Link i >= 1 (mass m_i, centre of mass d_i from its joint along its axis, inertia I_i about
    the centre of mass and the y axis) swings about joints 1..i, so
    ``M_jk = sum_(i >= max(j, k)) m_i r_ij . r_ik + I_i`` with ``r_ij`` the vector from joint j
    to the centre of mass of link i in the xz-plane (link 0 is clamped and adds nothing),
    summed in one compiled call (:mod:`.planar_mass_kernel`).

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
    points : tuple, optional
        :func:`chain_points` of the same lengths, offsets and poses when already computed.

    Returns
    -------
    ndarray, shape (m, n, n), kg m^2; (B, m, n, n) when the link arrays are stacks (B, n+1)
    of designs.
    """
    global _MASS_FROM_POINTS
    Q = np.asarray(Q, dtype=float)
    m, n = Q.shape
    L, mass, off, Iyy = (np.asarray(v, dtype=float).reshape(-1, n + 1)
                         for v in (lengths_m, mass_kg, com_offset_m, inertia_yy_kg_m2))
    B = L.shape[0]
    _, joints, coms = chain_points(L, off, Q) if points is None else points
    if _MASS_FROM_POINTS is None:  # numba is imported on first use, not with the package
        from .planar_mass_kernel import mass_from_points

        _MASS_FROM_POINTS = mass_from_points
    if joints.shape != (B, m, 2, n) or coms.shape != joints.shape:  # the kernel indexes them
        raise ValueError(f"points of shapes {joints.shape}, {coms.shape}: must be "
                         f"{(B, m, 2, n)}, those of the same design and poses")
    M = np.empty((B, m, n, n))
    _MASS_FROM_POINTS(joints, coms, mass, Iyy, M)
    if np.ndim(lengths_m) == 1:
        return M[0]
    return M


def chain_points(lengths_m: np.ndarray, com_offset_m: np.ndarray, Q: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Link axes, joints and centres of mass of the planar chain at the poses in the rows of Q.

    The sign of z is flipped (the quadratic forms of the mass matrix and of the modes' energy
    do not see it). No input checks.

    Parameters
    ----------
    lengths_m, com_offset_m : ndarray, shape (B, n+1)
        Link lengths and centre-of-mass distances from each link's start, m, of B designs.
    Q : ndarray, shape (m, n)
        Joint angles, rad.

    Returns
    -------
    axes : ndarray, shape (m, 2, n+1)
        Cosines and sines of the world angles of links 0..n.
    joints : ndarray, shape (B, m, 2, n)
        x and z of joints 1..n, m.
    coms : ndarray, shape (B, m, 2, n)
        x and z of the centres of mass of links 1..n, m.
    """
    m, n = Q.shape
    phi = np.zeros((m, n + 1))
    np.add.accumulate(Q, axis=1, out=phi[:, 1:])
    # x and z side by side: one numpy call for both where there were two
    axes = np.empty((m, 2, n + 1))
    np.cos(phi, out=axes[:, 0])
    np.sin(phi, out=axes[:, 1])
    joints = np.add.accumulate(lengths_m[:, None, None, :-1] * axes[..., :-1], axis=3)
    return axes, joints, joints + com_offset_m[:, None, None, 1:] * axes[..., 1:]
