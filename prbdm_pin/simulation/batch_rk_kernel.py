"""A step of an explicit Runge-Kutta pair over blocks of planar chains, compiled (numba).

The stages, the error norm and the dense output of :mod:`.batch_rk`'s shared step, for B
designs in blocks of W (arrays (blocks, ..., W), the designs innermost): each block's stages
are evaluated one after another while its arrays sit in the cache, each stage one call of
:func:`prbdm_pin.chain.planar_batch_kernel.block_rates` on the whole block. The tables are
scipy's (``A`` with the step's end and the interpolant's extra stages as rows, see
:func:`.batch_rk.stage_table`); the error norm is scipy's, design by design. Imported on the
first batched run only (numba).
"""

from __future__ import annotations

import math

import numba

from ..chain.planar_batch_kernel import block_rates

__all__ = ["stages", "dense"]


@numba.njit(cache=True, error_model="numpy")
def stages(P, n, m, damped, gained, FT, UT, T, Y, K, Ynew, A, h, s0, s1, ns, E5, E3,
           dop, rtol, atol, errs, X, S):  # pragma: no cover - compiled
    """Evaluate the stages s0 <= s < s1 of every block; with s1 = ns + 1, the error norms.

    Stage s is f at Y + h sum_(j < s) A[s, j] K_j (time t + C_s h: its inputs FT[s], UT[s]);
    stage ns is f at the step's end, Ynew (also written). errs (blocks * W,): each design's
    scaled error norm, scipy's: DOP853's blend of the 5th- and 3rd-order estimates (``dop``)
    or the single estimate of RK45 (E5), over tolerances atol (blocks, W) and rtol.
    """
    nc, d, W = Y.shape
    for c in range(nc):
        Yc, Kc = Y[c], K[c]
        for s in range(s0, s1):
            dst = Ynew[c] if s == ns else X
            for i in range(d):
                for b in range(W):
                    dst[i, b] = 0.0
                for j in range(s):
                    a = h * A[s, j]
                    if a != 0.0:
                        for b in range(W):
                            dst[i, b] += a * Kc[j, i, b]
                for b in range(W):
                    dst[i, b] += Yc[i, b]
            block_rates(P[c], n, m, damped, gained, FT[s], UT[s], T, dst, Kc[s], S)
        if s1 == ns + 1:
            _errors(Yc, Ynew[c], Kc, E5, E3, dop, h, rtol, atol[c], errs[c * W:(c + 1) * W],
                    ns, S)


@numba.njit(cache=True, error_model="numpy")
def _errors(Y, Ynew, K, E5, E3, dop, h, rtol, atol, out, ns, S):  # pragma: no cover
    """Each design's scipy error norm of the step Y -> Ynew (stages K) into out (W,)."""
    d, W = Y.shape
    for b in range(W):
        S[0, b] = 0.0
        S[1, b] = 0.0
    for i in range(d):
        for b in range(W):
            S[2, b] = 0.0
            S[3, b] = 0.0
        for j in range(ns + 1):
            e5, e3 = E5[j], E3[j]
            for b in range(W):
                S[2, b] += e5 * K[j, i, b]
                S[3, b] += e3 * K[j, i, b]
        for b in range(W):
            sc = atol[b] + max(abs(Y[i, b]), abs(Ynew[i, b])) * rtol
            r5, r3 = S[2, b] / sc, S[3, b] / sc
            S[0, b] += r5 * r5
            S[1, b] += r3 * r3
    for b in range(W):
        e5, e3 = S[0, b], S[1, b]
        if not dop:
            out[b] = h * math.sqrt(e5 / d)
        elif e5 == 0.0 and e3 == 0.0:
            out[b] = 0.0
        else:
            out[b] = h * e5 / math.sqrt((e5 + 0.01 * e3) * d)


@numba.njit(cache=True)
def dense(Y, Ynew, K, wts, a, h, out, j0, B, acc):  # pragma: no cover - compiled
    """Write the interpolant at some times into out[:, j0 + r] (B, samples, d), r < len(a).

    Sample r is Y + a_r (Ynew - Y) + h sum_s wts[r, s] K_s (the weights of the sample's time,
    the same for every design); the blocks' padding designs (index >= B) are skipped. acc:
    scratch (W,).
    """
    nc, d, W = Y.shape
    ns = wts.shape[1]
    for c in range(nc):
        Yc, Zc, Kc = Y[c], Ynew[c], K[c]
        w = min(W, B - c * W)
        for r in range(a.size):
            ar = a[r]
            for i in range(d):
                for b in range(W):
                    acc[b] = Yc[i, b] + ar * (Zc[i, b] - Yc[i, b])
                for s in range(ns):
                    hw = h * wts[r, s]
                    for b in range(W):
                        acc[b] += hw * Kc[s, i, b]
                for b in range(w):
                    out[c * W + b, j0 + r, i] = acc[b]
