"""Newmark's average-acceleration (trapezoidal) integrator, fixed step (``Trapezoidal``).

``Trapezoidal()`` (``method="trapezoidal"``): Newmark's average-acceleration rule
(beta = 1/4, gamma = 1/2), fixed step ``dt_s`` (default: 1/100 of the lowest natural period at
``q0``; shortened to divide ``output_dt``, the last step shortened to end on the duration).
Second order, A-stable, no
numerical damping. The residual M(q1) a1 + h(q1, v1) + K q1 + C v1 - J^T F is evaluated with
Pinocchio's RNEA and solved by Newton with the tangent
M + dt/2 (C + dh/dv) + dt^2/4 (K + d(Ma+h)/dq) from ``pin.computeRNEADerivatives``
(refreshed only when convergence slows). A linear mode of frequency omega
is integrated at omega_h = (2/dt) arctan(omega dt/2), a relative period error of about
(omega dt)^2/12 (3.3e-4 for mode 1 at the default step); undamped linear motion conserves
the energy exactly (to the Newton tolerance). Between the steps the output follows the scheme's
own constant average acceleration (q quadratic, v linear in time); at a step it is the step.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from ..errors import BeamInputError, SolveError
from ..options.integrators import Trapezoidal
from .system import System, mass_matrix, static_angle_rad, weight_angle_rad


class TrapezoidalStepper:
    """Newmark average-acceleration steps (the stepper of ``Trapezoidal``).

    Parameters
    ----------
    settings : Trapezoidal
    system : System
    t0, t_bound : float
        Start and end time, s.
    y0 : ndarray, shape (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    dt_s : float
        Step, s; shortened to divide ``output_dt_s``.
    output_dt_s : float or None
        Sample interval, s, that the steps land on (None: every step is a sample).
    max_steps : int
        Refuse a step that would take more steps (BeamInputError).
    """

    def __init__(self, settings: Trapezoidal, system: System, t0: float, y0: np.ndarray,
                 t_bound: float, *, dt_s: float, output_dt_s: float | None, max_steps: int):
        self.settings, self.system = settings, system
        n = y0.size // 2
        self.n, self.t0_s, self.t_bound = n, t0, t_bound
        duration = t_bound - t0
        if output_dt_s is not None:
            every = max(1, math.ceil(output_dt_s / dt_s - 1e-9))
            h = output_dt_s / every
        else:
            h = dt_s
        self.nsteps = math.ceil(duration / h - 1e-9)
        if self.nsteps > max_steps:
            raise BeamInputError(f"dt = {h} s: {self.nsteps} steps exceed max_steps = "
                                 f"{max_steps}")
        self.h = h
        q0, v0 = y0[:n], y0[n:]
        # initial acceleration from the equations of motion
        self.q, self.v = q0.copy(), v0.copy()
        a = -self._residual(self.q, self.v, np.zeros(n), t0)
        self.a = np.linalg.solve(mass_matrix(system.pin_model, system.data, self.q), a)
        self.a_prev = self.a
        self.lu = self.piv = None
        self.lu_h = h
        self.rhs_evaluations = 1
        # Newton stops when the update moves q1 by less than this (scaled by the motion's size;
        # a nanoradian floor, as Gauss's: a run from rest under a load that starts at zero has
        # no scale, and 1e-10 of a 1e-300 floor is below what any update can resolve)
        scale = max(float(np.max(np.abs(q0))), float(np.max(np.abs(v0))) * h, 1e-9)
        # a force sets the scale of the motion: its static deflection angle
        self.scale = max(scale, static_angle_rad(system.tau_external(q0, t0, v0),
                                                 system.springs(q0)),
                         weight_angle_rad(system, q0))
        self.tol = 1e-10 * self.scale
        self.rho = 1.0
        self.steps = self.jacobian_updates = 0
        self.t = self.t_old = t0
        self.y = y0.copy()
        self.done = False

    def _residual(self, q, v, a, t):
        sy = self.system
        r = pin.rnea(sy.pin_model, sy.data, q, v, a) + sy.springs(q) * q
        if sy.damping_Nms_per_rad is not None:
            r += sy.damping_Nms_per_rad @ v
        te = sy.tau_external(q, t, v)
        return r if te is None else r - te

    def step(self) -> None:
        """Take the next step; the last one ends on ``t_bound``."""
        sy, k = self.system, self.steps + 1
        h, t1 = self.h, self.t0_s + k * self.h
        last = k == self.nsteps
        if last and abs(t1 - self.t_bound) > 1e-9 * h:
            # the equal steps overrun the end: the last one is shortened to end on it
            h, t1 = self.t_bound - self.t, self.t_bound
        h2, hh4 = 0.5 * h, 0.25 * h * h
        q, v, a = self.q, self.v, self.a
        qp = q + h * v + hh4 * a
        vp = v + h2 * a
        # linear extrapolation of the acceleration: one Newton iteration fewer on smooth motion
        a1 = 2.0 * a - self.a_prev
        if self.lu_h != h:
            self.lu = None  # the iteration matrix depends on the step
        converged = False
        for _attempt in range(2):
            if self.lu is None:
                dq, dv, M = pin.computeRNEADerivatives(sy.pin_model, sy.data, q, v, a)
                S = M + hh4 * (dq + np.diag(sy.springs(q)))
                C = sy.damping_Nms_per_rad
                S += h2 * (dv if C is None else dv + C)
                self.lu, self.piv, info = lapack.dgetrf(S)
                self.lu_h = h
                if info != 0:
                    raise SolveError(f"trapezoidal rule: singular iteration matrix at t = {t1} s")
            prev = math.inf
            for it in range(12):
                q1 = qp + hh4 * a1
                v1 = vp + h2 * a1
                r = self._residual(q1, v1, a1, t1)
                self.rhs_evaluations += 1
                da, info = lapack.dgetrs(self.lu, self.piv, r)
                a1 -= da
                size = hh4 * np.abs(da).max()
                if it:
                    self.rho = size / prev
                rho = self.rho
                # Hairer & Wanner's stopping rule: the remaining error of a contraction with rate
                # rho is below rho / (1 - rho) times the last update
                if size <= self.tol or (rho < 1.0 and rho / (1.0 - rho) * size <= self.tol):
                    converged = True
                    break
                prev = size
            if it >= 3:
                self.lu = None  # slow convergence: refresh the tangent next step
            if converged:
                break
            self.lu = None
            a1 = a.copy()
        if not converged or not np.all(np.isfinite(a1)):
            raise SolveError(f"trapezoidal rule: Newton did not converge at t = {t1:.6g} s "
                             f"(dt = {h:.3g} s); try a smaller dt")
        self._start = (self.t, q, v, a, h)
        self.q = q = qp + hh4 * a1
        self.v = v = vp + h2 * a1
        self.scale = max(self.scale, np.abs(q).max())
        self.tol = 1e-10 * self.scale
        self.a_prev, self.a = a, a1
        self.steps = k
        self.done = last
        self.t_old, self.t = self.t, (self.t_bound if last else t1)
        self.y = np.concatenate((q, v))

    def dense_output(self):
        """Return the last step's output: times (m,) s -> states (m, 2n).

        A time within 1e-9 of a step of one of its ends is that end (the samples of an output
        interval the steps divide are the steps themselves); in between, the scheme's constant
        average acceleration (a_0 + a_1) / 2.
        """
        t_start, q0, v0, a0, h = self._start
        t_end, y_end = self.t, self.y
        mean = 0.5 * (a0 + self.a)
        y_start = np.concatenate((q0, v0))

        def sample(t_s):
            out = np.empty((len(t_s), y_end.size))
            for i, t in enumerate(t_s):
                if abs(t - t_end) <= 1e-9 * h:
                    out[i] = y_end
                elif abs(t - t_start) <= 1e-9 * h:
                    out[i] = y_start
                else:
                    s = t - t_start
                    out[i] = np.concatenate((q0 + s * v0 + 0.5 * s * s * mean, v0 + s * mean))
            return out

        return sample
