"""Time response of a PRBDM through Pinocchio: joint springs, damping and a tip force.

Equations of motion (relative joint angles q, rad):

    M(q) a + h(q, v) + K q + C v = J(q)^T F(t)

with h the Coriolis/centrifugal terms (no gravity), K the diagonal joint stiffness, C a damping
matrix (``prbdm_pin.damping``) and J the world-aligned linear Jacobian of the tip point.

Integrators (``method``)
------------------------
- ``"exponential"`` (default): the exponential Rosenbrock method exprb32 (Hochbruck, Ostermann
  & Schweitzer 2009) with step-size control; nominal (largest) step ``dt`` (default: lowest
  natural period at ``q0`` / 10). The
  dynamics y' = F(t, y), y = (q, v), are linearised, F ~ F_n + J (y - y_n) + b (t - t_n), with J
  from ``pin.computeABADerivatives`` plus the springs, the damping and the load stiffness (closed
  form for the planar chain). That linear system is propagated exactly, mode by mode, through
  the eigen-decomposition of J (phi functions of h lambda): every linear mode, however stiff,
  keeps its exact frequency and damping. The nonlinear remainder is evaluated once, at the
  predicted end point, and enters as a forcing that grows quadratically over the step (third
  order). Two dynamics evaluations per step; the eigen-decomposition is rebuilt only when a
  joint angle has moved by more than ``refresh_rad`` (0.01 rad) since the last one (in between,
  the Jacobian's change enters as a linearly growing forcing). Output at ``output_dt`` uses the
  method's own continuous extension (exact for the linear part).
  Step control: the remainder's quadratic model holds only while the remainder varies slowly
  over a step. When the motion carries higher modes at a finite amplitude (a release from a
  bent pose that is not a mode-1 shape: q0 = 0.1 rad on every joint puts 15-20 % of the tip
  motion into modes 2 and up), the remainder oscillates at their frequencies, h omega_k is
  5-50 at the nominal step, and the fixed-step result was 4-45 % of the peak off DOP853 over
  1 s (3R, 5R chains; third order only once h omega_max < ~1). The correction term
  2 h phi_3(h J) D (exprb32 minus its embedded second-order scheme), measured mode by mode as
  the joint-angle amplitude it would oscillate with (a stiff mode's velocity error shows in q
  only later), is kept below ``_EXP_RTOL`` = 3e-4 of the motion's scale (the largest joint
  angle so far): a step over three times that is redone shorter, the next step follows the
  usual (tol / err)^(1/3) rule, never longer than the nominal step (nor shorter than 1e-3 of
  it). Motion the nominal step resolves (linear, or mode-1-like) keeps the equal nominal steps.
  Measured against DOP853 at rtol 1e-10 (``scripts/bench_exponential_release.py``): releases
  from 0.1 rad on every joint, 1 s, 3R / 5R chains: 0.03-0.08 % of the peak (undamped: 2000-
  5000 steps per second, as many as the highest mode needs, 0.5-1.5 s CPU per simulated
  second, about half DOP853's; modal damping 0.02: 190-300 steps, the high modes decay);
  2500 N step loads with damping 0.02 (the ``scripts/bench_simulate.py`` rows): 0.01-0.06 %
  at about 1.35 times the nominal steps. A step whose correction
  exceeds 5 % of the larger of the motion's scale and the step's travel (or is not finite) is
  halved, up to 6 times in a row (a guard against divergence).
  Limits: it is not symplectic. Linear motion keeps its energy exactly (free vibration of
  amplitude 1e-4 rad: drift 2e-7 over 100 periods) but undamped nonlinear motion drifts
  (2e-6 at 0.01 rad, 2e-3 at 0.1 rad over 100 periods of mode 1): use ``"gauss"`` for long
  undamped runs at large amplitude. A kinked start (0.1 rad on the last joint only, undamped)
  is resolved by the step control (tip within 0.07 % of DOP853 over 0.2 s, energy within
  0.3 %) at about 5000 steps per second.
  With a ``stiffness_schedule`` the Jacobian leaves out dK/dq (the remainder carries it).
  A time-varying force needs ``dt`` well below its shortest period (1/8 of it for 0.5 %, 1/17
  for 0.07 %, harmonic load at 1.2 omega_1): the step control does not see the force's
  variation ahead of the step.
- ``"gauss"``: the 2-stage Gauss-Legendre collocation method, fixed step ``dt``
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
- ``"trapezoidal"``: Newmark's average-acceleration rule (beta = 1/4, gamma = 1/2), fixed
  step ``dt`` (default: 1/100 of the lowest natural period at ``q0``; shortened to divide
  ``output_dt``). Second order, A-stable, no
  numerical damping. The residual M(q1) a1 + h(q1, v1) + K q1 + C v1 - J^T F is evaluated with
  Pinocchio's RNEA and solved by Newton with the tangent
  M + dt/2 (C + dh/dv) + dt^2/4 (K + d(Ma+h)/dq) from ``pin.computeRNEADerivatives``
  (refreshed only when convergence slows). A linear mode of frequency omega
  is integrated at omega_h = (2/dt) arctan(omega dt/2), a relative period error of about
  (omega dt)^2/12 (3.3e-4 for mode 1 at the default step); undamped linear motion conserves
  the energy exactly (to the Newton tolerance).
- Any ``scipy.integrate.solve_ivp`` method (``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"BDF"``,
  ``"LSODA"``) with ``rtol``/``atol``; the accelerations come from Pinocchio's ABA and the implicit
  methods get the analytic Jacobian from ``pin.computeABADerivatives`` (the derivative of the
  tip force's generalised torque with q is left out; it only slows Newton down).

Damping: ``damping="modal"`` (default), ``"eq5c"`` (the paper's Eq. 5c) or ``"stiffness"``
(C = beta K, beta = 2 xi_1 / omega_1: what the MJCF and URDF exports carry as joint damping). C
depends on the pose through M(q) (the stiffness form only through omega_1, hence beta); it is
computed once, at ``damping_pose`` (default: ``q0``), from M there and K there (the schedule's
springs at that pose, if any), and frozen for the run: it then gives the modes of the system
linearised at that pose exactly their ratios, costs nothing per step and keeps the damping force
linear in v. Pass the static equilibrium as ``damping_pose`` to damp the oscillation about a
deflected pose with exactly the requested ratios. A MuJoCo run of the MJCF export matches
``damping="stiffness"`` with beta from the straight pose (the default for ``q0 = 0``; from a bent
start pass ``damping_pose=np.zeros(n)``, as ``prbdm simulate --damping-form stiffness`` does).

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

from .damping import DAMPING_FORMS, damping_matrix, damping_ratios
from .dynamics import planar_lengths
from .errors import BeamInputError, SolveError

__all__ = [
    "Trajectory",
    "StiffnessSchedule",
    "simulate",
    "mechanical_energy",
    "gauss_frequency_ratio",
    "FIXED_STEP_METHODS",
    "IVP_METHODS",
]

FIXED_STEP_METHODS = ("gauss", "exponential", "trapezoidal")
IVP_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")
# default steps per lowest natural period
_DEFAULT_SPP = {"gauss": 40.0, "exponential": 10.0, "trapezoidal": 100.0}


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
        Integrator steps taken (accepted steps for solve_ivp and ``"exponential"``).
    method : str
        Integrator used.
    wall_time_s : float
        Wall time of the whole call (set-up, integration, output), s.
    rhs_evaluations : int
        Dynamics evaluations (ABA for solve_ivp; RNEA residuals, plus one ABA per step when
        interpolating, for ``"gauss"`` and ``"trapezoidal"``; ABA and ABA derivatives for
        ``"exponential"``).
    jacobian_updates : int
        Iteration matrices built (``"gauss"``) or eigen-decompositions of the Jacobian
        (``"exponential"``); 0 otherwise.
    cpu_time_s : float
        Process CPU time of the whole call, s.
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    v_rad_s: np.ndarray
    tip_position_m: np.ndarray
    steps: int
    method: str
    wall_time_s: float
    rhs_evaluations: int = 0
    jacobian_updates: int = 0
    cpu_time_s: float = float("nan")

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


def _force_function(tip_force) -> tuple[Callable[[float], np.ndarray] | None, bool]:
    """The tip force as a function of time (None when absent or zero) and whether it is constant."""
    if tip_force is None:
        return None, True
    if callable(tip_force):
        def force(t: float) -> np.ndarray:
            f = np.asarray(tip_force(t), dtype=float).reshape(-1)
            if f.size != 3 or not np.all(np.isfinite(f)):
                raise BeamInputError(f"tip_force({t}) = {f!r}: must return 3 finite numbers (N)")
            return f
        force(0.0)
        return force, False
    f = _vector("tip_force", tip_force, 3)
    if not np.any(f):
        return None, True
    return (lambda t: f), True


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
    method: str = "exponential",
    rtol: float = 1e-9,
    atol: float | None = None,
    dt: float | None = None,
    output_dt: float | None = None,
    damping_pose: np.ndarray | None = None,
    max_steps: int = 10_000_000,
    steps_per_period: float | None = None,
    refresh_rad: float = 0.01,
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
        Modal damping ratios xi_k (``"modal"``), per-joint factors (``"eq5c"``) or mode 1's
        ratio (``"stiffness"``, one value); 0 disables damping.
    damping : {"modal", "eq5c", "stiffness"}
        Damping form, see ``prbdm_pin.damping``.
    stiffness_schedule : StiffnessSchedule, optional
        Pose-dependent stiffness (paper parametrisation); default: the model's constant stiffness.
    method : str
        ``"exponential"`` (default), ``"gauss"`` (symplectic; long undamped runs) or
        ``"trapezoidal"``, all fixed step ``dt``, or a ``solve_ivp`` method (``rtol``,
        ``atol``). See the module docstring for when to use which.
    rtol, atol : float
        Tolerances for ``solve_ivp`` methods (atol defaults to rtol times a joint-angle scale).
    dt : float, optional
        Step of the fixed-step schemes, s (default: the lowest natural period at ``q0`` divided
        by ``steps_per_period``); for ``"exponential"`` the nominal and largest step, shortened
        by its step control where the motion needs it.
    output_dt : float, optional
        Sample interval of the returned trajectory, s (default: every step).
        ``"exponential"`` evaluates its continuous extension, ``"gauss"`` interpolates between
        its steps (quintic Hermite); ``"trapezoidal"`` shortens its step to divide
        ``output_dt``.
    damping_pose : ndarray (n,), optional
        Pose at which the damping matrix is computed and frozen (default: ``q0``).
    max_steps : int
        Refuse runs that would take more fixed steps.
    steps_per_period : float, optional
        Default-step rule: steps per lowest natural period (``"exponential"`` 10,
        ``"gauss"`` 40, ``"trapezoidal"`` 100).
    refresh_rad : float
        ``"exponential"``: rebuild the linearisation's eigen-decomposition when a joint angle
        has moved by more than this since the last one, rad (0 rebuilds every step).

    Returns
    -------
    Trajectory
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    n = int(model.n_joints)
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    q0 = _vector("q0", q0, n)
    v0 = _vector("v0", v0, n)
    force, constant_force = _force_function(tip_force)
    xi = damping_ratios(damping_ratio, n)
    if damping not in DAMPING_FORMS:
        raise BeamInputError(f"damping = {damping!r}: must be one of {', '.join(DAMPING_FORMS)}")
    if stiffness_schedule is not None and not isinstance(stiffness_schedule, StiffnessSchedule):
        raise BeamInputError("stiffness_schedule: must be a StiffnessSchedule")
    if stiffness_schedule is not None and stiffness_schedule.stiffness_Nm_per_rad.shape[1] != n:
        raise BeamInputError(f"stiffness_schedule: needs {n} joint stiffnesses per pose")
    for name, val in (("dt", dt), ("output_dt", output_dt)):
        if val is not None and not (math.isfinite(val) and 0.0 < val <= duration_s):
            raise BeamInputError(f"{name} = {val!r} s: must be in (0, duration]")
    if not (isinstance(refresh_rad, (int, float, np.number)) and math.isfinite(refresh_rad)
            and refresh_rad >= 0.0):
        raise BeamInputError(f"refresh_rad = {refresh_rad!r}: must be a finite number >= 0")
    if method not in FIXED_STEP_METHODS and method not in IVP_METHODS:
        raise BeamInputError(
            f"method = {method!r}: must be one of {FIXED_STEP_METHODS + IVP_METHODS}"
        )
    if not (math.isfinite(rtol) and rtol > 0.0):
        raise BeamInputError(f"rtol = {rtol!r}: must be > 0")
    if steps_per_period is not None and not (
        math.isfinite(steps_per_period) and steps_per_period >= 1.0
    ):
        raise BeamInputError(f"steps_per_period = {steps_per_period!r}: must be >= 1")

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

    if method in FIXED_STEP_METHODS and dt is None:
        w2 = sla.eigh(np.diag(stiffness(q0)), _mass(pm, data, q0), eigvals_only=True)
        spp = steps_per_period or _DEFAULT_SPP[method]
        dt = min(2.0 * math.pi / math.sqrt(max(w2[0], 1e-300)) / spp, duration_s)

    def tau_external(q: np.ndarray, t: float) -> np.ndarray | None:
        if force is None:
            return None
        J = pin.computeFrameJacobian(pm, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
        return J[:3].T @ force(t)

    try:
        lengths = planar_lengths(pm, fid)
    except BeamInputError:
        lengths = None
    nfact = 0
    if method == "gauss":
        interpolate = output_dt is not None
        # a diverging trial step is detected and halved: no overflow warnings for it
        with np.errstate(over="ignore", invalid="ignore"):
            t, Q, V, Acc, steps, nfev, nfact = _gauss(
                pm, data, fid, k_const, None if stiffness_schedule is None else stiffness, C,
                force, constant_force, q0, v0, duration_s, dt, interpolate, max_steps)
        if interpolate:
            t, Q, V = _hermite_output(t, Q, V, Acc, duration_s, output_dt)
    elif method == "exponential":
        with np.errstate(over="ignore", invalid="ignore"):
            t, Q, V, steps, nfev, nfact = _exponential(
                pm, data, fid, lengths, k_const,
                None if stiffness_schedule is None else stiffness, C, force, constant_force,
                q0, v0, duration_s, dt, output_dt, max_steps, refresh_rad)
    elif method == "trapezoidal":
        t, Q, V, steps, nfev = _trapezoidal(pm, data, stiffness, C, tau_external,
                                            q0, v0, duration_s, dt, output_dt, max_steps)
    else:
        t, Q, V, steps, nfev = _ivp(pm, data, stiffness, C, tau_external, force, fid, q0, v0,
                                    duration_s, method, rtol, atol, output_dt)
    tip = _tip_positions(model, data, Q, lengths)
    for arr in (t, Q, V, tip):
        arr.setflags(write=False)
    return Trajectory(t, Q, V, tip, int(steps), method, time.perf_counter() - wall0,
                      int(nfev), int(nfact), time.process_time() - cpu0)


def _tip_positions(model, data: pin.Data, Q: np.ndarray, lengths: np.ndarray | None
                   ) -> np.ndarray:
    """Tip positions (s, 3) at the output samples only; closed form for a planar chain
    (``lengths``, None otherwise)."""
    pm, fid = model.pin_model, int(model.tip_frame_id)
    tip = np.empty((len(Q), 3))
    if lengths is not None:
        # joint i (1-based) turns link i to the world angle q_1 + ... + q_i about +y
        phi = np.cumsum(Q, axis=1)
        tip[:, 0] = lengths[0] + np.cos(phi) @ lengths[1:]
        tip[:, 1] = 0.0
        tip[:, 2] = -(np.sin(phi) @ lengths[1:])
        return tip
    for i, q in enumerate(Q):
        pin.framesForwardKinematics(pm, data, q)
        tip[i] = data.oMf[fid].translation
    return tip


def _hermite_output(t_nodes, Q, V, Acc, duration, output_dt):
    """Samples every ``output_dt`` by quintic Hermite interpolation of (q, v, a) at the steps.

    Local error O(dt^6) in q and O(dt^5) in v: below the scheme's own O(dt^4) error.
    """
    nout = math.floor(duration / output_dt + 1e-9) + 1
    t = np.arange(nout) * output_dt
    h = t_nodes[1] - t_nodes[0]
    i = np.minimum((t / h).astype(int), len(t_nodes) - 2)
    s = ((t - t_nodes[i]) / h)[:, None]
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5
    h1 = s - 6 * s3 + 8 * s4 - 3 * s5
    h2 = 0.5 * (s2 - 3 * s3 + 3 * s4 - s5)
    h3 = 0.5 * (s3 - 2 * s4 + s5)
    h4 = -4 * s3 + 7 * s4 - 3 * s5
    h5 = 10 * s3 - 15 * s4 + 6 * s5
    d0 = -30 * s2 + 60 * s3 - 30 * s4
    d1 = 1 - 18 * s2 + 32 * s3 - 15 * s4
    d2 = s - 4.5 * s2 + 6 * s3 - 2.5 * s4
    d3 = 1.5 * s2 - 4 * s3 + 2.5 * s4
    d4 = -12 * s2 + 28 * s3 - 15 * s4
    q0, v0, a0 = Q[i], V[i], Acc[i]
    q1, v1, a1 = Q[i + 1], V[i + 1], Acc[i + 1]
    hh = h * h
    q = h0 * q0 + h5 * q1 + h * (h1 * v0 + h4 * v1) + hh * (h2 * a0 + h3 * a1)
    v = (d0 * (q0 - q1)) / h + d1 * v0 + d4 * v1 + h * (d2 * a0 + d3 * a1)
    return t, q, v


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
_GAUSS_HALVINGS = 3


def gauss_frequency_ratio(omega_dt: float | np.ndarray) -> float | np.ndarray:
    """Numerical over exact frequency of an undamped linear mode under 2-stage Gauss-Legendre.

    The stability function R(z) = (1 + z/2 + z^2/12) / (1 - z/2 + z^2/12) has modulus 1 at
    z = i x (x = omega dt) and phase 2 arctan((x/2) / (1 - x^2/12)); the ratio is
    1 - x^4/720 + O(x^6).
    """
    x = np.asarray(omega_dt, dtype=float)
    return 2.0 * np.arctan2(0.5 * x, 1.0 - x * x / 12.0) / x


def _gauss(pm, data, fid, k_const, stiffness, C, force, constant_force, q0, v0, duration, dt,
           need_accel, max_steps, depth=0):
    """Fixed-step 2-stage Gauss-Legendre, simplified Newton on the two stage accelerations.

    ``stiffness`` is None for the constant springs ``k_const``. A step whose Newton iteration
    fails (with a fresh iteration matrix) is redone as two half steps, recursively up to
    ``_GAUSS_HALVINGS`` times (``depth`` counts them). Returns the node times, q, v, a (None
    unless ``need_accel``), steps, residual evaluations and iteration-matrix builds.
    """
    n = q0.size
    # equal steps ending on ``duration``; at most dt (up to a 1e-6 relative rounding slack)
    nsteps = max(1, math.ceil(duration / dt - 1e-6))
    if nsteps > max_steps:
        raise BeamInputError(f"dt = {dt} s: {nsteps} steps exceed max_steps = {max_steps}")
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

    def springs(q):
        return k_const if stiffness is None else stiffness(q)

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
        M = np.triu(M) + np.triu(M, 1).T
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
        scale = max(scale, float(np.abs(ext_torque(q0, f6) / springs(q0)).max()))
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
            if depth >= _GAUSS_HALVINGS:
                raise SolveError(f"Gauss-Legendre: Newton did not converge at t = {t0 + h:.6g} "
                                 f"s (dt = {h:.3g} s after {depth} halvings); try a smaller dt")
            # a violent stretch: redo this step as two half steps (recursively)
            sub_force = None if force is None else (lambda t, t0=t0: force(t0 + t))
            _, Qs, Vs, As, sub_steps, sub_fev, sub_fact = _gauss(
                pm, data, fid, k_const, stiffness, C, sub_force, constant_force, q, v, h,
                0.5 * h, need_accel, max_steps, depth + 1)
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


# Taylor coefficients 1 / (m + k)! of phi_k, k = 1, 2, 3, highest power first (Horner)
_PHI_TAYLOR = [[1.0 / math.factorial(m + k) for m in range(9, -1, -1)] for k in (1, 2, 3)]


def _phi123(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """phi_1, phi_2, phi_3 of complex ``z`` (elementwise): phi_k(z) = sum_m z^m / (m + k)!.

    Taylor series (10 terms: truncation below 1e-16) for |z| < 0.1; elsewhere the recurrence
    phi_{k+1} = (phi_k - 1/k!) / z, whose cancellation costs at most eps / |z|^3 ~ 2e-13.
    """
    small = np.abs(z) < 0.1
    zb = np.where(small, 1.0, z)
    p1 = (np.exp(zb) - 1.0) / zb
    p2 = (p1 - 1.0) / zb
    p3 = (p2 - 0.5) / zb
    if small.any():
        zs = z[small]
        for p, coef in zip((p1, p2, p3), _PHI_TAYLOR, strict=True):
            acc = np.full(zs.shape, coef[0], dtype=complex)
            for c in coef[1:]:
                acc = acc * zs + c
            p[small] = acc
    return p1, p2, p3


def _eig_with_inverse(J: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues lam, eigenvectors V and V^-1 of a real matrix; SolveError when defective."""
    try:
        lam, V = np.linalg.eig(J)
        return lam, V, np.linalg.inv(V)
    except np.linalg.LinAlgError:
        raise SolveError(f"exponential integrator: defective or non-finite Jacobian at "
                         f"t = {t:.6g} s") from None


