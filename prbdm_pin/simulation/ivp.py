"""The ``scipy.integrate.solve_ivp`` path (``method="DOP853"``, ``"Radau"``, ...).

Any ``scipy.integrate.solve_ivp`` method (``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"BDF"``,
``"LSODA"``) with ``rtol``/``atol``; the accelerations come from Pinocchio's ABA and the implicit
methods get the analytic Jacobian from ``pin.computeABADerivatives`` (the derivative of the
tip force's generalised torque with q is left out; it only slows Newton down).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from .steps import Samples, StepSettings, output_times
from .system import System, symmetrised

_IMPLICIT = ("Radau", "BDF", "LSODA")


def integrate(system: System, q0: np.ndarray, v0: np.ndarray, settings: StepSettings
              ) -> Samples:
    """Integrate with ``solve_ivp``, method ``settings.method`` and its tolerances.

    From (q0 rad, v0 rad/s) over ``settings.duration_s``; samples at its own steps, or dense
    output every ``output_dt_s``.
    """
    # scipy.integrate is imported only by the runs that use it
    from scipy.integrate import solve_ivp

    pm, data = system.pin_model, system.data
    stiffness, C, tau_external = system.springs, system.damping_Nms_per_rad, system.tau_external
    duration, method, output_dt = settings.duration_s, settings.method, settings.output_dt_s
    rtol, atol = settings.rtol, settings.atol
    n = q0.size
    if atol is None:
        atol = rtol * max(float(np.max(np.abs(q0))), 1e-6)

    def torque(t, q, v):
        tau = -stiffness(q) * q
        if C is not None:
            tau -= C @ v
        te = tau_external(q, t, v)
        return tau if te is None else tau + te

    def rhs(t, y):
        q, v = y[:n], y[n:]
        return np.concatenate((v, pin.aba(pm, data, q, v, torque(t, q, v))))

    jac = None
    if method in _IMPLICIT:
        top = np.hstack((np.zeros((n, n)), np.eye(n)))

        def jac(t, y):
            q, v = y[:n], y[n:]
            dq, dv, Minv = pin.computeABADerivatives(pm, data, q, v, torque(t, q, v))
            Minv = symmetrised(Minv)
            bottom_q = dq - Minv * stiffness(q)
            bottom_v = dv if C is None else dv - Minv @ C
            return np.vstack((top, np.hstack((bottom_q, bottom_v))))

    kw = {"jac": jac} if jac is not None else {}
    sol = solve_ivp(rhs, (0.0, duration), np.concatenate((q0, v0)), method=method, rtol=rtol,
                    atol=atol, dense_output=output_dt is not None, **kw)
    if not sol.success:
        raise SolveError(f"solve_ivp({method}) failed: {sol.message}")
    steps = len(sol.t) - 1
    if output_dt is None:
        t, Y = sol.t.copy(), sol.y.T
    else:
        t = output_times(duration, output_dt)
        Y = sol.sol(t).T
    return Samples(t, Y[:, :n].copy(), Y[:, n:].copy(), steps, sol.nfev)
