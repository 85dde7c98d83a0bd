"""The planar chain's points and mass matrices, each in one compiled call (numba).

:func:`prbdm_pin.chain.planar_mass.planar_mass_matrices`' sum, for one design or a stack: the
numpy form (a stacked matrix product R^T R of the lever arms and an indexed add of the link
inertias) made six numpy calls whose cost, for a short chain, was many times the arithmetic.
Imported on first use only (the package's import and the CLI do not load numba).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["mass_from_points", "points_into"]


# one signature, inputs read-only (a writable array converts; the sections' arrays are not)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_IN4 = numba.types.Array(numba.float64, 4, "A", readonly=True)
_OUT4 = numba.types.Array(numba.float64, 4, "A")
_OUT3C = numba.types.Array(numba.float64, 3, "C")
_OUT4C = numba.types.Array(numba.float64, 4, "C")


@numba.njit(numba.types.void(_IN4, _IN4, _IN2, _IN2, _OUT4), cache=True)
def mass_from_points(joints, coms, mass, inertia, out):  # pragma: no cover - compiled
    """Fill ``out`` (B, m, n, n) with M_jk = sum_(i >= max(j, k)) m_i r_ij . r_ik + I_i.

    ``joints`` and ``coms`` (B, m, 2, n): x and z of joints 1..n and of the centres of mass of
    links 1..n (m; :func:`.planar_mass.chain_points`), r_ij = com_i - joint_j; ``mass`` (kg)
    and ``inertia`` (about the centre of mass and y, kg m^2) of links 0..n, (B, n+1) (link 0,
    clamped, adds nothing).
    """
    B, m, _, n = joints.shape
    tail = np.empty(n)
    for b in range(B):
        # sum of I_i over links i >= j, from the tip down
        acc = 0.0
        for i in range(n - 1, -1, -1):
            acc += inertia[b, i + 1]
            tail[i] = acc
        for p in range(m):
            for j in range(n):
                for k in range(j, n):
                    s = 0.0
                    for i in range(k, n):  # the links that move with both joints
                        s += mass[b, i + 1] * (
                            (coms[b, p, 0, i] - joints[b, p, 0, j])
                            * (coms[b, p, 0, i] - joints[b, p, 0, k])
                            + (coms[b, p, 1, i] - joints[b, p, 1, j])
                            * (coms[b, p, 1, i] - joints[b, p, 1, k]))
                    out[b, p, j, k] = s + tail[k]
                    out[b, p, k, j] = s + tail[k]


@numba.njit(numba.types.void(_IN2, _IN2, _IN2, _OUT3C, _OUT4C, _OUT4C), cache=True)
def points_into(lengths, offsets, Q, axes, joints, coms):  # pragma: no cover - compiled
    """Fill the chain's link axes, joints and centres of mass at the poses in the rows of Q.

    ``lengths`` and ``offsets`` (B, n+1): link lengths and centre-of-mass distances from each
    link's start, m; ``Q`` (m, n), rad. ``axes`` (m, 2, n+1) receives the cosines and sines
    of the links' world angles phi_i = q_1 + ... + q_i (phi_0 = 0), ``joints`` and ``coms``
    (B, m, 2, n) x and z (z flipped) of joints 1..n and of the centres of mass of links 1..n,
    m: joint j is the sum of L_i (cos phi_i, sin phi_i) over i < j + 1, the centre of link
    j + 1 lies off_(j+1) further along its axis.
    """
    m, n = Q.shape
    B = lengths.shape[0]
    for p in range(m):
        phi = 0.0
        axes[p, 0, 0] = 1.0
        axes[p, 1, 0] = 0.0
        for i in range(n):
            phi += Q[p, i]
            axes[p, 0, i + 1] = math.cos(phi)
            axes[p, 1, i + 1] = math.sin(phi)
    for b in range(B):
        for p in range(m):
            for c in range(2):
                acc = 0.0
                for j in range(n):
                    acc += lengths[b, j] * axes[p, c, j]
                    joints[b, p, c, j] = acc
                    coms[b, p, c, j] = acc + offsets[b, j + 1] * axes[p, c, j + 1]