def _generalised_force(pm, data, fid, lengths):
    """tau_ext(q, f) = J(q)^T f, its derivative d tau_ext / dq (the load stiffness), and a
    function returning both.

    Closed form for the planar chain (link i at world angle phi_i = q_1 + ... + q_i); Pinocchio's
    frame Jacobian and forward differences otherwise.
    """
    if lengths is not None:
        links = lengths[1:]
        n = links.size
        # tail[j, i] = 1 for i >= j: joint j carries the links beyond it
        tail = np.triu(np.ones((n, n)))
        upper = np.maximum.outer(np.arange(n), np.arange(n))

        def tau_ext(q, f):
            phi = np.cumsum(q)
            return tail @ (links * (-f[0] * np.sin(phi) - f[2] * np.cos(phi)))

        def load_stiffness(q, f):
            phi = np.cumsum(q)
            return (tail @ (links * (-f[0] * np.cos(phi) + f[2] * np.sin(phi))))[upper]

        def both(q, f):
            phi = np.cumsum(q)
            s, c = np.sin(phi), np.cos(phi)
            return (tail @ (links * (-f[0] * s - f[2] * c)),
                    (tail @ (links * (-f[0] * c + f[2] * s)))[upper])

        return tau_ext, load_stiffness, both

    lwa = pin.LOCAL_WORLD_ALIGNED

    def tau_ext(q, f):
        return pin.computeFrameJacobian(pm, data, q, fid, lwa)[:3].T @ f

    def load_stiffness(q, f):
        base = tau_ext(q, f)
        eps = 1e-7 * max(1.0, float(np.abs(q).max()))
        out = np.empty((q.size, q.size))
        for j in range(q.size):
            qj = q.copy()
            qj[j] += eps
            out[:, j] = (tau_ext(qj, f) - base) / eps
        return out

    def both(q, f):
        return tau_ext(q, f), load_stiffness(q, f)

    return tau_ext, load_stiffness, both


