"""Newmark's average-acceleration (trapezoidal) integrator, fixed step (``method="trapezoidal"``).

``"trapezoidal"``: Newmark's average-acceleration rule (beta = 1/4, gamma = 1/2), fixed
step ``dt`` (default: 1/100 of the lowest natural period at ``q0``; shortened to divide
``output_dt``). Second order, A-stable, no
numerical damping. The residual M(q1) a1 + h(q1, v1) + K q1 + C v1 - J^T F is evaluated with
Pinocchio's RNEA and solved by Newton with the tangent
M + dt/2 (C + dh/dv) + dt^2/4 (K + d(Ma+h)/dq) from ``pin.computeRNEADerivatives``
(refreshed only when convergence slows). A linear mode of frequency omega
is integrated at omega_h = (2/dt) arctan(omega dt/2), a relative period error of about
(omega dt)^2/12 (3.3e-4 for mode 1 at the default step); undamped linear motion conserves
the energy exactly (to the Newton tolerance).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from ..errors import BeamInputError, SolveError
from .steps import Samples, StepSettings
from .system import System, mass_matrix, static_angle_rad


def integrate(system: System, q0: np.ndarray, v0: np.ndarray, settings: StepSettings
              ) -> Samples:
    """Integrate with Newmark average-acceleration steps of at most ``settings.dt_s`` (s).

    The step is shortened to divide ``output_dt_s``; from (q0 rad, v0 rad/s) over
    ``settings.duration_s``.
    """
    pm, data = system.pin_model, system.data
    stiffness, C, tau_external = system.springs, system.damping_Nms_per_rad, system.tau_external
    duration, dt, output_dt = settings.duration_s, settings.dt_s, settings.output_dt_s
    max_steps = settings.max_steps
    n = q0.size
    if output_dt is not None:
        every = max(1, math.ceil(output_dt / dt - 1e-9))
        h = output_dt / every
    else:
        every = 1
        h = dt
    nsteps = math.ceil(duration / h - 1e-9)
    if nsteps > max_steps:
        raise BeamInputError(f"dt = {h} s: {nsteps} steps exceed max_steps = {max_steps}")
    nout = nsteps // every + 1
    t_out = np.arange(nout) * (h * every)
    Q = np.empty((nout, n))
    V = np.empty((nout, n))
    Q[0], V[0] = q0, v0
    h2, hh4 = 0.5 * h, 0.25 * h * h
    zero = np.zeros(n)

    def residual(q, v, a, t):
        r = pin.rnea(pm, data, q, v, a) + stiffness(q) * q
        if C is not None:
            r += C @ v
        te = tau_external(q, t, v)
        return r if te is None else r - te

    # initial acceleration from the equations of motion
    q, v = q0.copy(), v0.copy()
    a = -residual(q, v, zero, 0.0)
    a = np.linalg.solve(mass_matrix(pm, data, q), a)
    a_prev = a
    lu = piv = None
    nfev = 1
    # Newton stops when the update moves q1 by less than this (scaled by the motion's size)
    scale = max(float(np.max(np.abs(q0))), float(np.max(np.abs(v0))) * h, 1e-300)
    # a force sets the scale of the motion: its static deflection angle
    scale = max(scale, static_angle_rad(tau_external(q0, 0.0, v0), stiffness(q0)))
    tol = 1e-10 * scale
    rho = 1.0
    for step in range(1, nsteps + 1):
        t1 = step * h
        qp = q + h * v + hh4 * a
        vp = v + h2 * a
        # linear extrapolation of the acceleration: one Newton iteration fewer on smooth motion
        a1 = 2.0 * a - a_prev
        converged = False
        for _attempt in range(2):
            if lu is None:
                dq, dv, M = pin.computeRNEADerivatives(pm, data, q, v, a)
                S = M + hh4 * (dq + np.diag(stiffness(q)))
                S += h2 * (dv if C is None else dv + C)
                lu, piv, info = lapack.dgetrf(S)
                if info != 0:
                    raise SolveError(f"trapezoidal rule: singular iteration matrix at t = {t1} s")
            prev = math.inf
            for it in range(12):
                q1 = qp + hh4 * a1
                v1 = vp + h2 * a1
                r = residual(q1, v1, a1, t1)
                nfev += 1
                da, info = lapack.dgetrs(lu, piv, r)
                a1 -= da
                size = hh4 * np.abs(da).max()
                if it:
                    rho = size / prev
                # Hairer & Wanner's stopping rule: the remaining error of a contraction with rate
                # rho is below rho / (1 - rho) times the last update
                if size <= tol or (rho < 1.0 and rho / (1.0 - rho) * size <= tol):
                    converged = True
                    break
                prev = size
            if it >= 3:
                lu = None  # slow convergence: refresh the tangent next step
            if converged:
                break
            lu = None
            a1 = a.copy()
        if not converged or not np.all(np.isfinite(a1)):
            raise SolveError(f"trapezoidal rule: Newton did not converge at t = {t1:.6g} s "
                             f"(dt = {h:.3g} s); try a smaller dt")
        q = qp + hh4 * a1
        v = vp + h2 * a1
        scale = max(scale, np.abs(q).max())
        tol = 1e-10 * scale
        a_prev, a = a, a1
        if step % every == 0:
            Q[step // every] = q
            V[step // every] = v
    return Samples(t_out, Q, V, nsteps, nfev)
