"""The steps of an explicit Runge-Kutta pair over a block of planar chains, compiled (numba).

:mod:`.batch_rk`'s stepping for one block of W designs (arrays (..., W), the designs
innermost): the stages, each one call of
:func:`prbdm_pin.chain.planar_batch_kernel.block_rates` on the whole block, scipy's error norm
design by design, scipy's step-size rule on the largest, and scipy's dense output at the sample
times, with no Python per step (:func:`advance`). The tables are scipy's (``A`` with the step's
end and the interpolant's extra stages as rows, see :func:`.batch_rk.stage_table`). Imported on
the first batched run only (numba).

Status codes: 0 done (or, with ``once``, one attempt made), 1 step below scipy's minimum,
2 more than ``max_steps`` steps, 3 a state that is not finite.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..chain.planar_batch_kernel import block_rates
from ..chain.planar_batch_tip import block_tip

__all__ = ["block_stages", "advance"]

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0  # scipy's step-size rule


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def block_stages(P, n, m, damped, gained, FT, UT, T, Y, K, Ynew, A, h, s0, s1, ns, X,
                 S):  # pragma: no cover - compiled
    """Evaluate the stages s0 <= s < s1 of the block into K (S, d, W).

    Stage s is f at Y + h sum_(j < s) A[s, j] K_j (time t + C_s h: its inputs FT[s], UT[s]);
    stage ns is f at the step's end, Ynew (also written).
    """
    d, W = Y.shape
    for s in range(s0, s1):
        dst = Ynew if s == ns else X
        for i in range(d):
            for b in range(W):
                dst[i, b] = 0.0
            for j in range(s):
                a = h * A[s, j]
                if a != 0.0:
                    for b in range(W):
                        dst[i, b] += a * K[j, i, b]
            for b in range(W):
                dst[i, b] += Y[i, b]
        block_rates(P, n, m, damped, gained, FT[s], UT[s], T, dst, K[s], S)


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def _error(Y, Ynew, K, E5, E3, dop, h, rtol, atol, ns, S):  # pragma: no cover - compiled
    """Return the largest over the block of each design's scipy error norm (NaN if any is).

    DOP853's blend of the 5th- and 3rd-order estimates (``dop``) or RK45's one (E5), over the
    tolerances atol (W,) and rtol.
    """
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
    worst = 0.0
    for b in range(W):
        e5, e3 = S[0, b], S[1, b]
        if not dop:
            e = h * math.sqrt(e5 / d)
        elif e5 == 0.0 and e3 == 0.0:
            e = 0.0
        else:
            e = h * e5 / math.sqrt((e5 + 0.01 * e3) * d)
        if not e <= worst:  # a larger one, or NaN (which then stays)
            worst = e
            if e != e:
                return e
    return worst


@numba.njit(cache=True)
def _weights(dop, ns, P45, D, x, w):  # pragma: no cover - compiled
    """Write the interpolant's stage weights at x = (t - t_old) / h into w; return a.

    The sample is y_old + a (y - y_old) + h w . K: scipy's interpolants are linear in the
    step's increment and stages with coefficients of x only. DOP853's seven terms F (dy,
    h f_old - dy, 2 dy - h (f + f_old), h D K) are nested in x and 1 - x, so F_k's coefficient
    is the product of the factors applied after it; RK45's is h K^T P (x, x^2, x^3, x^4).
    """
    for s in range(w.size):
        w[s] = 0.0
    if not dop:
        for j in range(P45.shape[0]):
            acc, xp = 0.0, 1.0
            for r in range(P45.shape[1]):
                xp *= x
                acc += P45[j, r] * xp
            w[j] = acc
        return 0.0
    c = np.empty(7)
    c[0] = x  # the last factor (i = 6) is x
    for k in range(1, 7):
        i = 6 - k
        c[k] = c[k - 1] * (x if i % 2 == 0 else 1.0 - x)
    w[0] += c[1] - c[2]
    w[ns] -= c[2]
    for r in range(D.shape[0]):
        for j in range(D.shape[1]):
            w[j] += c[3 + r] * D[r, j]
    return c[0] - c[1] + 2.0 * c[2]


@numba.njit(cache=True)
def _dense(Y, Ynew, K, h, a, w, P, n, out, tips, j, idx, S):  # pragma: no cover - compiled
    """Write the sample Y + a (Ynew - Y) + h w . K of each design b into out[idx[b], j].

    And its tip position into tips[idx[b], j] (the block's lengths: P's first rows). S: scratch
    (>= d + 3 rows).
    """
    d, W = Y.shape
    for i in range(d):
        for b in range(W):
            S[i, b] = Y[i, b] + a * (Ynew[i, b] - Y[i, b])
        for s in range(w.size):
            hw = h * w[s]
            for b in range(W):
                S[i, b] += hw * K[s, i, b]
    block_tip(P, S, n, S[d:d + 3])
    for b in range(W):
        g = idx[b]
        if g >= 0:
            for i in range(d):
                out[g, j, i] = S[i, b]
            tips[g, j, 0] = S[d, b]
            tips[g, j, 1] = 0.0
            tips[g, j, 2] = S[d + 1, b]


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def advance(P, n, m, damped, gained, FT, UT, T, Y, K, Ynew, X, S, A, C, ns, E5, E3, dop, P45,
            D, exponent, rtol, atol, t_end, max_steps, t_out, Y_out, tips, idx, ints, fl,
            once):  # pragma: no cover - compiled
    """Step the block from its state to t_end (with ``once``: make one attempt); the status.

    The state between calls: fl = [t, h], ints = [steps, rejected, evaluations, next sample,
    last attempt rejected, last attempt accepted]; Y holds y(t) and K[0] f(t, y) (FSAL). The
    samples at t_out (s) go to Y_out[idx[b]] and their tip positions (m) to tips[idx[b]]
    (idx < 0: a padding lane); with no samples
    (t_out empty) an accepted step leaves y(t) in Y for the caller to read.
    """
    Sn = K.shape[0]
    nt = t_out.size
    w = np.empty(Sn)
    while fl[0] < t_end:
        t, h_abs = fl[0], fl[1]
        if ints[0] >= max_steps:
            return 2
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs < min_step:
            return 1
        t_new = min(t + h_abs, t_end)
        h = t_new - t
        block_stages(P, n, m, damped, gained, FT, UT, T, Y, K, Ynew, A, h, 1, ns + 1, ns, X, S)
        ints[2] += ns
        err = _error(Y, Ynew, K, E5, E3, dop, h, rtol, atol, ns, S)
        if not err == err or math.isinf(err):
            return 3
        ints[5] = 1 if err < 1.0 else 0
        if err < 1.0:
            factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** exponent)
            if ints[4]:
                factor = min(1.0, factor)
            ints[4] = 0
            ints[0] += 1
            # as the single run samples: the times in [t, t_new), the last step also the end
            # and its rounding slack beyond
            k, end = ints[3], nt
            if t_new < t_end:
                end = k
                while end < nt and t_out[end] < t_new:
                    end += 1
            if end > k and Sn > ns + 1:  # DOP853's interpolant: three more stages
                block_stages(P, n, m, damped, gained, FT, UT, T, Y, K, Ynew, A, h, ns + 1, Sn,
                             ns, X, S)
                ints[2] += Sn - ns - 1
            for j in range(k, end):
                a = _weights(dop, ns, P45, D, (t_out[j] - t) / h, w)
                _dense(Y, Ynew, K, h, a, w, P, n, Y_out, tips, j, idx, S)
            ints[3] = end
            Y[:] = Ynew
            K[0] = K[ns]  # f at the new start (FSAL)
            fl[0], fl[1] = t_new, h * factor
        else:
            ints[1] += 1
            ints[4] = 1
            fl[1] = h * max(MIN_FACTOR, SAFETY * err ** exponent)
        if once:
            return 0
    return 0
