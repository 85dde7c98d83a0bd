"""The compiled chain dynamics: kinematics, CRBA, RNEA, forward dynamics and the tip force.

numba functions on the arrays of a :class:`~.build.ChainKernel` (``K``, ``kernel.arrays()``)
and a :class:`~.build.KernelData` workspace (``W``, ``data.arrays()``); they write into the
workspace and allocate nothing.

Everything is computed in the world frame at the world origin (Featherstone's absolute
formulation): joint i's unit motion S_i (linear, angular) is (o_i x a_i, a_i) for a revolute
joint of world axis a_i through o_i and (a_i, 0) for a prismatic one; the bodies' spatial
inertias about the origin simply add, so the mass matrix is M_ij = S_i . (I^c_j S_j) for
i <= j with I^c_j the composite inertia of bodies j..n-1 (O(n^2), no frame transforms), and
the bias forces h(q, v) are the RNEA with a = 0 and the base accelerating at -g (so the
weight is included). Forward dynamics solves M a = tau - h by Cholesky: for n <= 16 the
O(n^2) CRBA plus an n^3/6 factorisation (680 multiply-adds at n = 16) costs about what one
O(n) ABA pass costs with its 6x6 articulated inertias (several hundred per joint), and M is
what the mass matrix and the integrator's callers need anyway.
"""

from __future__ import annotations

import math

import numba

from ..chain.small_cholesky import cholesky_solve

__all__ = ["kinematics", "body_inertias", "crba", "rnea_bias", "cholesky_solve",
           "tip_position", "tip_force_torque", "forward_dynamics"]


@numba.njit(cache=True)
def kinematics(jtype, jaxis, Rp, pp, q, Rw, ow, S):
    """Joint frames (rotation Rw, origin ow) and world unit motions S of pose ``q``."""
    n = q.size
    for i in range(n):
        # R_i = R_parent Rp_i (then the joint's rotation), o_i = o_parent + R_parent pp_i
        for r in range(3):
            if i == 0:
                for c in range(3):
                    Rw[i, r, c] = Rp[i, r, c]
                ow[i, r] = pp[i, r]
            else:
                for c in range(3):
                    Rw[i, r, c] = Rw[i - 1, r, 0] * Rp[i, 0, c] + Rw[i - 1, r, 1] * Rp[i, 1, c] \
                        + Rw[i - 1, r, 2] * Rp[i, 2, c]
                ow[i, r] = ow[i - 1, r] + Rw[i - 1, r, 0] * pp[i, 0] \
                    + Rw[i - 1, r, 1] * pp[i, 1] + Rw[i - 1, r, 2] * pp[i, 2]
        ax = jaxis[i]
        if jtype[i] == 0:
            # the joint's axis column stays; about axis ax, column a -> c e_a + s e_b and
            # column b -> -s e_a + c e_b
            for r in range(3):
                S[i, 3 + r] = Rw[i, r, ax]
            a, b = (ax + 1) % 3, (ax + 2) % 3
            cq, sq = math.cos(q[i]), math.sin(q[i])
            for r in range(3):
                ta, tb = Rw[i, r, a], Rw[i, r, b]
                Rw[i, r, a] = cq * ta + sq * tb
                Rw[i, r, b] = -sq * ta + cq * tb
            # the origin's velocity on a rotation about o_i: o_i x a_i
            S[i, 0] = ow[i, 1] * S[i, 5] - ow[i, 2] * S[i, 4]
            S[i, 1] = ow[i, 2] * S[i, 3] - ow[i, 0] * S[i, 5]
            S[i, 2] = ow[i, 0] * S[i, 4] - ow[i, 1] * S[i, 3]
        else:
            for r in range(3):
                S[i, r] = Rw[i, r, ax]
                S[i, 3 + r] = 0.0
                ow[i, r] += Rw[i, r, ax] * q[i]


