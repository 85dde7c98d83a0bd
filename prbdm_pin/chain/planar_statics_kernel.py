"""The planar chain's damped Newton statics under a dead tip force, in one compiled call (numba).

:func:`prbdm_pin.chain.statics._newton` at the full load, step for step: the potential
V(q) = 1/2 q^T K q - F . p_tip(q) of :class:`prbdm_pin.chain.planar.ChainPotential`, its
gradient K q - J^T F and Hessian diag(K) - d(J^T F)/dq from the lever arms
c_m = sum_(i >= m) L_i cos phi_i, s_m = sum_(i >= m) L_i sin phi_i, a Cholesky step
(:mod:`.small_cholesky`) capped at ``max_step`` and Armijo backtracking that also takes a step
which halves the gradient. Its numpy form costs about 80 us for a 5-joint chain, nearly all of
it numpy's calls on five numbers.

Only the plain descent is here: wherever the numpy path would leave it (a Hessian that is not
positive definite, a residual that is not finite, a backtracking or iteration budget spent)
this answers False, and the caller runs the numpy path from the start, with its load stepping,
saddle escape and errors. Imported on first use only.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .small_cholesky import cholesky_solve

__all__ = ["planar_newton", "load_stiffness_into"]

_IN1 = numba.types.Array(numba.float64, 1, "A", readonly=True)
_OUT1 = numba.types.Array(numba.float64, 1, "C")
_MAX_HALVINGS = 40  # as the numpy path's backtracking


@numba.njit(cache=True)
def _arms(lengths, q, c, s, rc, rs):  # pragma: no cover - compiled
    """Cosines, sines and lever arms (c_m, s_m) of the link angles phi_i = q_1 + ... + q_i."""
    n = q.size
    phi = 0.0
    for i in range(n):
        phi += q[i]
        c[i] = math.cos(phi)
        s[i] = math.sin(phi)
    ac = 0.0
    asn = 0.0
    for i in range(n - 1, -1, -1):
        ac += lengths[i + 1] * c[i]
        asn += lengths[i + 1] * s[i]
        rc[i] = ac
        rs[i] = asn


@numba.njit(cache=True)
def load_stiffness_into(lengths, q, fx, fz, c, s, rc, rs, T):  # pragma: no cover - compiled
    """T = d(J^T F)/dq at ``q`` into ``T`` (n, n), N m/rad: (-fx c_m + fz s_m), m = max(i, j).

    :func:`prbdm_pin.chain.planar.load_stiffness`'s closed form; ``c`` .. ``rs`` scratch (n,).
    """
    _arms(lengths, q, c, s, rc, rs)
    n = q.size
    for i in range(n):
        for j in range(n):
            m = max(i, j)
            T[i, j] = -fx * rc[m] + fz * rs[m]


@numba.njit(cache=True)
def _value(lengths, k, fx, fz, q, c, s, rc, rs):  # pragma: no cover - compiled
    """V(q), J: the springs' energy less the load's work on the tip (x = L_0 + c_0, z = -s_0)."""
    _arms(lengths, q, c, s, rc, rs)
    e = 0.0
    for i in range(q.size):
        e += q[i] * k[i] * q[i]
    return 0.5 * e - (fx * (lengths[0] + rc[0]) - fz * rs[0])


@numba.njit(cache=True)
def _gradient(lengths, k, fx, fz, q, c, s, rc, rs, g):  # pragma: no cover - compiled
    """Write K q - J^T F into ``g``; returns (|g|, max(|K q|, |J^T F|, 1e-300)), N m."""
    _arms(lengths, q, c, s, rc, rs)
    gg = 0.0
    kk = 0.0
    jj = 0.0
    for i in range(q.size):
        kq = k[i] * q[i]
        jtf = -fx * rs[i] - fz * rc[i]
        g[i] = kq - jtf
        gg += g[i] * g[i]
        kk += kq * kq
        jj += jtf * jtf
    return math.sqrt(gg), max(math.sqrt(kk), math.sqrt(jj), 1e-300)


@numba.njit(numba.types.boolean(_IN1, _IN1, numba.float64, numba.float64, numba.float64,
                                numba.int64, numba.float64, _OUT1), cache=True)
def planar_newton(lengths, k, fx, fz, rtol, max_iter, max_step, q):  # pragma: no cover
    """Descend from the pose ``q`` (rad, updated in place) to the equilibrium under (fx, fz).

    Parameters
    ----------
    lengths : ndarray (n+1,)
        Link lengths, m (link 0 clamped).
    k : ndarray (n,)
        Joint springs, N m/rad.
    fx, fz : float
        The dead tip force's world x and z, N.
    rtol : float
        Converged when |K q - J^T F| <= rtol max(|K q|, |J^T F|) at a minimum of V.
    max_iter : int
        Newton steps at most.
    max_step : float
        Largest change of one angle per step, rad.
    q : ndarray (n,)
        The start; receives the equilibrium.

    Returns
    -------
    bool
        True at a converged minimum; False where the numpy path would go on otherwise
        (``q`` then undefined).
    """
    n = k.size
    c, s, rc, rs = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    g, d, qn, H, L = np.empty(n), np.empty(n), np.empty(n), np.empty((n, n)), np.empty((n, n))
    for it in range(max_iter + 1):
        gn, scale = _gradient(lengths, k, fx, fz, q, c, s, rc, rs, g)
        if not (math.isfinite(gn) and math.isfinite(scale)):
            return False
        load_stiffness_into(lengths, q, fx, fz, c, s, rc, rs, H)
        for i in range(n):  # H = diag(k) - T
            for j in range(n):
                H[i, j] = -H[i, j]
            H[i, i] += k[i]
        pd = cholesky_solve(H, L, g, d)
        if gn <= rtol * scale:
            return pd
        if not pd or it == max_iter:
            return False
        step = 0.0
        for i in range(n):
            d[i] = -d[i]
            step = max(step, abs(d[i]))
        if step > max_step:
            for i in range(n):
                d[i] *= max_step / step
        v0 = _value(lengths, k, fx, fz, q, c, s, rc, rs)
        slope = 0.0
        for i in range(n):
            slope += g[i] * d[i]
        alpha = 1.0
        accepted = False
        for _ in range(_MAX_HALVINGS):
            for i in range(n):
                qn[i] = q[i] + alpha * d[i]
            if _value(lengths, k, fx, fz, qn, c, s, rc, rs) <= \
                    v0 + 1e-4 * alpha * min(slope, 0.0):
                accepted = True
                break
            if _gradient(lengths, k, fx, fz, qn, c, s, rc, rs, g)[0] < 0.5 * gn:
                accepted = True
                break
            alpha *= 0.5
        if not accepted:
            return False
        for i in range(n):
            q[i] = qn[i]
    return False
