"""LQG output feedback on a linear plant and its closed loop with any other plant.

``lqg_compensator`` designs, on a design plant (A, B, C), the state feedback u = -K x_hat (LQR)
and the Kalman filter x_hat' = A x_hat + B u + L (y - C x_hat), and returns them as one dynamic
compensator from the measured outputs y to the inputs u:

    x_k' = A_k x_k + B_k y,  u = C_k x_k + D_k y,
    A_k = A - B K - L C,  B_k = L,  C_k = -K,  D_k = 0.

Nothing in it refers to the design plant's states any more, so it runs on any plant with the
same inputs and outputs (a PRBDM of another order, the finite-element truth in its own
coordinates): ``closed_loop`` connects them, ``initial_response`` propagates the closed loop
exactly (matrix exponential) and ``quadratic_cost`` integrates a quadratic cost of it in closed
form (a Lyapunov equation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..errors import BeamInputError

__all__ = ["Compensator", "lqg_compensator", "closed_loop", "initial_response",
           "quadratic_cost"]


@dataclass(frozen=True, eq=False)
class Compensator:
    """A dynamic output-feedback compensator x_k' = A x_k + B y, u = C x_k + D y.

    Attributes
    ----------
    A, B, C, D : ndarray
        Shapes (k, k), (k, p), (m, k), (m, p); y and u in the design plant's units.
    state_gain : ndarray (m, k)
        The LQR gain K (u = -K x_hat).
    estimator_gain : ndarray (k, p)
        The Kalman gain L.
    regulator_poles, estimator_poles : ndarray (k,)
        eig(A - B K) and eig(A - L C) of the design plant, complex, rad/s.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_gain: np.ndarray
    estimator_gain: np.ndarray
    regulator_poles: np.ndarray
    estimator_poles: np.ndarray


def _sym(a: np.ndarray) -> np.ndarray:
    return 0.5 * (a + a.T)


def lqg_compensator(A: np.ndarray, B: np.ndarray, C: np.ndarray, Q: np.ndarray,
                    R: np.ndarray, input_noise: np.ndarray, sensor_noise: np.ndarray
                    ) -> Compensator:
    """LQR on (A, B, Q, R) and a Kalman filter on (A, C) with noise entering as the inputs do.

    Parameters
    ----------
    A, B, C : ndarray
        Design plant, (n, n), (n, m), (p, n).
    Q, R : ndarray
        LQR weights on the state (n, n, positive semidefinite) and the inputs (m, m, positive
        definite): J = int x^T Q x + u^T R u dt.
    input_noise : ndarray (m, m)
        Intensity of white noise added to the inputs (process noise B w).
    sensor_noise : ndarray (p, p)
        Intensity of the measurement noise (positive definite).

    Returns
    -------
    Compensator
    """
    import control

    n, m = B.shape
    p = C.shape[0]
    shapes = {"Q": (Q, (n, n)), "R": (R, (m, m)), "input_noise": (input_noise, (m, m)),
              "sensor_noise": (sensor_noise, (p, p))}
    for name, (a, shape) in shapes.items():
        if np.shape(a) != shape or not np.all(np.isfinite(a)):
            raise BeamInputError(f"{name}: must be a finite {shape[0]} x {shape[1]} matrix "
                                 f"for {n} states, {m} inputs and {p} outputs")
    K, _, reg = control.lqr(A, B, _sym(Q), _sym(R))
    # python-control checks G QN G^T for exact symmetry, which rounding breaks: pass it whole
    W = _sym(B @ input_noise @ B.T)
    L, _, est = control.lqe(A, np.eye(n), C, W, _sym(sensor_noise))
    K, L = np.asarray(K), np.asarray(L)
    return Compensator(A=A - B @ K - L @ C, B=L, C=-K, D=np.zeros((m, p)), state_gain=K,
                       estimator_gain=L, regulator_poles=np.asarray(reg),
                       estimator_poles=np.asarray(est))


def closed_loop(A: np.ndarray, B: np.ndarray, C: np.ndarray, comp: Compensator) -> np.ndarray:
    """State matrix of plant (A, B, C) under ``comp`` (u = C_k x_k + D_k y), state [x; x_k]."""
    if B.shape[1] != comp.C.shape[0] or C.shape[0] != comp.B.shape[1]:
        raise BeamInputError(f"plant with {B.shape[1]} inputs and {C.shape[0]} outputs: the "
                             f"compensator has {comp.C.shape[0]} and {comp.B.shape[1]}")
    return np.block([[A + B @ comp.D @ C, B @ comp.C], [comp.B @ C, comp.A]])


def initial_response(A_cl: np.ndarray, x0: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """Return the states (len(t), n) of x' = A_cl x from x(0) = ``x0`` on a uniform grid.

    ``t_s`` (s) starts at 0; exact up to rounding: x_(k+1) = expm(A_cl dt) x_k.
    """
    t = np.asarray(t_s, dtype=float)
    dt = np.diff(t)
    if t.size < 2 or t[0] != 0.0 or not np.allclose(dt, dt[0], rtol=1e-9, atol=0.0) \
            or not dt[0] > 0.0:
        raise BeamInputError("t_s: must be a uniform increasing grid starting at 0 s")
    step = sla.expm(A_cl * dt[0])
    X = np.empty((t.size, x0.size))
    X[0] = x0
    for k in range(1, t.size):
        X[k] = step @ X[k - 1]
    return X


def quadratic_cost(A_cl: np.ndarray, Q_cl: np.ndarray, x0: np.ndarray) -> float:
    """Return the closed-loop cost int_0^inf x^T Q_cl x dt along x' = A_cl x from ``x0``.

    It is x0^T P x0 with A_cl^T P + P A_cl + Q_cl = 0; ``inf`` when the closed loop is not
    asymptotically stable.
    """
    if np.max(np.linalg.eigvals(A_cl).real) >= 0.0:
        return float("inf")
    P = sla.solve_continuous_lyapunov(A_cl.T, -_sym(Q_cl))
    return float(x0 @ P @ x0)
