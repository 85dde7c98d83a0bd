"""scipy's DOP853 as one compiled run on the chain kernel (the numba side of ``"compiled"``).

A line-for-line port of ``scipy.integrate.DOP853`` (``_ivp/rk.py`` and ``common.py``): the
same stages, the same error norm (the 5th- and 3rd-order estimates blended as
``|h| e5^2 / sqrt((e5^2 + 0.01 e3^2) N)``), the same controller (safety 0.9, factors in
[0.2, 10], exponent -1/8, no growth right after a rejection), the same initial step
(``select_initial_step``, order 7) and the same 7th-order dense output; the coefficients are
scipy's own arrays, passed in. The right-hand side is the kernel's forward dynamics with the
springs, a frozen damping matrix and a constant world tip force:

    M(q) a = -K q - C v + J(q)^T f - h(q, v)

Status codes: 0 done, 1 step below scipy's minimum, 2 more than ``max_steps`` steps,
3 a mass matrix that is not positive definite or a state that is not finite.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _co

from ..kernel.dynamics import (
    body_inertias,
    cholesky_solve,
    crba,
    kinematics,
    rnea_bias,
    tip_force_torque,
)

__all__ = ["dop853_run", "COEFFICIENTS"]

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
N_STAGES = _co.N_STAGES  # 12
# scipy's own arrays, in dop853_run's argument order (A, B, C, E3, E5, D)
COEFFICIENTS = tuple(np.ascontiguousarray(a, dtype=float)
                     for a in (_co.A, _co.B, _co.C, _co.E3, _co.E5, _co.D))
EXPONENT = -1.0 / 8.0  # -1 / (error estimator order 7 + 1)


@numba.njit(cache=True)
def _rhs(K, W, k, C, damped, f, forced, y, out):
    """Write (v, a) at the state y = (q, v) into out; False if M is not positive definite."""
    jtype, jaxis, Rp, pp, mass, com, Ic, tj, _, tp, grav = K
    Rw, ow, S, mc, IO, cm, cmc, cIO, V, A, F, M, L, h, tau, a = W
    n = k.size
    q, v = y[:n], y[n:]
    kinematics(jtype, jaxis, Rp, pp, q, Rw, ow, S)
    body_inertias(mass, com, Ic, Rw, ow, mc, IO)
    crba(mass, S, mc, IO, cm, cmc, cIO, F, M)
    rnea_bias(mass, grav, S, mc, IO, v, V, A, F, h)
    for i in range(n):
        s = -k[i] * q[i] - h[i]
        if damped:
            for j in range(n):
                s -= C[i, j] * v[j]
        tau[i] = s
    if forced:
        tip_force_torque(tj[0], tp, Rw, ow, S, f, tau)
    ok = cholesky_solve(M, L, tau, a)
    for i in range(n):
        out[i] = v[i]
        out[n + i] = a[i]
    return ok


@numba.njit(cache=True)
def _rms(x, scale):
    s = 0.0
    for i in range(x.size):
        r = x[i] / scale[i]
        s += r * r
    return math.sqrt(s / x.size)


@numba.njit(cache=True)
def _stages(K, W, k, C, damped, f, forced, y, Kst, A, B, h, s0, s1, tmp, y_new):
    """Evaluate the stages s0 <= s < s1 into Kst; False if a mass matrix was not SPD.

    Stage s is f at y + h sum_{j < s} A[s, j] K_j, stage N_STAGES f at the step's end
    y_new = y + h sum_j B_j K_j (also written). The run's only dynamics call site.
    """
    ok = True
    for s in range(s0, s1):
        src = tmp
        if s == N_STAGES:
            src = y_new
        for i in range(y.size):
            acc = 0.0
            if s == N_STAGES:
                for j in range(N_STAGES):
                    acc += B[j] * Kst[j, i]
            else:
                for j in range(s):
                    acc += A[s, j] * Kst[j, i]
            src[i] = y[i] + h * acc
        ok &= _rhs(K, W, k, C, damped, f, forced, src, Kst[s])
    return ok


@numba.njit(cache=True)
def _error_norm(Kst, E3, E5, y, y_new, rtol, atol, h_abs):
    """Return scipy DOP853's error norm of the step y -> y_new (stages in Kst)."""
    e5, e3 = 0.0, 0.0
    N = y.size
    for i in range(N):
        sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
        a5, a3 = 0.0, 0.0
        for j in range(N_STAGES + 1):
            a5 += Kst[j, i] * E5[j]
            a3 += Kst[j, i] * E3[j]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return h_abs * e5 / math.sqrt((e5 + 0.01 * e3) * N)


