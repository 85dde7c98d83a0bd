"""Time response of a PRBDM through Pinocchio: joint springs, damping and a tip force.

Equations of motion (relative joint angles q, rad):

    M(q) a + h(q, v) + K q + C v = J(q)^T F(t)

with h the Coriolis/centrifugal terms (no gravity), K the diagonal joint stiffness, C a damping
matrix (``prbdm_pin.damping``) and J the world-aligned linear Jacobian of the tip point.

Integrators (``method``)
------------------------
- ``"trapezoidal"`` (default): Newmark's average-acceleration rule (beta = 1/4, gamma = 1/2), fixed
  step ``dt`` (default: 1/100 of the lowest natural period at ``q0``). Second order, A-stable, no
  numerical damping. The residual M(q1) a1 + h(q1, v1) + K q1 + C v1 - J^T F is evaluated with
  Pinocchio's RNEA and solved by Newton with the tangent
  M + dt/2 (C + dh/dv) + dt^2/4 (K + d(Ma+h)/dq) from ``pin.computeRNEADerivatives``
  (the tangent is refreshed only when convergence slows; it
  affects the iteration count, not the converged answer). Accuracy: a linear mode of frequency omega
  is integrated at omega_h = (2/dt) arctan(omega dt/2), a relative period error of about
  (omega dt)^2/12 (3.3e-4 for mode 1 at the default step); undamped linear motion conserves
  the energy exactly (to the Newton tolerance), so the energy error does not drift; for the
  geometrically nonlinear chain it stays bounded, O((omega_1 dt)^2 A^2) relative at amplitude A.
  Modes with omega dt >> 1 are not resolved: they stay bounded and barely damped by the scheme,
  at a wrong frequency; their share of the tip response is small (static share ~ 1/omega^2)
  but choose ``dt`` below 1/omega_max if they matter.
- Any ``scipy.integrate.solve_ivp`` method (``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"BDF"``,
  ``"LSODA"``) with ``rtol``/``atol``; the accelerations come from Pinocchio's ABA and the implicit
  methods get the analytic Jacobian from ``pin.computeABADerivatives`` (the derivative of the
  tip force's generalised torque with q is left out; it only slows Newton down).

Damping: ``damping="modal"`` (default) or ``"eq5c"`` (the paper's Eq. 5c). C depends on the pose
through M(q); it is computed once, at ``damping_pose`` (default: ``q0``), and frozen for the run: it
then gives the modes of the system linearised at that pose exactly their ratios, costs nothing per
step and keeps the damping force linear in v. Pass the static equilibrium as ``damping_pose``
to damp the oscillation about a deflected pose with exactly the requested ratios.

Only what the scene needs is computed: no tip Jacobian without a tip force, no damping matrix
when every ratio is zero.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import scipy.linalg as sla
from scipy.linalg import lapack

from .damping import damping_matrix, damping_ratios
from .errors import BeamInputError, SolveError

__all__ = ["Trajectory", "StiffnessSchedule", "simulate", "mechanical_energy", "IVP_METHODS"]

IVP_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A simulated time response.

    Attributes
    ----------
    t_s : ndarray, shape (s,)
        Sample times, s.
    q_rad : ndarray, shape (s, n)
        Joint angles, rad.
    v_rad_s : ndarray, shape (s, n)
        Joint velocities, rad/s.
    tip_position_m : ndarray, shape (s, 3)
        Tip point in world coordinates, m.
    steps : int
        Integrator steps taken (accepted steps for solve_ivp).
    method : str
        Integrator used.
    wall_time_s : float
        Wall time of the integration, s.
    rhs_evaluations : int
        Dynamics evaluations (ABA for solve_ivp, RNEA residuals for the trapezoidal rule).
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    v_rad_s: np.ndarray
    tip_position_m: np.ndarray
    steps: int
    method: str
    wall_time_s: float
    rhs_evaluations: int = 0

    @property
    def tip_displacement_m(self) -> np.ndarray:
        """Tip position minus its position at the first sample, m, shape (s, 3)."""
        return self.tip_position_m - self.tip_position_m[0]


@dataclass(frozen=True, eq=False)
class StiffnessSchedule:
    """Pose-dependent joint stiffness of the paper's parametrisation (Eq. 14, one SCF per pose).

    The pose sweep (Eqs. 10-11) puts every joint at the same angle theta_i; a general pose q is
    mapped to the mean absolute joint angle, and each joint's stiffness is interpolated linearly
    in it (held constant beyond the first and last pose). The spring torque is -K(q) q.

    Attributes
    ----------
    pose_angle_rad : ndarray, shape (m,)
        Joint angle theta_i of each sweep pose, strictly increasing, rad.
    stiffness_Nm_per_rad : ndarray, shape (m, n)
        Joint stiffness at each pose, N m/rad.
    """

    pose_angle_rad: np.ndarray
    stiffness_Nm_per_rad: np.ndarray

    def __post_init__(self) -> None:
        th = np.asarray(self.pose_angle_rad, dtype=float).reshape(-1)
        k = np.asarray(self.stiffness_Nm_per_rad, dtype=float)
        if k.ndim != 2 or k.shape[0] != th.size or th.size < 1:
            raise BeamInputError(
                f"stiffness_schedule: stiffness shape {k.shape} must be (poses={th.size}, n)"
            )
        if not (np.all(np.isfinite(th)) and np.all(np.diff(th) > 0.0)):
            raise BeamInputError("stiffness_schedule.pose_angle_rad: must be finite and increasing")
        if not (np.all(np.isfinite(k)) and np.all(k > 0.0)):
            raise BeamInputError("stiffness_schedule.stiffness_Nm_per_rad: must be finite and > 0")
        object.__setattr__(self, "pose_angle_rad", th)
        object.__setattr__(self, "stiffness_Nm_per_rad", k)

    def at(self, q: np.ndarray) -> np.ndarray:
        """Joint stiffness (n,) at pose ``q``, N m/rad."""
        s = float(np.mean(np.abs(q)))
        th = self.pose_angle_rad
        if th.size == 1 or s <= th[0]:
            return self.stiffness_Nm_per_rad[0]
        if s >= th[-1]:
            return self.stiffness_Nm_per_rad[-1]
        i = int(np.searchsorted(th, s)) - 1
        w = (s - th[i]) / (th[i + 1] - th[i])
        return (1.0 - w) * self.stiffness_Nm_per_rad[i] + w * self.stiffness_Nm_per_rad[i + 1]


def _vector(name: str, value, n: int) -> np.ndarray:
    if value is None:
        return np.zeros(n)
    try:
        a = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise BeamInputError(f"{name} = {value!r}: must be {n} numbers") from None
    if a.size != n or not np.all(np.isfinite(a)):
        raise BeamInputError(f"{name} = {value!r}: must be {n} finite numbers")
    return a.copy()


def _force_function(tip_force) -> Callable[[float], np.ndarray] | None:
    if tip_force is None:
        return None
    if callable(tip_force):
        def force(t: float) -> np.ndarray:
            f = np.asarray(tip_force(t), dtype=float).reshape(-1)
            if f.size != 3 or not np.all(np.isfinite(f)):
                raise BeamInputError(f"tip_force({t}) = {f!r}: must return 3 finite numbers (N)")
            return f
        force(0.0)
        return force
    f = _vector("tip_force", tip_force, 3)
    if not np.any(f):
        return None
    return lambda t: f


def _mass(pm: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    M = pin.crba(pm, data, q)
    return np.triu(M) + np.triu(M, 1).T


def mechanical_energy(model, q_rad: np.ndarray, v_rad_s: np.ndarray,
                      stiffness_Nm_per_rad: np.ndarray | None = None) -> np.ndarray:
    """Kinetic plus spring energy 1/2 v^T M(q) v + 1/2 q^T K q at each sample, J.

    ``q_rad`` and ``v_rad_s`` are (s, n) (or (n,)); ``stiffness_Nm_per_rad`` defaults to the
    model's.
    """
    pm = model.pin_model
    data = pm.createData()
    k = np.asarray(model.stiffness_Nm_per_rad if stiffness_Nm_per_rad is None
                   else stiffness_Nm_per_rad, dtype=float)
    Q = np.atleast_2d(q_rad)
    V = np.atleast_2d(v_rad_s)
    e = np.empty(len(Q))
    for i, (q, v) in enumerate(zip(Q, V, strict=True)):
        e[i] = 0.5 * v @ _mass(pm, data, q) @ v + 0.5 * np.sum(k * q * q)
    return e if np.ndim(q_rad) == 2 else e[0]


def simulate(
    model,
    duration_s: float,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    tip_force: np.ndarray | Callable[[float], np.ndarray] | None = None,
    damping_ratio: float | np.ndarray = 0.02,
    damping: str = "modal",
    stiffness_schedule: StiffnessSchedule | None = None,
    method: str = "trapezoidal",
    rtol: float = 1e-9,
    atol: float | None = None,
    dt: float | None = None,
    output_dt: float | None = None,
    damping_pose: np.ndarray | None = None,
    max_steps: int = 10_000_000,
) -> Trajectory:
    """Integrate the PRBDM's equations of motion from (q0, v0) over ``duration_s``.

    Parameters
    ----------
    model : PrbdmModel
        Provides ``pin_model``, ``tip_frame_id``, ``n_joints`` and ``stiffness_Nm_per_rad``.
    duration_s : float
        Simulated time, s.
    q0, v0 : ndarray, shape (n,), optional
        Initial joint angles (rad) and velocities (rad/s); default zero (straight, at rest).
    tip_force : ndarray (3,) or callable t -> (3,), optional
        World-frame force at the tip point, N (a constant array is a step load applied at t = 0).
    damping_ratio : float or ndarray (n,)
        Modal damping ratios xi_k (``"modal"``) or per-joint factors (``"eq5c"``); 0 disables
        damping.
    damping : {"modal", "eq5c"}
        Damping form, see ``prbdm_pin.damping``.
    stiffness_schedule : StiffnessSchedule, optional
        Pose-dependent stiffness (paper parametrisation); default: the model's constant stiffness.
    method : str
        ``"trapezoidal"`` (fixed step ``dt``) or a ``solve_ivp`` method (``rtol``, ``atol``).
    rtol, atol : float
        Tolerances for ``solve_ivp`` methods (atol defaults to rtol times a joint-angle scale).
    dt : float, optional
        Step of the trapezoidal rule, s (default: lowest natural period / 100).
    output_dt : float, optional
        Sample interval of the returned trajectory, s (default: every step).
    damping_pose : ndarray (n,), optional
        Pose at which the damping matrix is computed and frozen (default: ``q0``).

    Returns
    -------
    Trajectory
    """
    n = int(model.n_joints)
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    q0 = _vector("q0", q0, n)
    v0 = _vector("v0", v0, n)
    force = _force_function(tip_force)
    xi = damping_ratios(damping_ratio, n)
    if damping not in ("modal", "eq5c"):
        raise BeamInputError(f"damping = {damping!r}: must be 'modal' or 'eq5c'")
    if stiffness_schedule is not None and not isinstance(stiffness_schedule, StiffnessSchedule):
        raise BeamInputError("stiffness_schedule: must be a StiffnessSchedule")
    if stiffness_schedule is not None and stiffness_schedule.stiffness_Nm_per_rad.shape[1] != n:
        raise BeamInputError(f"stiffness_schedule: needs {n} joint stiffnesses per pose")
    for name, val in (("dt", dt), ("output_dt", output_dt)):
        if val is not None and not (math.isfinite(val) and 0.0 < val <= duration_s):
            raise BeamInputError(f"{name} = {val!r} s: must be in (0, duration]")
    if method != "trapezoidal" and method not in IVP_METHODS:
        raise BeamInputError(f"method = {method!r}: must be 'trapezoidal' or one of {IVP_METHODS}")
    if not (math.isfinite(rtol) and rtol > 0.0):
        raise BeamInputError(f"rtol = {rtol!r}: must be > 0")

    pm = model.pin_model
    data = pm.createData()
    fid = int(model.tip_frame_id)
    k_const = np.asarray(model.stiffness_Nm_per_rad, dtype=float).copy()
    if stiffness_schedule is None:
        def stiffness(q: np.ndarray) -> np.ndarray:
            return k_const
    else:
        stiffness = stiffness_schedule.at

    C = None
    if np.any(xi > 0.0):
        qc = q0 if damping_pose is None else _vector("damping_pose", damping_pose, n)
        C = damping_matrix(_mass(pm, data, qc), np.diag(stiffness(qc)), xi, damping)

    def tau_external(q: np.ndarray, t: float) -> np.ndarray | None:
        if force is None:
            return None
        J = pin.computeFrameJacobian(pm, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
        return J[:3].T @ force(t)

    start = time.perf_counter()
    if method == "trapezoidal":
        if dt is None:
            w2 = sla.eigh(np.diag(stiffness(q0)), _mass(pm, data, q0), eigvals_only=True)
            dt = 2.0 * math.pi / math.sqrt(max(w2[0], 1e-300)) / 100.0
        t, Q, V, steps, nfev = _trapezoidal(pm, data, stiffness, C, tau_external,
                                            q0, v0, duration_s, dt, output_dt, max_steps)
    else:
        t, Q, V, steps, nfev = _ivp(pm, data, stiffness, C, tau_external, force, fid, q0, v0,
                                    duration_s, method, rtol, atol, output_dt)
    wall = time.perf_counter() - start
    tip = np.empty((len(t), 3))
    for i, q in enumerate(Q):
        pin.framesForwardKinematics(pm, data, q)
        tip[i] = data.oMf[fid].translation
    for a in (t, Q, V, tip):
        a.setflags(write=False)
    return Trajectory(t, Q, V, tip, int(steps), method, wall, int(nfev))


def _trapezoidal(pm, data, stiffness, C, tau_external, q0, v0, duration, dt, output_dt,
                 max_steps):
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
        te = tau_external(q, t)
        return r if te is None else r - te

    # initial acceleration from the equations of motion
    q, v = q0.copy(), v0.copy()
    a = -residual(q, v, zero, 0.0)
    a = np.linalg.solve(_mass(pm, data, q), a)
    a_prev = a
    lu = piv = None
    nfev = 1
    # Newton stops when the update moves q1 by less than this (scaled by the motion's size)
    scale = max(float(np.max(np.abs(q0))), float(np.max(np.abs(v0))) * h, 1e-300)
    if tau_external(q0, 0.0) is not None:
        # a force sets the scale of the motion: its static deflection angle
        scale = max(scale, float(np.max(np.abs(tau_external(q0, 0.0) / stiffness(q0)))))
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
    return t_out, Q, V, nsteps, nfev


def _ivp(pm, data, stiffness, C, tau_external, force, fid, q0, v0, duration, method, rtol,
         atol, output_dt):
    from scipy.integrate import solve_ivp

    n = q0.size
    if atol is None:
        atol = rtol * max(float(np.max(np.abs(q0))), 1e-6)

    def torque(t, q, v):
        tau = -stiffness(q) * q
        if C is not None:
            tau -= C @ v
        te = tau_external(q, t)
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
            Minv = np.triu(Minv) + np.triu(Minv, 1).T
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
        t = np.arange(math.floor(duration / output_dt + 1e-9) + 1) * output_dt
        Y = sol.sol(t).T
    return t, Y[:, :n].copy(), Y[:, n:].copy(), steps, sol.nfev