@numba.njit(cache=True)
def body_inertias(mass, com, Ic, Rw, ow, mc, IO):
    """Each body's first moment m c and rotational inertia IO about the world origin (world)."""
    n = mass.size
    for i in range(n):
        m = mass[i]
        c0 = ow[i, 0] + Rw[i, 0, 0] * com[i, 0] + Rw[i, 0, 1] * com[i, 1] + Rw[i, 0, 2] * com[i, 2]
        c1 = ow[i, 1] + Rw[i, 1, 0] * com[i, 0] + Rw[i, 1, 1] * com[i, 1] + Rw[i, 1, 2] * com[i, 2]
        c2 = ow[i, 2] + Rw[i, 2, 0] * com[i, 0] + Rw[i, 2, 1] * com[i, 1] + Rw[i, 2, 2] * com[i, 2]
        mc[i, 0], mc[i, 1], mc[i, 2] = m * c0, m * c1, m * c2
        cc = c0 * c0 + c1 * c1 + c2 * c2
        for r in range(3):
            # row r of R Ic, then (R Ic R^T)[r, k]
            ri0 = Rw[i, r, 0] * Ic[i, 0, 0] + Rw[i, r, 1] * Ic[i, 1, 0] + Rw[i, r, 2] * Ic[i, 2, 0]
            ri1 = Rw[i, r, 0] * Ic[i, 0, 1] + Rw[i, r, 1] * Ic[i, 1, 1] + Rw[i, r, 2] * Ic[i, 2, 1]
            ri2 = Rw[i, r, 0] * Ic[i, 0, 2] + Rw[i, r, 1] * Ic[i, 1, 2] + Rw[i, r, 2] * Ic[i, 2, 2]
            cr = c0 if r == 0 else (c1 if r == 1 else c2)
            for k in range(3):
                ck = c0 if k == 0 else (c1 if k == 1 else c2)
                # parallel axes to the origin: m (|c|^2 1 - c c^T)
                IO[i, r, k] = ri0 * Rw[i, k, 0] + ri1 * Rw[i, k, 1] + ri2 * Rw[i, k, 2] \
                    + m * ((cc if r == k else 0.0) - cr * ck)


@numba.njit(cache=True)
def _inertia_times(m, mc, IO, x, out, i):
    """Row i: spatial inertia (m, m c, I_O)[i] about the origin times the motion x[i] = (v, w).

    Rows by index, not views: a view costs its reference count in the inner loop.
    """
    v0, v1, v2, w0, w1, w2 = x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5]
    c0, c1, c2 = mc[i, 0], mc[i, 1], mc[i, 2]
    # linear momentum m v + w x (m c); angular (m c) x v + I_O w
    out[i, 0] = m * v0 + w1 * c2 - w2 * c1
    out[i, 1] = m * v1 + w2 * c0 - w0 * c2
    out[i, 2] = m * v2 + w0 * c1 - w1 * c0
    out[i, 3] = c1 * v2 - c2 * v1 + IO[i, 0, 0] * w0 + IO[i, 0, 1] * w1 + IO[i, 0, 2] * w2
    out[i, 4] = c2 * v0 - c0 * v2 + IO[i, 1, 0] * w0 + IO[i, 1, 1] * w1 + IO[i, 1, 2] * w2
    out[i, 5] = c0 * v1 - c1 * v0 + IO[i, 2, 0] * w0 + IO[i, 2, 1] * w1 + IO[i, 2, 2] * w2


@numba.njit(cache=True)
def crba(mass, S, mc, IO, cm, cmc, cIO, F, M):
    """Mass matrix M(q) (after ``kinematics`` and ``body_inertias``; cm, cmc, cIO, F scratch)."""
    n = mass.size
    for j in range(n - 1, -1, -1):
        cm[j] = mass[j]
        for r in range(3):
            cmc[j, r] = mc[j, r]
            for k in range(3):
                cIO[j, r, k] = IO[j, r, k]
        if j < n - 1:
            cm[j] += cm[j + 1]
            for r in range(3):
                cmc[j, r] += cmc[j + 1, r]
                for k in range(3):
                    cIO[j, r, k] += cIO[j + 1, r, k]
        _inertia_times(cm[j], cmc, cIO, S, F, j)
        for i in range(j + 1):
            s = 0.0
            for r in range(6):
                s += S[i, r] * F[j, r]
            M[i, j] = s
            M[j, i] = s


