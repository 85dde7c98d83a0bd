"""A trajectory gradient's per-stage arithmetic in compiled form (numba): torque, df/dx, S'.

The formulas are those of :mod:`.sensitivity_field` (the closed loop's torque and its state
and design derivatives) and :mod:`.sensitivity_run` (S' = (df/dx) S + df/dp and the cost's
gradient rate), with the planar chain's tip terms of :mod:`prbdm_pin.chain.planar` (lever arms
c_m, s_m: J^T F, the tip height and d(J^T F)/dq). Pinocchio's ``computeABADerivatives`` still
gives d a/dq, d a/dv and M^-1; what is compiled here is everything around it, which in numpy
took some forty array calls per stage (each costing more than a short chain's arithmetic).

Imported by :mod:`.sensitivity_field` on a gradient's first use (numba loads with it).
"""

from __future__ import annotations

import math

import numba

__all__ = ["closed_loop_torque", "joint_torque", "state_jacobian", "stage_rates"]


@numba.njit(cache=True)
def closed_loop_torque(L, q, v, u, k, beta, c, B, force, rc, rs, tau):
    """Write tau = -K (q + beta v) - c v + J^T F + B u (N m) and the lever arms; return z (m).

    ``L`` (n+1,) the link lengths (m, the clamped one first), ``rc``/``rs`` (n,) receive
    c_m = sum_(i >= m) L_i cos phi_i and s_m likewise with sines (the tip height is -s_0, its
    gradient dz/dq = -c).
    """
    n = q.size
    phi = 0.0
    for i in range(n):
        phi += q[i]
        rc[i] = L[i + 1] * math.cos(phi)
        rs[i] = L[i + 1] * math.sin(phi)
    for i in range(n - 2, -1, -1):
        rc[i] += rc[i + 1]
        rs[i] += rs[i + 1]
    fx, fz = force[0], force[2]
    for r in range(n):
        tau[r] = joint_torque(r, q, v, u, k, beta, c, B) - fx * rs[r] - fz * rc[r]
    return -rs[0]


@numba.njit(cache=True)
def joint_torque(r, q, v, u, k, beta, c, B):
    """Return joint r's spring, damper and input torque -k (q + beta v) - c v + (B u), N m.

    ``B`` (n, m) the inputs' map; the one place this torque is written (the stations' moved
    chains call it too).
    """
    s = -k[r] * (q[r] + beta * v[r]) - c[r] * v[r]
    for j in range(u.size):
        s += B[r, j] * u[j]
    return s


@numba.njit(cache=True)
def state_jacobian(dq, dv, Minv, dtau0, rc, rs, force, loaded, A):
    """Write df/dx's lower half A = [da/dq, da/dv] + M^-1 d tau/dx (n, 2 n).

    ``dtau0`` (n, 2 n) is d tau/dx without the load stiffness, which is added here when
    ``loaded``: d(J^T F)_j/dq_k = T_max(j,k), T_m = -F_x c_m + F_z s_m.
    """
    n = dq.shape[0]
    fx, fz = force[0], force[2]
    for i in range(n):
        for j in range(2 * n):
            s = dq[i, j] if j < n else dv[i, j - n]
            for r in range(n):
                d = dtau0[r, j]
                if loaded and j < n:
                    m = r if r > j else j
                    d += -fx * rc[m] + fz * rs[m]
                s += Minv[i, r] * d
            A[i, j] = s


@numba.njit(cache=True)
def stage_rates(dq, dv, Minv, dtau0, rc, rs, force, loaded, B, x, x_ref, k, beta, gain,
                starts, S, lx, lu, lz, dzp, A, Fp, dS, dg):
    """Write S' (2 n, P) into dS and the gradient's rate dl/dx S + dl/dp (P,) into dg.

    ``starts`` (4,) are the first columns of the springs, beta, dampers and gain (-1 absent);
    the stations' columns of ``Fp`` (n, P) and ``dzp`` (P,) are filled before the call, the
    start state's columns of ``Fp`` stay zero (it enters through S(0) alone). ``A`` (n, 2 n)
    is scratch (receives df/dx's lower half). Returns False when a partial of the cost is
    NaN or infinite (their sum is then not finite).
    """
    n = x.size // 2
    P = S.shape[1]
    m = lu.size
    state_jacobian(dq, dv, Minv, dtau0, rc, rs, force, loaded, A)
    s_k, s_b, s_c, s_g = starts[0], starts[1], starts[2], starts[3]
    for i in range(n):
        if s_k >= 0:
            for j in range(n):
                Fp[i, s_k + j] = -Minv[i, j] * (x[j] + beta * x[n + j])
        if s_b >= 0:
            s = 0.0
            for r in range(n):
                s -= Minv[i, r] * k[r] * x[n + r]
            Fp[i, s_b] = s
        if s_c >= 0:
            for j in range(n):
                Fp[i, s_c + j] = -Minv[i, j] * x[n + j]
        if s_g >= 0:
            for a in range(m):
                mb = 0.0
                for r in range(n):
                    mb += Minv[i, r] * B[r, a]
                for b in range(2 * n):
                    Fp[i, s_g + a * 2 * n + b] = -mb * (x[b] - x_ref[b])
    # row by row, the inner loops along the contiguous parameter axis
    for i in range(n):
        for p in range(P):
            dS[i, p] = S[n + i, p]
            dS[n + i, p] = Fp[i, p]
        for j in range(2 * n):
            w = A[i, j]
            for p in range(P):
                dS[n + i, p] += w * S[j, p]
    # dl/dx through u = u_ref - G (x - x_ref) and z(q): lx - lu G, plus lz dz/dq on the angles
    for p in range(P):
        dg[p] = lz * dzp[p]
    for j in range(2 * n):
        w = lx[j]
        for a in range(m):
            w -= lu[a] * gain[a, j]
        if j < n:
            w -= lz * rc[j]
        for p in range(P):
            dg[p] += w * S[j, p]
    if s_g >= 0:
        for a in range(m):
            for b in range(2 * n):
                dg[s_g + a * 2 * n + b] += lu[a] * (x_ref[b] - x[b])
    check = lz
    for j in range(2 * n):
        check += lx[j]
    for a in range(m):
        check += lu[a]
    return math.isfinite(check)
