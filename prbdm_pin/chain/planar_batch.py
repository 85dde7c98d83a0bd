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

__all__ = ["PlanarLinks", "planar_links", "stack_links", "design_links", "batch_mass"]


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
    x axis (a centre of mass off it, in z, would need the general kinematics). Plain float
    checks: a batch reads one layout per design, and ``pin_dynamics.planar_lengths``'s
    ``np.allclose`` per placement cost ten times this whole read.
    """
    n = pin_model.njoints - 1
    lengths, mass, off, iyy = np.empty(n + 1), np.empty(n), np.empty(n), np.empty(n)
    # each attribute of the model is fetched once (every fetch wraps the whole vector)
    parents, joints, places = pin_model.parents, pin_model.joints, pin_model.jointPlacements
    inertias = pin_model.inertias
    for j in range(1, n + 1):
        if parents[j] != j - 1 or joints[j].shortname() != "JointModelRY":
            return None
        x = _along_x(places[j])
        inertia = inertias[j]
        lever = inertia.lever
        # a y offset leaves the planar motion alone (y is every joint's axis); a z one does not
        if x is None or abs(lever[2]) > 1e-12 * max(1.0, abs(lever[0])):
            return None
        lengths[j - 1] = x
        mass[j - 1], off[j - 1], iyy[j - 1] = inertia.mass, lever[0], inertia.inertia[1, 1]
    frame = pin_model.frames[tip_frame_id]
    x = _along_x(frame.placement) if frame.parentJoint == n else None
    if x is None:
        return None
    lengths[n] = x
    return lengths, mass, off, iyy


def _along_x(placement) -> float | None:
    """Return the x offset of a pure x offset placement (to 1e-12 m and rad), else None."""
    p = placement.translation.tolist()
    rot = placement.rotation.tolist()  # Python floats: cheaper than numpy's reductions here
    if abs(p[1]) + abs(p[2]) > 1e-12 or max(abs(rot[i][j] - (i == j)) for i in range(3)
                                            for j in range(3)) > 1e-12:
        return None
    return p[0]


def stack_links(rows: list[tuple[np.ndarray, ...]]) -> PlanarLinks:
    """Stack the :func:`planar_links` of B designs of one joint count into a PlanarLinks."""
    return PlanarLinks(*(np.array([r[i] for r in rows], dtype=float) for i in range(4)))


def design_links(models) -> PlanarLinks | None:
    """Return the PlanarLinks of planar clamped designs (PrbdmModel), or None if one is not.

    Read from each model's lengths and link sections, which its Pinocchio model is built from
    (:mod:`prbdm_pin.model.pin_chain`; the tests check the two readings agree): a few array
    reads per design, where reading the Pinocchio model (:func:`planar_links`) costs more
    than a design's frequencies. None for a hub, a free bus, a spatial chain or a centre of
    mass off its link's axis in z.
    """
    for m in models:
        if m.hub is not None or m.bus is not None or m.axes.spatial:
            return None
    secs = [m.sections for m in models]
    com = np.array([s.com_m[1:] for s in secs])
    if np.any(np.abs(com[:, :, 2]) > 1e-12 * np.maximum(1.0, np.abs(com[:, :, 0]))):
        return None
    start = np.array([s.start_m[1:] for s in secs])
    return PlanarLinks(np.array([m.lengths_m for m in models], dtype=float),
                       np.array([s.mass_kg[1:] for s in secs], dtype=float),
                       com[:, :, 0] - start,
                       np.array([s.inertia_com_kg_m2[1:, 1, 1] for s in secs], dtype=float))


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


def batch_mass(links: PlanarLinks, Q: np.ndarray) -> np.ndarray:
    """Mass matrices of B designs, each at its own pose ``Q[b]`` (rad), kg m^2, (B, n, n).

    Entry (k, j <= k) about joint k, as the compiled kernel has it
    (:mod:`.planar_batch_kernel`): M_kj = S_k + (p_k - p_j) . T_k, one pass per joint over
    the batch. No input checks: the caller passes valid arrays.
    """
    B, n = Q.shape
    _, joints, coms = _points(links, Q)
    m = links.mass_kg[:, None, :]
    tail_inertia = np.add.accumulate(links.inertia_yy_kg_m2[:, ::-1], axis=1)[:, ::-1]
    M = np.empty((B, n, n))
    for k in range(n):
        d = coms[:, :, k:] - joints[:, :, k:k + 1]  # (B, 2, n - k): c_i - p_k, i >= k
        md = m[:, :, k:] * d
        S = np.einsum("bxi,bxi->b", md, d) + tail_inertia[:, k]
        T = md.sum(axis=2)  # (B, 2)
        row = S[:, None] + np.einsum("bxj,bx->bj", joints[:, :, k:k + 1] - joints[:, :, :k + 1],
                                     T)
        M[:, k, :k + 1] = row
        M[:, :k, k] = row[:, :k]
    return M