@numba.njit(cache=True)
def _interpolant(Kst, D, y, y_new, h, F):
    """Write scipy's Dop853DenseOutput coefficients F (7, N) of the step (after its stages)."""
    for i in range(y.size):
        dy = y_new[i] - y[i]
        F[0, i] = dy
        F[1, i] = h * Kst[0, i] - dy
        F[2, i] = 2.0 * dy - h * (Kst[N_STAGES, i] + Kst[0, i])
        for r in range(4):
            acc = 0.0
            for j in range(16):
                acc += D[r, j] * Kst[j, i]
            F[3 + r, i] = h * acc


@numba.njit(cache=True)
def _dense(F, y_old, x, out):
    """Evaluate scipy's Dop853DenseOutput at x = (t - t_old) / h, into out."""
    nF = F.shape[0]
    for i in range(y_old.size):
        acc = 0.0
        for r in range(nF):
            acc += F[nF - 1 - r, i]
            acc *= x if r % 2 == 0 else 1.0 - x
        out[i] = acc + y_old[i]


@numba.njit(cache=True)
def dop853_run(K, W, k, C, damped, f, forced, t0, y0, t_bound, rtol, atol, t_out,
               every_step, max_steps, A, B, Cs, E3, E5, D, Y_out):
    """Integrate from (t0, y0) to t_bound; samples at ``t_out`` into ``Y_out`` or every step.

    Returns (status, steps, evaluations, t reached, step times, step states); the last two are
    filled only when ``every_step`` (the start included).
    """
    N = y0.size
    Kst = np.empty((16, N))
    y, y_new, tmp, scale = y0.copy(), np.empty(N), np.empty(N), np.empty(N)
    F = np.empty((7, N))
    cap = 64 if every_step else 0
    ts, ys = np.empty(cap), np.empty((cap, N))
    m = 0
    if every_step:
        ts[0] = t0
        ys[0] = y0
        m = 1
    steps, ks = 0, 0
    t = t0
    # f(t0, y0) is stage 0 at h = 0; the initial step's trial f(y0 + h0 f0) is stage 1 with
    # h = h0 / A[1, 0] (scipy's select_initial_step, order 7)
    if not _stages(K, W, k, C, damped, f, forced, y, Kst, A, B, 0.0, 0, 1, tmp, y_new):
        return 3, steps, 1, t, ts[:m], ys[:m]
    interval = t_bound - t0
    for i in range(N):
        scale[i] = atol + abs(y[i]) * rtol
    d0, d1 = _rms(y, scale), _rms(Kst[0], scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    _stages(K, W, k, C, damped, f, forced, y, Kst, A, B, h0 / A[1, 0], 1, 2, tmp, y_new)
    nfev = 2
    for i in range(N):
        tmp[i] = Kst[1, i] - Kst[0, i]
    d2 = _rms(tmp, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h_abs = min(100.0 * h0, h1, interval)
    nt = t_out.size
    while t < t_bound:
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                return 1, steps, nfev, t, ts[:m], ys[:m]
            t_new = t + h_abs
            if t_new - t_bound > 0.0:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)
            ok = _stages(K, W, k, C, damped, f, forced, y, Kst, A, B, h, 1, N_STAGES + 1,
                         tmp, y_new)
            nfev += N_STAGES
            if not ok:
                return 3, steps, nfev, t, ts[:m], ys[:m]
            err = _error_norm(Kst, E3, E5, y, y_new, rtol, atol, h_abs)
            if err < 1.0:
                factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            factor = SAFETY * err ** EXPONENT
            h_abs *= factor if factor > MIN_FACTOR else MIN_FACTOR  # also a NaN error
            rejected = True
            # stage 0 is f at the step's start, kept for the retry
        steps += 1
        if steps > max_steps:
            return 2, steps, nfev, t, ts[:m], ys[:m]
        done = not t_new < t_bound
        if every_step:
            if m == cap:
                cap *= 2
                ts2, ys2 = np.empty(cap), np.empty((cap, N))
                ts2[:m] = ts[:m]
                ys2[:m] = ys[:m]
                ts, ys = ts2, ys2
            ts[m] = t_new
            ys[m] = y_new
            m += 1
        else:
            end = nt
            if not done:
                end = ks
                while end < nt and t_out[end] < t_new:
                    end += 1
            if end > ks:
                # the three extra stages of the 7th-order interpolant, only for a sampled step
                _stages(K, W, k, C, damped, f, forced, y, Kst, A, B, h, N_STAGES + 1, 16,
                        tmp, y_new)
                nfev += 3
                _interpolant(Kst, D, y, y_new, h, F)
                for j in range(ks, end):
                    _dense(F, y, (t_out[j] - t) / h, Y_out[j])
                ks = end
        t = t_new
        for i in range(N):
            y[i] = y_new[i]
            Kst[0, i] = Kst[N_STAGES, i]  # f at the new start: scipy's FSAL
    return 0, steps, nfev, t, ts[:m], ys[:m]
