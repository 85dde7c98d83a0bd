"""Gauss-Legendre's Newton pieces (``gauss``).

The analytic iteration matrix, the predictor from the linearised step, and the highest frequency
a failed step's message names. The residual of the two stages is R_i = M(Q_i) A_i + h(Q_i, V_i)
+ K Q_i + C V_i - J^T F_i with Q_i = q + c_i h v + h^2 (A^2)_ij A_j and V_i = v + h A_ij A_j.
Newton starts from the solution of the collocation equations linearised at the step's start.
Before, it started from the previous step's stage accelerations extrapolated: at omega dt >> 1
those put the stages radians off (dt^2 times the stiff modes' accelerations), where the first
residual is meaningless, and Newton diverged or found another root of the collocation equations
(the 5R and 8R releases from 0.1 rad per joint failed after three halvings).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from .system import System, mass_matrix, symmetrised


def stage_jacobians(system: System, tau_and_stiffness, q: np.ndarray, v: np.ndarray,
                    a: np.ndarray, f: np.ndarray | None):
    """Return M, dR/dv and dR/dq of the residual M a + h + K q + C v - J^T f at one state.

    Analytic: ``pin.computeRNEADerivatives`` (dM/dq a included), the springs, the damping and
    the load stiffness ``tau_and_stiffness(q, f)[1]`` (closed form for a planar chain). A
    stiffness schedule's dK/dq q is left out: it only sets the convergence rate. q (rad),
    v (rad/s), a (rad/s^2), f (N, or None without a tip force).
    """
    dq, dv, M = pin.computeRNEADerivatives(system.pin_model, system.data, q, v, a)
    Kt = dq + np.diag(system.springs(q))
    if system.damping_Nms_per_rad is not None:
        dv = dv + system.damping_Nms_per_rad
    if f is not None:
        Kt = Kt - tau_and_stiffness(q, f)[1]
    return symmetrised(M), dv, Kt


def iteration_matrix(system: System, tau_and_stiffness, hA: np.ndarray, hhAA: np.ndarray,
                     E: np.ndarray, states) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Return Newton's inverse iteration matrix, stacked over ``E`` times it, and (M, K).

    The matrix is dR_i/dA_j = delta_ij M_i + h A_ij D_i + h^2 (A^2)_ij K_i; (M, K) are the first
    stage's. ``states`` holds each stage's (q, v, a, f): the step's start for both (the
    simplified Newton matrix), or the stages' own iterates (Newton's exact matrix). ``hA`` and
    ``hhAA`` are the tableau times h and h^2 (s, s^2); ``E`` maps an update of the stage
    accelerations to the updates of (q1, h v1).
    """
    n = system.stiffness_Nm_per_rad.size
    S = np.empty((2 * n, 2 * n))
    first = None
    for i, state in enumerate(states):
        M, D, K = stage_jacobians(system, tau_and_stiffness, *state)
        if first is None:
            first = (M, K)
        rows = slice(i * n, (i + 1) * n)
        for j in range(2):
            S[rows, j * n:(j + 1) * n] = hA[i, j] * D + hhAA[i, j] * K
        S[rows, i * n:(i + 1) * n] += M
    try:
        # one matvec per iteration is the cheapest solve of 2n <= ~20 unknowns from Python
        W = np.linalg.inv(S)
    except np.linalg.LinAlgError:
        raise SolveError("Gauss-Legendre: singular iteration matrix") from None
    return np.vstack((W, E @ W)), first


def linear_predictor(B: np.ndarray, start_jacobians: tuple[np.ndarray, np.ndarray],
                     a: np.ndarray, v: np.ndarray, hc: np.ndarray, force_change) -> np.ndarray:
    """Return the stage accelerations (2n,) of the step of the equations linearised at its start.

    The linearised collocation equations, R_i ~ M (A_i - a) + D (V_i - v) + K (Q_i - q)
    + J^T (f(t0) - f(t0 + c_i h)) = 0, keep every linear mode where the scheme puts it
    (A-stable): S A = M a - c_i h K v + (the force's change ``force_change``, per stage, N m,
    or None), with the start's exact acceleration ``a`` (rad/s^2), the start rate ``v``
    (rad/s) and the stage offsets ``hc`` (s). A linear chain is solved in one iteration.
    ``B``'s first 2n rows are S^-1; ``start_jacobians`` the (M, K) of its build.
    """
    M, K = start_jacobians
    n = v.size
    Ma, Kv = M @ a, K @ v
    rhs = np.concatenate((Ma - hc[0] * Kv, Ma - hc[1] * Kv))
    if force_change is not None:
        rhs[:n] += force_change[0]
        rhs[n:] += force_change[1]
    return B[:2 * n] @ rhs


def omega_max(system: System, q: np.ndarray) -> float:
    """Return the highest natural frequency of the chain linearised at ``q`` (rad), rad/s."""
    M = mass_matrix(system.pin_model, system.data, q)
    w2 = np.linalg.eigvals(np.linalg.solve(M, np.diag(system.springs(q)))).real
    return math.sqrt(max(float(w2.max()), 1e-300))
