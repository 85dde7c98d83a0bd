"""The common plant's matrices assembled in one compiled call (numba).

:func:`prbdm_pin.linearize` of a plain planar chain (no hub, bus, gravity, spin or actuators;
modal damping; tip-force and joint-torque inputs, tip, angle, rate and spring-torque outputs)
spent about twenty numpy-sized steps of 2-20 us each after Pinocchio's CRBA and frame Jacobian.
Here, from those quantities (M, J, the tip position, the springs; the dead load's stiffness T
from the lengths, :mod:`prbdm_pin.chain.planar_statics_kernel`), one call forms what the
general path forms step by step, with the same formulas:

- K_e = diag(k) - T, symmetrised (:func:`prbdm_pin.plant.equilibrium.static_terms`);
- C_d = M Phi diag(2 xi omega) Phi^T M, symmetrised, from the scaled problem S M S (S = K^-1/2)
  as :func:`prbdm_pin.simulation.damping.spring_modal_damping` solves it (LAPACK's ``dsyevd``
  through numba), under :func:`prbdm_pin.chain.eigen.check_spectrum`'s fast guard;
- X = M^-1 [K_e, C_d, B_q] by a Cholesky solve (:mod:`prbdm_pin.chain.small_cholesky`) and
  A, B as :func:`prbdm_pin.plant.linearize.first_order`;
- B_q, C_q, C_v and y_eq from the layout's selections of the tip Jacobian's rows and its
  fixed columns (:mod:`.plant_layout`); C = [C_q, C_v] and D = 0 (no output reads the
  acceleration here).

It answers False whenever the guard would not pass at once (a spectrum not positive, not
finite or too ill-conditioned; M not positive definite): the caller then takes the general
path, which raises what it raises. Imported on first use only (the package's import and the
CLI do not load numba).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..chain.planar_statics_kernel import load_stiffness_into
from ..chain.small_cholesky import cholesky_solve, cholesky_substitute

__all__ = ["assemble_plant", "assemble_plant_entry"]

_IN1 = numba.types.Array(numba.float64, 1, "A", readonly=True)
_IN2 = numba.types.Array(numba.float64, 2, "A", readonly=True)
_OUT1 = numba.types.Array(numba.float64, 1, "C")
_OUT2 = numba.types.Array(numba.float64, 2, "C")
_SIGNATURE = numba.types.boolean(
    _IN2, _IN1, _IN1, _IN1, _IN2, _IN1, _IN1, _IN1,  # M, k, xi, lengths, J, p, q, F
    _IN2, _IN2, _IN2, _IN2, _IN2, _IN2, _IN2,  # b_sel, b_fixed, cq_sel, cq_fixed, cv_sel, ...
    numba.float64, numba.float64,  # cond_limit, safe_inverse
    _OUT2, _OUT2, _OUT2, _OUT2, _OUT2, _OUT2, _OUT1, _OUT1,  # A, B, C, K, Cd, Bq, y, u
)


@numba.njit(_SIGNATURE, cache=True)
def assemble_plant(M, k, xi, lengths, J, p, q, F, b_sel, b_fixed, cq_sel, cq_fixed, cv_sel,
                   cv_fixed, u_sel, cond_limit, safe_inverse, A, B, C, K, Cd, Bq, y, u
                   ):  # pragma: no cover - compiled
    """Fill the plant's matrices from M, the springs, the load stiffness and the tip kinematics.

    Parameters
    ----------
    M : ndarray (n, n)
        Mass matrix at the pose, kg m^2 (symmetric).
    k, xi : ndarray (n,)
        Joint springs (N m/rad, > 0) and the modes' damping ratios (ascending frequency).
    lengths : ndarray (n+1,)
        Link lengths, m: the lever arms of the load stiffness T = d(J^T F)/dq.
    J, p : ndarray (3, n), (3,)
        The tip's world-aligned linear Jacobian (m/rad) and position (m).
    q, F : ndarray (n,), (3,)
        The pose (rad) and the dead tip force (N, world).
    b_sel, b_fixed : ndarray (m, 3), (n, m)
        B_q = J^T b_sel^T + b_fixed.
    cq_sel, cq_fixed, cv_sel, cv_fixed : ndarray (p, 3), (p, n), (p, 3), (p, n)
        C_q = cq_sel J + cq_fixed, C_v = cv_sel J + cv_fixed, y_eq = cq_sel p + cq_fixed q.
    u_sel : ndarray (m, 3)
        u_eq = u_sel F (the load's components on the tip-force inputs).
    cond_limit, safe_inverse : float
        :data:`prbdm_pin.chain.eigen.COND_LIMIT` and the smallest eigenvalue whose inverse
        cannot overflow.
    A, B, C, K, Cd, Bq, y, u : ndarray
        Outputs, shapes (2n, 2n), (2n, m), (p, 2n), (n, n) twice, (n, m), (p,), (m,); C is
        [C_q, C_v].

    Returns
    -------
    bool
        False (outputs undefined) when the spectrum's guard does not pass at once or M is not
        positive definite.
    """
    n = k.size
    m = b_sel.shape[0]
    s = np.empty(n)
    for i in range(n):
        s[i] = 1.0 / math.sqrt(k[i])
    a = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            a[i, j] = M[i, j] * s[i] * s[j]
            if not math.isfinite(a[i, j]):
                return False  # numba's eigh would raise; the general path says what is wrong
    mu, V = np.linalg.eigh(a)
    if not (mu[0] > 0.0 and mu[n - 1] / mu[0] <= cond_limit and mu[0] >= safe_inverse):
        return False  # NaN fails too
    for i in range(n):
        if not math.isfinite(mu[i]):
            return False
    # mass-normalised modes in ascending frequency: phi = S v / sqrt(mu), omega = mu^-1/2
    Phi = np.empty((n, n))
    d = np.empty(n)
    for c in range(n):
        src = n - 1 - c
        r = math.sqrt(mu[src])
        d[c] = 2.0 * xi[c] * math.sqrt(1.0 / mu[src])
        for i in range(n):
            Phi[i, c] = s[i] * V[i, src] / r
    T = np.zeros((n, n))
    if F[0] != 0.0 or F[2] != 0.0:  # the planar chain feels the load's x and z
        load_stiffness_into(lengths, q, F[0], F[2], np.empty(n), np.empty(n), np.empty(n),
                            np.empty(n), T)
    # loops, not BLAS: for a short chain a dgemm call costs more than its arithmetic
    MP = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            for c in range(n):
                MP[i, c] += M[i, j] * Phi[j, c]
    Cfull = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            for c in range(n):
                Cfull[i, j] += MP[i, c] * d[c] * MP[j, c]
    for i in range(n):
        for j in range(n):
            Cd[i, j] = 0.5 * (Cfull[i, j] + Cfull[j, i])
            K[i, j] = -0.5 * (T[i, j] + T[j, i])
        K[i, i] += k[i]
    for i in range(n):
        for c in range(m):
            v = b_fixed[i, c]
            for r in range(3):
                v += J[r, i] * b_sel[c, r]
            Bq[i, c] = v
    # X = M^-1 [K_e, C_d, B_q], column by column through one factor's solves
    L = np.empty((n, n))
    rhs = np.empty(n)
    x = np.empty(n)
    A[:, :] = 0.0
    B[:, :] = 0.0
    for i in range(n):
        A[i, n + i] = 1.0
    for c in range(2 * n + m):
        for i in range(n):
            rhs[i] = K[i, c] if c < n else (Cd[i, c - n] if c < 2 * n else Bq[i, c - 2 * n])
        if c == 0:
            if not cholesky_solve(M, L, rhs, x):  # the factor, once
                return False
        else:
            cholesky_substitute(L, rhs, x)
        for i in range(n):
            if c < 2 * n:
                A[n + i, c] = -x[i]
            else:
                B[n + i, c - 2 * n] = x[i]
    for r in range(cq_sel.shape[0]):
        yr = 0.0
        for t in range(3):
            yr += cq_sel[r, t] * p[t]
        for i in range(n):
            vq = cq_fixed[r, i]
            vv = cv_fixed[r, i]
            for t in range(3):
                vq += cq_sel[r, t] * J[t, i]
                vv += cv_sel[r, t] * J[t, i]
            C[r, i] = vq
            C[r, n + i] = vv
            yr += cq_fixed[r, i] * q[i]
        y[r] = yr
    for c in range(m):
        u[c] = u_sel[c, 0] * F[0] + u_sel[c, 1] * F[1] + u_sel[c, 2] * F[2]
    return True


def assemble_plant_entry():
    """:func:`assemble_plant`'s compiled entry point for its one signature, or the function.

    As :func:`prbdm_pin.chain.small_eigen.scaled_omega_entry`: the entry point skips the
    dispatcher's type resolution (it unboxes without checking types, so the caller passes
    float64 arrays of the right dimensions, the outputs C-contiguous).
    """
    try:
        return assemble_plant.overloads[assemble_plant.signatures[0]].entry_point
    except (AttributeError, IndexError, KeyError):  # another numba: its dispatcher checks
        return assemble_plant
