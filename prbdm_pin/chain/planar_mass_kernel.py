"""The planar chain's mass matrices assembled from its points in one compiled call (numba).

:func:`prbdm_pin.chain.planar_mass.planar_mass_matrices`' sum, for one design or a stack: the
numpy form (a stacked matrix product R^T R of the lever arms and an indexed add of the link
inertias) made six numpy calls whose cost, for a short chain, was many times the arithmetic.
Imported on first use only (the package's import and the CLI do not load numba).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["mass_from_points"]


# one signature, inputs read-only (a writable array converts; the sections' arrays are not)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_IN4 = numba.types.Array(numba.float64, 4, "A", readonly=True)
_OUT4 = numba.types.Array(numba.float64, 4, "A")


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
