"""A trajectory cost by scipy's DOP853 on an independent right-hand side, for checking
``trajectory_gradient``'s runs.

Imported as ``from trajectory_reference import ...`` (pytest puts this folder on ``sys.path``);
not a test module. The dynamics are Pinocchio's ABA with the tip force through Pinocchio's own
frame Jacobian and the tip height from its frame placement (the package's run uses the planar
closed form); the cost J = integral of w_z z^2 + u^T R u, plus w_zT z(T)^2, is integrated as
one more state.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp
from tolerances import REFERENCE_ATOL, REFERENCE_RTOL

__all__ = ["dop853_cost"]


def dop853_cost(model, T: float, q0, *, B=None, G=None, beta: float = 0.0, c=None,
                force=(0.0, 0.0, 0.0), w_z: float = 0.0, r: float = 0.0,
                w_zT: float = 0.0, cost_scale: float = 1.0) -> float:
    """Return J of the closed loop u = -G x through the inputs' map B (n, m).

    ``cost_scale`` is J's magnitude: the integrator's absolute tolerance on the cost state is
    REFERENCE_ATOL times it.
    """
    pm = model.pin_model
    data = pm.createData()
    n = pm.nv
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    c = np.zeros(n) if c is None else np.asarray(c, dtype=float)
    B = np.zeros((n, 0)) if B is None else np.asarray(B, dtype=float)
    G = np.zeros((B.shape[1], 2 * n)) if G is None else np.asarray(G, dtype=float)
    F = np.asarray(force, dtype=float)
    fid = model.tip_frame_id

    def tip(q):
        pin.framesForwardKinematics(pm, data, q)
        return data.oMf[fid].translation[2]

    def rhs(t, y):
        q, v = y[:n], y[n:2 * n]
        u = -G @ y[:2 * n]
        z = tip(q)
        J = pin.computeFrameJacobian(pm, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
        tau = -k * q - (beta * k + c) * v + J.T @ F + B @ u
        a = pin.aba(pm, data, q, v, tau)
        return np.concatenate((v, a, [w_z * z * z + r * u @ u]))

    y0 = np.concatenate((np.asarray(q0, dtype=float), np.zeros(n), [0.0]))
    atol = np.full(y0.size, REFERENCE_ATOL)
    atol[-1] = REFERENCE_ATOL * cost_scale
    sol = solve_ivp(rhs, (0.0, T), y0, method="DOP853", rtol=REFERENCE_RTOL, atol=atol)
    assert sol.success, sol.message
    zT = tip(sol.y[:n, -1])
    return float(sol.y[-1, -1] + w_zT * zT * zT)