@numba.njit(cache=True)
def rnea_bias(mass, grav, S, mc, IO, v, V, A, F, h):
    """Bias forces h(q, v) (Coriolis, centrifugal, weight), with V, A, F the bodies' motion.

    After ``kinematics`` and ``body_inertias``.
    """
    n = v.size
    for i in range(n):
        x0, x1, x2 = S[i, 0] * v[i], S[i, 1] * v[i], S[i, 2] * v[i]
        x3, x4, x5 = S[i, 3] * v[i], S[i, 4] * v[i], S[i, 5] * v[i]
        if i == 0:
            V[i, 0], V[i, 1], V[i, 2], V[i, 3], V[i, 4], V[i, 5] = x0, x1, x2, x3, x4, x5
            # the base accelerates up at g: the weight enters every body's force
            A[i, 0], A[i, 1], A[i, 2] = -grav[0], -grav[1], -grav[2]
            A[i, 3], A[i, 4], A[i, 5] = 0.0, 0.0, 0.0
        else:
            V[i, 0], V[i, 1], V[i, 2] = V[i - 1, 0] + x0, V[i - 1, 1] + x1, V[i - 1, 2] + x2
            V[i, 3], V[i, 4], V[i, 5] = V[i - 1, 3] + x3, V[i - 1, 4] + x4, V[i - 1, 5] + x5
            for r in range(6):
                A[i, r] = A[i - 1, r]
        v0, v1, v2, w0, w1, w2 = V[i, 0], V[i, 1], V[i, 2], V[i, 3], V[i, 4], V[i, 5]
        # A_i += V_i x (S_i v_i): (w x x_lin + v x x_ang, w x x_ang)
        A[i, 0] += w1 * x2 - w2 * x1 + v1 * x5 - v2 * x4
        A[i, 1] += w2 * x0 - w0 * x2 + v2 * x3 - v0 * x5
        A[i, 2] += w0 * x1 - w1 * x0 + v0 * x4 - v1 * x3
        A[i, 3] += w1 * x5 - w2 * x4
        A[i, 4] += w2 * x3 - w0 * x5
        A[i, 5] += w0 * x4 - w1 * x3
        # F_i = I_i A_i + V_i x* p, p = I_i V_i: (w x p_lin, w x p_ang + v x p_lin)
        _inertia_times(mass[i], mc, IO, V, F, i)
        p0, p1, p2, p3, p4, p5 = F[i, 0], F[i, 1], F[i, 2], F[i, 3], F[i, 4], F[i, 5]
        _inertia_times(mass[i], mc, IO, A, F, i)
        F[i, 0] += w1 * p2 - w2 * p1
        F[i, 1] += w2 * p0 - w0 * p2
        F[i, 2] += w0 * p1 - w1 * p0
        F[i, 3] += w1 * p5 - w2 * p4 + v1 * p2 - v2 * p1
        F[i, 4] += w2 * p3 - w0 * p5 + v2 * p0 - v0 * p2
        F[i, 5] += w0 * p4 - w1 * p3 + v0 * p1 - v1 * p0
    for i in range(n - 1, -1, -1):
        if i < n - 1:
            for r in range(6):
                F[i, r] += F[i + 1, r]
        s = 0.0
        for r in range(6):
            s += S[i, r] * F[i, r]
        h[i] = s


@numba.njit(cache=True)
def tip_position(tj, tp, Rw, ow, out):
    """World position of the tip frame (after ``kinematics``), m, into ``out`` (3,)."""
    for r in range(3):
        out[r] = ow[tj, r] + Rw[tj, r, 0] * tp[0] + Rw[tj, r, 1] * tp[1] + Rw[tj, r, 2] * tp[2]


@numba.njit(cache=True)
def tip_force_torque(tj, tp, Rw, ow, S, f, out):
    """Add J(q)^T f of a world force ``f`` (N) at the tip to ``out`` (n,), N m.

    After ``kinematics``: the force's wrench at the origin (f, p x f) on each joint's unit motion
    up to the tip's joint ``tj`` (the tip at ``tp`` in its frame).
    """
    p0 = ow[tj, 0] + Rw[tj, 0, 0] * tp[0] + Rw[tj, 0, 1] * tp[1] + Rw[tj, 0, 2] * tp[2]
    p1 = ow[tj, 1] + Rw[tj, 1, 0] * tp[0] + Rw[tj, 1, 1] * tp[1] + Rw[tj, 1, 2] * tp[2]
    p2 = ow[tj, 2] + Rw[tj, 2, 0] * tp[0] + Rw[tj, 2, 1] * tp[1] + Rw[tj, 2, 2] * tp[2]
    m0 = p1 * f[2] - p2 * f[1]
    m1 = p2 * f[0] - p0 * f[2]
    m2 = p0 * f[1] - p1 * f[0]
    for i in range(tj + 1):
        out[i] += S[i, 0] * f[0] + S[i, 1] * f[1] + S[i, 2] * f[2] \
            + S[i, 3] * m0 + S[i, 4] * m1 + S[i, 5] * m2


@numba.njit(cache=True)
def forward_dynamics(K, W, q, v, tau):
    """Joint accelerations a = M(q)^-1 (tau - h(q, v)) into ``W``'s acceleration_joint.

    ``tau`` may be ``W``'s torque array (it is overwritten). Returns False when M is not
    positive definite (a degenerate chain).
    """
    jtype, jaxis, Rp, pp, mass, com, Ic, _, _, _, grav = K
    Rw, ow, S, mc, IO, cm, cmc, cIO, V, A, F, M, L, h, rhs, a = W
    kinematics(jtype, jaxis, Rp, pp, q, Rw, ow, S)
    body_inertias(mass, com, Ic, Rw, ow, mc, IO)
    crba(mass, S, mc, IO, cm, cmc, cIO, F, M)
    rnea_bias(mass, grav, S, mc, IO, v, V, A, F, h)
    for i in range(q.size):
        rhs[i] = tau[i] - h[i]
    return cholesky_solve(M, L, rhs, a)
