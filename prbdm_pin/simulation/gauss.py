"""2-stage Gauss-Legendre integrator, fixed step, symplectic (``method="gauss"``).

``"gauss"``: the 2-stage Gauss-Legendre collocation method, fixed step ``dt``
(default: lowest natural period at ``q0`` / 40). Fourth order, symplectic, A-stable, no
numerical damping: a linear mode is integrated at the frequency ratio
:func:`gauss_frequency_ratio` = 1 - (omega dt)^4/720 + ... (period error 3.4e-6 at 40
steps per period, 1.35e-5 at 20); the energy of undamped linear motion is conserved exactly
(a quadratic invariant), for the nonlinear chain it stays bounded (no drift).
The unknowns are the two stage accelerations; each iteration evaluates the residual
M a + h + K q + C v - J^T F by two Pinocchio RNEA calls and applies a stored inverse of the
2n x 2n iteration matrix (simplified Newton; built from ``pin.computeRNEADerivatives``, the
load stiffness by differences, and rebuilt only when the contraction rate exceeds 0.03);
Newton stops when the update of (q1, dt v1) is below 1e-8 of the motion's scale. Output at
``output_dt`` is interpolated (quintic Hermite in q, v, a at the steps; one ABA per step),
and the tip position is computed only at the output samples (closed form for the planar
chain).
Why 40 steps per period, not 20: mode 1 alone needs only ~T1/10 for 0.1 %, but a step load
excites every mode, and the phase error of modes 2-3 sets the error of the tip response:
against DOP853 (rtol 1e-10), 5R chain, 2500 N step, 1 s: 3.2 % of the peak at T1/20,
1.35 % at T1/30, 0.7 % at T1/40 (measured; ``scripts/bench_simulate.py`` tabulates it).
Modes with omega dt >> 1 stay bounded and barely damped by the scheme, at a wrong frequency.
Violent initial conditions that excite them strongly can stall the simplified Newton at the
default step: such a step is redone as two half steps, up to 3 times (then SolveError asks
for a smaller ``dt``).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from .steps import Samples, StepSettings, equal_steps
from .system import System, static_angle_rad, symmetrised
from .trajectory import hermite_output

# 2-stage Gauss-Legendre tableau (c, A, b = (1/2, 1/2)); for q'' = a the stage positions use
# A @ A and the end position b^T A
_R3 = math.sqrt(3.0)
_GL_C = np.array([0.5 - _R3 / 6.0, 0.5 + _R3 / 6.0])
_GL_A = np.array([[0.25, 0.25 - _R3 / 6.0], [0.25 + _R3 / 6.0, 0.25]])
_GL_AA = _GL_A @ _GL_A
_GL_BA = 0.5 * _GL_A.sum(axis=0)
_NEWTON_RTOL = 1e-8
_REFRESH_RATE = 0.03
_PREDICTOR_SLOPE = 0.5
# a step whose Newton iteration fails is redone as two half steps, at most this many times over
MAX_HALVINGS = 3


def gauss_frequency_ratio(omega_dt: float | np.ndarray) -> float | np.ndarray:
    """Return the numerical over exact frequency of an undamped mode under 2-stage Gauss.

    Parameters
    ----------
    omega_dt : float or ndarray
        The mode's frequency times the step, omega (rad/s) dt (s): dimensionless.

    Returns
    -------
    float or ndarray
        The ratio, dimensionless (1 for an exact scheme).

    Notes
    -----
    The stability function R(z) = (1 + z/2 + z^2/12) / (1 - z/2 + z^2/12) has modulus 1 at
    z = i x (x = omega dt) and phase 2 arctan((x/2) / (1 - x^2/12)); the ratio is
    1 - x^4/720 + O(x^6).
    """
    x = np.asarray(omega_dt, dtype=float)
    return 2.0 * np.arctan2(0.5 * x, 1.0 - x * x / 12.0) / x


def integrate(system: System, q0: np.ndarray, v0: np.ndarray, settings: StepSettings
              ) -> Samples:
    """Integrate with fixed Gauss-Legendre steps of at most ``settings.dt_s`` (s).

    From (q0 rad, v0 rad/s) over ``settings.duration_s``; samples every step, or quintic
    Hermite samples every ``output_dt_s``.
    """
    interpolate = settings.output_dt_s is not None
    # a diverging trial step is detected and halved: no overflow warnings for it
    with np.errstate(over="ignore", invalid="ignore"):
        t, Q, V, Acc, steps, nfev, nfact = _steps(
            system, system.tip_force_N, q0, v0, settings.duration_s, settings.dt_s,
            interpolate, settings.max_steps)
    if interpolate:
        t, Q, V = hermite_output(t, Q, V, Acc, settings.duration_s, settings.output_dt_s)
    return Samples(t, Q, V, steps, nfev, nfact)


def _steps(system: System, force: Callable[[float], np.ndarray] | None, q0: np.ndarray,
           v0: np.ndarray, duration: float, dt: float, need_accel: bool, max_steps: int,
           depth: int = 0):
    """Fixed-step 2-stage Gauss-Legendre, simplified Newton on the two stage accelerations.

    ``force`` is the system's tip force shifted to this call's start. A step whose Newton
    iteration fails (with a fresh iteration matrix) is redone as two half steps, recursively up
    to ``MAX_HALVINGS`` times (``depth`` counts them). Returns the node times, q, v, a (None
    unless ``need_accel``), steps, residual evaluations and iteration-matrix builds.
    """
    pm, data, fid = system.pin_model, system.data, system.tip_frame_id
    k_const, stiffness = system.stiffness_Nm_per_rad, system.schedule
    C, constant_force = system.damping_Nms_per_rad, system.constant_force
    n = q0.size
    nsteps = equal_steps(duration, dt, max_steps)
    h = duration / nsteps
    hA, hhAA, hc, hhba = h * _GL_A, h * h * _GL_AA, h * _GL_C, h * h * _GL_BA
    half_h, hh2 = 0.5 * h, 0.5 * h * h
    hc_col = hc[:, None]
    Q = np.empty((nsteps + 1, n))
    V = np.empty((nsteps + 1, n))
    Acc = np.empty((nsteps + 1, n)) if need_accel else None
    Q[0], V[0] = q0, v0
    rnea, jac, lwa = pin.rnea, pin.computeFrameJacobian, pin.LOCAL_WORLD_ALIGNED
    Ct = None if C is None else np.ascontiguousarray(C.T)
    F6 = np.zeros((2, 6))  # stage forces as spatial forces (torque part zero) for J^T f
    springs = system.springs

    def ext_torque(q, f6):
        return jac(pm, data, q, fid, lwa).T @ f6

    f6_end = np.zeros(6)

    def accel(q, v, t):
        tau = -springs(q) * q
        if C is not None:
            tau -= C @ v
        if force is not None:
            f6_end[:3] = force(t)
            tau += ext_torque(q, f6_end)
        return pin.aba(pm, data, q, v, tau)

    def iteration_matrix(q, v, a, t):
        # dR_i/dA_j = delta_ij M + h A_ij (dh/dv + C) + h^2 (A^2)_ij (dh/dq + K - d(J^T F)/dq)
        dq, dv, M = pin.computeRNEADerivatives(pm, data, q, v, a)
        M = symmetrised(M)
        Kt = dq + np.diag(springs(q))
        if C is not None:
            dv = dv + C
        if force is not None:
            # load stiffness by forward differences: it only sets the convergence rate
            f6 = np.zeros(6)
            f6[:3] = force(t)
            base = ext_torque(q, f6)
            eps = 1e-7 * max(1.0, float(np.abs(q).max()))
            for j in range(n):
                qj = q.copy()
                qj[j] += eps
                Kt[:, j] -= (ext_torque(qj, f6) - base) / eps
        S = np.kron(np.eye(2), M) + np.kron(hA, dv) + np.kron(hhAA, Kt)
        try:
            # one matvec per iteration is the cheapest solve of 2n <= ~20 unknowns from Python
            return np.linalg.inv(S)
        except np.linalg.LinAlgError:
            raise SolveError("Gauss-Legendre: singular iteration matrix") from None

    q, v = q0.copy(), v0.copy()
    a = accel(q, v, 0.0)
    if need_accel:
        Acc[0] = a
    # flat stage accelerations X = (A_1, A_2) and the stacked stage states Z = (Q_1, Q_2, V_1, V_2)
    Xf = np.concatenate((a, a))
    X = Xf.reshape(2, n)
    G = np.vstack((hhAA, hA))
    base = np.empty((4, n))
    # linear forces K Q_i + C V_i of the stages as lin0 + L @ Xf (one matvec per iteration)
    L = np.zeros((2 * n, 2 * n))
    if stiffness is None:
        L += np.kron(hhAA, np.diag(k_const))
    if C is not None:
        L += np.kron(hA, C)
    # maps an update of Xf to the updates of q1 and dt * v1, which carry on to the next step
    E = np.vstack((np.kron(hhba[None, :], np.eye(n)), np.kron(np.full((1, 2), hh2), np.eye(n))))
    B = None
    r = np.empty(2 * n)
    nfev, nfact = 1, 0
    # Newton stops when the update moves (q1, dt v1) by less than rtol * this scale
    # (a nanoradian floor: a run from rest under a force that starts at zero has no scale yet)
    scale = max(float(np.abs(q0).max()), float(np.abs(v0).max()) * h, 1e-9)
    if force is not None:
        f6 = np.zeros(6)
        f6[:3] = force(0.0)
        scale = max(scale, static_angle_rad(ext_torque(q0, f6), springs(q0)))
    tol2 = (_NEWTON_RTOL * scale) ** 2
    rho = 1.0  # contraction rate of the last iterations, carried across steps
    constant_force = constant_force and force is not None
    if constant_force:
        F6[:, :3] = force(0.0)
    F6a, F6b = F6[0], F6[1]
    n2 = 2 * n
    halved_steps = 0
    for step in range(1, nsteps + 1):
        t0 = (step - 1) * h
        if force is not None and not constant_force:
            F6a[:3] = force(t0 + hc[0])
            F6b[:3] = force(t0 + hc[1])
        base[:2] = q + hc_col * v
        base[2:] = v
        lin0 = np.zeros(n2)
        if stiffness is None:
            lin0 += (base[:2] * k_const).reshape(-1)
        if Ct is not None:
            lin0 += np.concatenate((v @ Ct, v @ Ct))
        converged = False
        for _attempt in range(2):
            if B is None:
                W = iteration_matrix(q, v, a, t0)
                B = np.vstack((W, E @ W))
                nfact += 1
            prev = math.inf
            for it in range(10):
                Z = base + G @ X
                np.add(lin0, L @ Xf, out=r)
                r[:n] += rnea(pm, data, Z[0], Z[2], X[0])
                r[n:] += rnea(pm, data, Z[1], Z[3], X[1])
                if stiffness is not None:
                    r[:n] += stiffness(Z[0]) * Z[0]
                    r[n:] += stiffness(Z[1]) * Z[1]
                if force is not None:
                    r[:n] -= ext_torque(Z[0], F6a)
                    r[n:] -= ext_torque(Z[1], F6b)
                nfev += 2
                out = B @ r
                Xf -= out[:n2]
                e = out[n2:]
                size2 = float(e @ e)
                if it:
                    rho = math.sqrt(size2 / prev)
                # Hairer & Wanner's stopping rule: a contraction of rate rho leaves at most
                # rho / (1 - rho) times the last update
                if size2 <= tol2 or (rho < 1.0 and (rho / (1.0 - rho)) ** 2 * size2 <= tol2):
                    converged = True
                    break
                prev = size2
            if converged:
                if rho > _REFRESH_RATE:
                    B = None  # slow convergence: rebuild the iteration matrix next step
                break
            B = None
            X[0] = X[1] = a
        if not converged:  # a NaN or inf update never passes the size test
            if depth >= MAX_HALVINGS:
                raise SolveError(f"Gauss-Legendre: Newton did not converge at t = {t0 + h:.6g} "
                                 f"s (dt = {h:.3g} s after {depth} halvings); try a smaller dt")
            # a violent stretch: redo this step as two half steps (recursively)
            sub_force = None if force is None else (lambda t, t0=t0: force(t0 + t))
            _, Qs, Vs, As, sub_steps, sub_fev, sub_fact = _steps(
                system, sub_force, q, v, h, 0.5 * h, need_accel, max_steps, depth + 1)
            q, v = Qs[-1].copy(), Vs[-1].copy()
            Q[step] = q
            V[step] = v
            nfev += sub_fev
            nfact += sub_fact
            halved_steps += sub_steps - 1
            if need_accel:
                a = As[-1].copy()
                Acc[step] = a
            else:
                a = accel(q, v, t0 + h)
                nfev += 1
            X[0] = X[1] = a
            B = None
            continue
        q = q + h * v + hhba @ X
        v = v + half_h * (X[0] + X[1])
        Q[step] = q
        V[step] = v
        # the linear stage-acceleration polynomial, extrapolated: end value and next predictor
        slope = _R3 * (X[1] - X[0])
        if need_accel:
            a = accel(q, v, t0 + h)
            Acc[step] = a
            nfev += 1
        else:
            a = X[1] + (1.0 - _GL_C[1]) * slope
        X += _PREDICTOR_SLOPE * slope
        scale = max(scale, float(np.abs(q).max()))
        tol2 = (_NEWTON_RTOL * scale) ** 2
    t = np.arange(nsteps + 1) * h
    t[-1] = duration
    return t, Q, V, Acc, nsteps + halved_steps, nfev, nfact