# a step whose correction 2 h phi_3(h J) D exceeds this fraction of the motion's scale (the
# largest joint angle so far) is halved (the divergence guard)
_EXP_LOCAL_TOL = 0.05
_MAX_HALVINGS = 6
# step control: the correction's modal amplitude is kept near this fraction of the motion's
# scale; a step over _EXP_REJECT times it is redone shorter (never below _EXP_MIN_STEP times the
# nominal step). 3e-4 keeps releases within 0.1 % of the peak over 1 s; rejecting only above 3x
# (the next step shrinks anyway) saves the rejected steps' evaluations on step loads.
_EXP_RTOL = 3e-4
_EXP_MIN_STEP = 1e-3
_EXP_REJECT = 3.0


def _exponential(pm, data, fid, lengths, k_const, stiffness, C, force, constant_force, q0, v0,
                 duration, dt, output_dt, max_steps, refresh_rad):
    """Exponential Rosenbrock method exprb32 (Hochbruck, Ostermann & Schweitzer 2009), step
    controlled, nominal step ``dt``.

    y = (q, v), y' = F(t, y) = (v, ABA(q, v, tau)). The dynamics are linearised,
    F ~ F_n + J (y - y_n) + b_n (t - t_n) (J from ``pin.computeABADerivatives``, the springs,
    the damping and the load stiffness; b_n from the force's rate), that linear system is
    propagated exactly through the eigen-decomposition J = V diag(lam) V^-1 (phi functions of
    h lam, mode by mode), and the remainder g = F - (linearisation), evaluated once at the
    predicted end point U, is taken to grow quadratically over the step:
    y_{n+1} = U + 2 h phi_3(h J) D. The decomposition is rebuilt only when a joint angle has
    moved by more than ``refresh_rad`` since the last build; in between, the Jacobian's change
    J_n - J enters as a forcing that grows linearly over the step. Two dynamics evaluations per
    step (one with derivatives, one ABA). The correction 2 h phi_3(h J) D is the local error
    estimate of the embedded second-order scheme; its modal joint-angle amplitude sets the step
    (``_EXP_RTOL``, ``_EXP_REJECT``), capped at the nominal step. A step whose correction is
    large (``_EXP_LOCAL_TOL``) or not finite is halved, up to ``_MAX_HALVINGS`` times in a row.
    Returns t, Q, V, steps, evaluations, decompositions.
    """
    n = q0.size
    nsteps = max(1, math.ceil(duration / dt - 1e-6))
    if nsteps > max_steps:
        raise BeamInputError(f"dt = {dt} s: {nsteps} steps exceed max_steps = {max_steps}")
    h0 = duration / nsteps
    n2 = 2 * n
    tau_ext, _, tau_and_load_stiffness = _generalised_force(pm, data, fid, lengths)
    Jm = np.zeros((n2, n2))
    Jm[:n, n:] = np.eye(n)
    const_spring = -np.diag(k_const) if stiffness is None else None
    minus_C = None if C is None else -C
    aba, aba_derivatives = pin.aba, pin.computeABADerivatives
    varying = force is not None and not constant_force
    f_const = force(0.0) if force is not None else None
    half_minv = None
    # step records for the dense output: start time, step, start state, decomposition, coefs
    records = []
    counts = {"fev": 0, "decomp": 0, "steps": 0}
    # the motion's scale: largest joint angle so far, at least the static deflection angle of the
    # initial force and the first step's travel
    scale = [max(float(np.abs(q0).max()), float(np.abs(v0).max()) * h0, 1e-300)]
    if force is not None:
        scale[0] = max(scale[0], float(np.abs(tau_ext(q0, force(0.0)) / (
            k_const if stiffness is None else stiffness(q0))).max()))

    def torque(q, v, f):
        tau = -(k_const if stiffness is None else stiffness(q)) * q
        if C is not None:
            tau -= C @ v
        if f is not None:
            tau += tau_ext(q, f)
        return tau

    # the decomposition of the last Jacobian and the phi functions of its step
    cache = {"q": None, "h": None}

    def attempt(t, y, h):
        """One exprb32 step of length h from (t, y): the end state, the correction's size in q,
        its reference (the guard's) and the dense-output record."""
        nonlocal half_minv
        q, v = y[:n], y[n:]
        f = force(t) if varying else f_const
        tau = -(k_const if stiffness is None else stiffness(q)) * q
        if C is not None:
            tau -= C @ v
        Kt = const_spring if stiffness is None else -np.diag(stiffness(q))
        if f is not None:
            tau_f, k_f = tau_and_load_stiffness(q, f)
            tau += tau_f
            Kt = Kt + k_f
        dadq, dadv, Minv = aba_derivatives(pm, data, q, v, tau)
        counts["fev"] += 1
        if half_minv is None:
            # some Pinocchio versions fill only the upper triangle of M^-1
            half_minv = n > 1 and not np.any(np.tril(Minv, -1))
        if half_minv:
            Minv = np.triu(Minv) + np.triu(Minv, 1).T
        Fn = np.concatenate((v, data.ddq))
        Jm[n:, :n] = dadq + Minv @ Kt
        Jm[n:, n:] = dadv if C is None else dadv + Minv @ minus_C
        if cache["q"] is None or np.abs(q - cache["q"]).max() > refresh_rad:
            cache["lam"], cache["V"], cache["Vinv"] = _eig_with_inverse(Jm, t)
            cache["J"] = Jm.copy()
            # the largest joint angle each mode's unit coordinate swings through
            cache["vq"] = np.abs(cache["V"][:n]).max(axis=0)
            cache["q"] = q.copy()
            cache["h"] = None
            counts["decomp"] += 1
            b = np.zeros(n2)
        else:
            # the Jacobian's change since the decomposition acts like a forcing that grows
            # linearly over the step, (J_n - J) (y - y_n) ~ (J_n - J) F_n s
            b = (Jm - cache["J"]) @ Fn
        lam, Vc, Vinv, J = cache["lam"], cache["V"], cache["Vinv"], cache["J"]
        if cache["h"] != h:
            hp1, hhp2, hp3 = _phi123(h * lam)
            cache["phi"] = (h * hp1, h * h * hhp2, 2.0 * h * hp3)
            cache["h"] = h
        hp1, hhp2, hp3 = cache["phi"]
        if varying:
            # the force's rate by a short forward difference (no evaluation before t = 0)
            delta = 1e-6 * h
            b[n:] += Minv @ tau_ext(q, (force(t + delta) - f) / delta)
        c1 = Vinv @ Fn
        cb = Vinv @ b
        U = y + (Vc @ (hp1 * c1 + hhp2 * cb)).real
        qU, vU = U[:n], U[n:]
        aU = aba(pm, data, qU, vU, torque(qU, vU, force(t + h) if varying else f))
        counts["fev"] += 1
        D = np.concatenate((vU - Fn[:n], aU - Fn[n:])) - J @ (U - y) - h * b
        cd = Vinv @ D
        zc = hp3 * cd
        corr = (Vc @ zc).real
        size = float(np.abs(corr[:n]).max())
        ref = max(scale[0], float(np.abs(U[:n] - q).max()))
        # the correction's modal content as the joint-angle amplitude it would oscillate with:
        # a velocity error of a stiff mode shows in q only later, over its oscillation
        amp = float(cache["vq"] @ np.abs(zc))
        return U + corr, size, ref, amp, (t, h, lam, Vc, c1, cd, cb)

    def accept(y1, record):
        scale[0] = max(scale[0], float(np.abs(y1[:n]).max()))
        counts["steps"] += 1
        if counts["steps"] > max_steps:
            raise BeamInputError(f"the exponential integrator took more than max_steps = "
                                 f"{max_steps} steps")
        records.append(record)
        t_list.append(record[0] + record[1])
        y_list.append(y1)

    t_list, y_list = [0.0], [np.concatenate((q0, v0))]
    # step control: the correction 2 h phi_3(h J) D is the difference between exprb32 and its
    # embedded second-order scheme, an upper estimate of the local error. The step never
    # exceeds h0, so motion the scheme resolves at h0 (linear, or mode-1-like) keeps the equal
    # steps h0.
    t, y, h = 0.0, y_list[0].copy(), h0
    halvings = 0
    rejected = False
    while duration - t > 1e-9 * h0:
        left = duration - t
        if h >= left * (1.0 - 1e-9):
            h = left
        elif h > 0.5 * left:
            h = 0.5 * left  # no sliver of a last step
        first = attempt(t, y, h)
        y1, size, ref, amp, _ = first
        if not (size <= _EXP_LOCAL_TOL * ref):  # also catches NaN
            # the divergence guard: halve the step, at most _MAX_HALVINGS times in a row
            if halvings >= _MAX_HALVINGS:
                raise SolveError(f"exponential integrator: no acceptable step at "
                                 f"t = {t:.6g} s after {halvings} halvings (dt = {h:.3g} s); "
                                 "try method='gauss' or a smaller dt")
            halvings += 1
            h *= 0.5
            continue
        halvings = 0
        err = amp / (_EXP_RTOL * scale[0])
        if err > _EXP_REJECT and h > h0 * _EXP_MIN_STEP:
            h = max(h * max(0.2, 0.9 * err ** (-1.0 / 3.0)), h0 * _EXP_MIN_STEP)
            rejected = True
            continue
        accept(y1, first[4])
        y = y1
        t = t_list[-1] = t + h
        grow = 2.0 if err <= (0.9 / 2.0) ** 3 else 0.9 * err ** (-1.0 / 3.0)
        if rejected:
            grow = min(grow, 1.0)  # no growth right after a rejection (Hairer & Wanner)
            rejected = False
        h = min(h0, h * grow)
    t_nodes = np.array(t_list)
    t_nodes[-1] = duration
    Y = np.array(y_list)
    if output_dt is None:
        return (t_nodes, Y[:, :n].copy(), Y[:, n:].copy(), counts["steps"], counts["fev"],
                counts["decomp"])
    # continuous extension of each step: the same formula with h replaced by the offset s
    nout = math.floor(duration / output_dt + 1e-9) + 1
    t_out = np.arange(nout) * output_dt
    starts = t_nodes[:-1]
    idx = np.clip(np.searchsorted(starts, t_out, side="right") - 1, 0, len(starts) - 1)
    hs = np.array([r[1] for r in records])[idx][:, None]
    s_col = np.minimum(t_out - starts[idx], hs[:, 0])[:, None]
    lam = np.array([r[2] for r in records])[idx]
    Vs = np.array([r[3] for r in records])[idx]
    C_all = np.array([r[4:] for r in records])[idx]
    p1, p2, p3 = _phi123(s_col * lam)
    coef = (s_col * p1 * C_all[:, 0] + (2.0 * s_col**3 / hs**2) * p3 * C_all[:, 1]
            + s_col**2 * p2 * C_all[:, 2])
    Yo = Y[idx] + np.einsum("sij,sj->si", Vs, coef).real
    return t_out, Yo[:, :n].copy(), Yo[:, n:].copy(), counts["steps"], counts["fev"], \
        counts["decomp"]
