"""Compiled tip positions of planar chains, the designs innermost (numba).

p_tip = L_0 e_x + sum_i L_i (cos phi_i, 0, -sin phi_i), :mod:`.planar`'s closed form, over a
block of designs side by side (SIMD lanes, the polynomial sine and cosine of
:mod:`.planar_batch_kernel`): the batched simulation's samples' tips, computed with each sample
(numpy's version over a batch's samples cost a tenth of the batched run).
"""

from __future__ import annotations

import numba
import numpy as np

from .planar_batch_kernel import sincos

__all__ = ["block_tip", "batch_tips"]


@numba.njit(cache=True)
def block_tip(L, x, n, out):  # pragma: no cover - compiled
    """Write the tip's x and z (m) of a block at the joint angles x[:n] (rad) into out[:2].

    p_tip = L_0 e_x + sum_i L_i (cos phi_i, 0, -sin phi_i) (:mod:`.planar`'s closed form), the
    designs innermost; L: the lengths' rows (n+1, W), m; out (3, W), its last row scratch.
    """
    W = x.shape[1]
    for b in range(W):
        out[0, b] = L[0, b]
        out[1, b] = 0.0
        out[2, b] = 0.0
    for i in range(n):
        for b in range(W):
            p = out[2, b] + x[i, b]
            out[2, b] = p
            sn, c = sincos(p)
            out[0, b] += L[i + 1, b] * c
            out[1, b] -= L[i + 1, b] * sn


@numba.njit(cache=True)
def _tips(L, Y, out):  # pragma: no cover - compiled
    s = Y.shape[0]
    n = L.shape[0] - 1
    xz = np.empty((3, Y.shape[2]))
    for t in range(s):
        block_tip(L, Y[t], n, xz)
        out[t, 0] = xz[0]
        out[t, 2] = xz[1]


def batch_tips(lengths_m: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Return the tip positions (B, s, 3), m, of B chains' samples Y (B, s, >= n), q first, rad.

    :func:`block_tip` over the samples, the B designs one block; ``lengths_m`` (B, n+1), m.
    """
    B, s = Y.shape[:2]
    out = np.zeros((s, 3, B))
    _tips(np.ascontiguousarray(np.asarray(lengths_m, dtype=float).T),
          np.ascontiguousarray(np.moveaxis(Y, 0, 2)), out)
    return np.ascontiguousarray(np.moveaxis(out, 2, 0))
