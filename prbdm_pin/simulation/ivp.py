"""The ``scipy.integrate`` solvers as steppers (``ScipyIVP``; ``method="DOP853"``, ...).

Any of ``scipy.integrate``'s ``RK45``, ``RK23``, ``DOP853``, ``Radau``, ``BDF``, ``LSODA`` with
``rtol``/``atol``, stepped one accepted step at a time through its ``step()`` and sampled through
its ``dense_output()``, as ``scipy.integrate.solve_ivp`` steps it (the same solver, arguments and
sampling, so the same trajectory). The accelerations come from Pinocchio's ABA and the implicit
methods get the analytic Jacobian from ``pin.computeABADerivatives`` (the derivative of the tip
force's generalised torque with q is left out; it only slows Newton down).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from ..options.integrators import ScipyIVP
from .system import System, symmetrised

_IMPLICIT = ("Radau", "BDF", "LSODA")


def default_atol(settings, y0: np.ndarray) -> float:
    """Return ``settings.atol``, or when None ``rtol`` times the largest initial joint angle.

    At least 1e-6 rad (``y0`` is (q, v); a start from rest takes the floor).
    """
    if settings.atol is not None:
        return settings.atol
    n = y0.size // 2
    return settings.rtol * max(float(np.max(np.abs(y0[:n]))), 1e-6)


class ScipyStepper:
    """A ``scipy.integrate.OdeSolver`` on the system (the stepper of ``ScipyIVP``).

    Parameters
    ----------
    settings : ScipyIVP
    system : System
    t0, t_bound : float
        Start and end time, s.
    y0 : ndarray, shape (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    """

    def __init__(self, settings: ScipyIVP, system: System, t0: float, y0: np.ndarray,
                 t_bound: float):
        # scipy.integrate is imported only by the runs that use it
        import scipy.integrate

        self.settings, self.t_bound = settings, t_bound
        pm, data = system.pin_model, system.data
        stiffness, C = system.springs, system.damping_Nms_per_rad
        tau_external = system.tau_external
        n = y0.size // 2
        atol = default_atol(settings, y0)

        def torque(t, q, v):
            tau = -stiffness(q) * q
            if C is not None:
                tau -= C @ v
            te = tau_external(q, t, v)
            return tau if te is None else tau + te

        def rhs(t, y):
            q, v = y[:n], y[n:]
            return np.concatenate((v, pin.aba(pm, data, q, v, torque(t, q, v))))

        kw = {}
        if settings.method in _IMPLICIT:
            top = np.hstack((np.zeros((n, n)), np.eye(n)))

            def jac(t, y):
                q, v = y[:n], y[n:]
                dq, dv, Minv = pin.computeABADerivatives(pm, data, q, v, torque(t, q, v))
                Minv = symmetrised(Minv)
                bottom_q = dq - Minv * stiffness(q)
                bottom_v = dv if C is None else dv - Minv @ C
                return np.vstack((top, np.hstack((bottom_q, bottom_v))))

            kw["jac"] = jac
        # built as solve_ivp builds it: the same solver takes the same steps
        solver_class = getattr(scipy.integrate, settings.method)
        self.solver = solver_class(rhs, float(t0), y0, float(t_bound), vectorized=False,
                                   rtol=settings.rtol, atol=atol, **kw)
        self.t = self.t_old = t0
        self.y = y0
        self.done = False
        self.steps = 0
        self.jacobian_updates = 0  # as the solve_ivp path always reported

    @property
    def rhs_evaluations(self) -> int:
        """Right-hand side (ABA) evaluations, the solver's ``nfev``."""
        return self.solver.nfev

    def step(self) -> None:
        """Take the solver's next accepted step; SolveError when it fails."""
        solver = self.solver
        message = solver.step()
        if solver.status == "failed":
            raise SolveError(f"solve_ivp({self.settings.method}) failed: {message}")
        self.steps += 1
        self.t_old, self.t, self.y = solver.t_old, solver.t, solver.y
        self.done = solver.status == "finished"

    def dense_output(self):
        """Return the solver's interpolant of the last step: times (m,) s -> states (m, 2n)."""
        sol = self.solver.dense_output()
        return lambda t_s: sol(t_s).T
