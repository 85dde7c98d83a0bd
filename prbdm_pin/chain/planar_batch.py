"""Many planar chains at once: their inertial layout and M(q) in closed form.

The chain is that of :mod:`prbdm_pin.chain.planar` (a clamped link 0 along x, then n links on
revolute joints about +y), one design per row: B designs of the same joint count, each at its
own state. A batched eigen-solve evaluates them in a few numpy calls over the leading batch
axis instead of B Pinocchio calls; the batched simulation's accelerations (M, h and J^T F of
the same closed forms, then a solve) are compiled in :mod:`.planar_batch_kernel`.
tests/chain/test_planar_batch.py checks every term against Pinocchio's CRBA, RNEA and ABA at
random states.

In the xz-plane (z flipped, as :func:`.planar_mass.chain_points` has it: the quadratic and
bilinear forms below do not see the sign) link i has the world angle phi_i = q_1 + ... + q_i,
its joint at p_i and its centre of mass at c_i = p_i + d_i e(phi_i), e = (cos, sin). Its
centre of mass moves with joint j <= i along R(c_i - p_j) (R: a quarter turn), so

    M_jk = sum_(i >= max(j,k)) m_i (c_i - p_j).(c_i - p_k) + I_i,
    h_j  = sum_(i >= j) m_i (c_i - p_j) x a_i,

with a_i the centre of mass's acceleration at zero joint accelerations (the centripetal terms
-L_k w_k^2 e(phi_k) along the links before it and -d_i w_i^2 e(phi_i), w_k = v_1 + ... + v_k)
and x the planar cross product; the links turn about parallel axes, so the rotational part adds
no bias.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from .pin_dynamics import planar_lengths
from .planar_mass import _lower, max_index

__all__ = ["PlanarLinks", "planar_links", "stack_links", "batch_mass"]


@dataclass(frozen=True, eq=False)
class PlanarLinks:
    """The inertial layout of B planar chains of n joints, one row per design.

    Attributes
    ----------
    lengths_m : ndarray, shape (B, n+1)
        Link lengths (the clamped link 0 first), m.
    mass_kg : ndarray, shape (B, n)
        Masses of the moving links 1..n, kg.
    com_offset_m : ndarray, shape (B, n)
        Centre-of-mass distance of links 1..n from their joint along the link axis, m.
    inertia_yy_kg_m2 : ndarray, shape (B, n)
        Inertias of links 1..n about their centre of mass around y, kg m^2.
    """

    lengths_m: np.ndarray
    mass_kg: np.ndarray
    com_offset_m: np.ndarray
    inertia_yy_kg_m2: np.ndarray

    @property
    def n_designs(self) -> int:
        """Number of designs B."""
        return int(self.lengths_m.shape[0])


def planar_links(pin_model, tip_frame_id: int) -> tuple[np.ndarray, ...] | None:
    """Return the lengths (n+1,) m and link masses, offsets, inertias (n,) of a planar chain.

    Read from Pinocchio's model (what every dynamics call of the model uses). None when the
    chain is not a serial y-revolute chain along x with each centre of mass on its link's
    x axis (a centre of mass off it, in z, would need the general kinematics).
    """
    try:
        lengths = planar_lengths(pin_model, tip_frame_id)
    except BeamInputError:
        return None
    n = lengths.size - 1
    mass, off, iyy = np.empty(n), np.empty(n), np.empty(n)
    for j in range(n):
        inertia = pin_model.inertias[j + 1]
        lever = np.asarray(inertia.lever)
        # a y offset leaves the planar motion alone (y is every joint's axis); a z one does not
        if abs(lever[2]) > 1e-12 * max(1.0, abs(lever[0])):
            return None
        mass[j], off[j], iyy[j] = inertia.mass, lever[0], np.asarray(inertia.inertia)[1, 1]
    return lengths, mass, off, iyy


def stack_links(rows: list[tuple[np.ndarray, ...]]) -> PlanarLinks:
    """Stack the :func:`planar_links` of B designs of one joint count into a PlanarLinks."""
    return PlanarLinks(*(np.array([r[i] for r in rows], dtype=float) for i in range(4)))


def _points(links: PlanarLinks, Q: np.ndarray):
    """Cosines and sines (B, 2, n) of the link angles, joints and centres of mass (B, 2, n)."""
    B, n = Q.shape
    phi = np.add.accumulate(Q, axis=1)
    e = np.empty((B, 2, n))
    np.cos(phi, out=e[:, 0])
    np.sin(phi, out=e[:, 1])
    L = links.lengths_m
    joints = np.empty((B, 2, n))
    joints[:, 0, 0] = L[:, 0]
    joints[:, 1, 0] = 0.0
    if n > 1:
        joints[:, :, 1:] = joints[:, :, :1] + np.add.accumulate(
            L[:, None, 1:n] * e[:, :, :-1], axis=2)
    return e, joints, joints + links.com_offset_m[:, None, :] * e


def batch_mass(links: PlanarLinks, Q: np.ndarray, points: tuple | None = None) -> np.ndarray:
    """Mass matrices of B designs, each at its own pose ``Q[b]`` (rad), kg m^2, (B, n, n).

    No input checks: the caller passes valid arrays. ``points``: :func:`_points` of the same
    designs and poses when already computed.
    """
    B, n = Q.shape
    _, joints, coms = _points(links, Q) if points is None else points
    # rows (x or z, i) of R hold sqrt(m_i) (c_i - p_j); link i moves with joint j only if j <= i
    w = np.sqrt(links.mass_kg)[:, None, :, None] * _lower(n)
    R = ((coms[:, :, :, None] - joints[:, :, None, :]) * w).reshape(B, 2 * n, n)
    M = R.swapaxes(1, 2) @ R
    tail = np.add.accumulate(links.inertia_yy_kg_m2[:, ::-1], axis=1)[:, ::-1]
    M += tail[:, max_index(n)]
    return M
