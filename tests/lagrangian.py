"""The planar chain's mass matrix from its closed-form Lagrangian, and omega^2 in mpmath.

An independent reference for Pinocchio's CRBA and the package's eigensolver: numpy for every n,
mpmath at 40 digits through its own Cholesky factor.
"""

import mpmath
import numpy as np

MP_RTOL = 1e-9


def chain_inputs(model):
    """Per-link (mass kg, COM offset from the link's joint m, inertia about y at the COM kg m^2)."""
    s = model.sections
    return s.mass_kg, s.com_m[:, 0] - s.start_m, s.inertia_com_kg_m2[:, 1, 1]


def lagrangian_mass_matrix(lengths, mass, d, Iyy, q, lib=np):
    """M(q) of the planar chain from T = 1/2 sum_i (m_i |v_i|^2 + Iyy_i phi_i'^2).

    Link i >= 1 has world angle phi_i = q_1 + ... + q_i, axis u(phi) = (cos phi, -sin phi) in
    (x, z), and COM p_i = joint_i + d_i u(phi_i), so dp_i/dq_j = sum_(k=j)^(i-1) L_k u'(phi_k)
    + d_i u'(phi_i) for j <= i. ``lib`` is numpy (float) or mpmath (arbitrary precision).
    """
    n = len(q)
    if lib is np:
        num, zeros, sin, cos = float, lambda: np.zeros((n, n)), np.sin, np.cos
    else:
        num, zeros, sin, cos = mpmath.mpf, lambda: mpmath.zeros(n, n), mpmath.sin, mpmath.cos
    phi, acc = [num(0)], num(0)
    for v in q:
        acc += num(v)
        phi.append(acc)
    # u'(phi) = (-sin phi, -cos phi)
    du = [(-sin(p), -cos(p)) for p in phi]
    M = zeros()
    for i in range(1, n + 1):
        m_i, d_i, I_i = num(mass[i]), num(d[i]), num(Iyy[i])
        # build the COM Jacobian columns j = i, i-1, ..., 1 by accumulating the link terms
        cols = [None] * i
        jx, jz = d_i * du[i][0], d_i * du[i][1]
        cols[i - 1] = (jx, jz)
        for j in range(i - 1, 0, -1):
            jx += num(lengths[j]) * du[j][0]
            jz += num(lengths[j]) * du[j][1]
            cols[j - 1] = (jx, jz)
        for a in range(i):
            for b in range(i):
                M[a, b] += m_i * (cols[a][0] * cols[b][0] + cols[a][1] * cols[b][1]) + I_i
    return M


def mpmath_omega2(M, k, dps=40):
    """Ascending omega^2 of K phi = omega^2 M phi via M = C C^T: eig of C^-1 K C^-T, in mpmath."""
    with mpmath.workdps(dps):
        C = mpmath.cholesky(M)
        Ci = mpmath.inverse(C)
        A = Ci * mpmath.diag([mpmath.mpf(float(v)) for v in k]) * Ci.T
        A = (A + A.T) / 2
        E = mpmath.eigsy(A, eigvals_only=True)
        return np.array(sorted(float(E[i]) for i in range(A.rows)))


def reference_omega2(model, q):
    with mpmath.workdps(40):
        M = lagrangian_mass_matrix(model.lengths_m, *chain_inputs(model), q, lib=mpmath)
        return mpmath_omega2(M, model.stiffness_Nm_per_rad)
