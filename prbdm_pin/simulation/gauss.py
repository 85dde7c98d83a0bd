"""2-stage Gauss-Legendre integrator, fixed step, symplectic (``Gauss``).

``Gauss()`` (``method="gauss"``): the 2-stage Gauss-Legendre collocation method, fixed step
``dt_s`` (default: lowest natural period at ``q0`` / 40). Fourth order, symplectic, A-stable, no
numerical damping: a linear mode is integrated at the frequency ratio
:func:`gauss_frequency_ratio` = 1 - (omega dt)^4/720 + ... (period error 3.4e-6 at 40
steps per period, 1.35e-5 at 20); the energy of undamped linear motion is conserved exactly
(a quadratic invariant), for the nonlinear chain it stays bounded (no drift).
The unknowns are the two stage accelerations; each iteration evaluates the residual
M a + h + K q + C v - J^T F by two Pinocchio RNEA calls and applies a stored inverse of the
2n x 2n iteration matrix (analytic: ``pin.computeRNEADerivatives``, the springs, the damping
and the load stiffness in closed form for the planar chain). Newton starts from the step of
the equations linearised at the step's start (exact for a linear chain: one iteration), with
the matrix of an earlier step (simplified Newton, rebuilt at the next step when the
contraction rate exceeds 0.03); when it contracts slowly (rate above 0.3) the matrix is
rebuilt at the stages' current iterates (Newton's own, quadratic). Newton stops when the
update of (q1, dt v1) is below 1e-8 of the motion's scale. Every step ends with one ABA (the
acceleration there: the next predictor and the output's). Output at ``output_dt`` is
interpolated (quintic Hermite in q, v, a at the steps), and the tip position is computed only
at the output samples (closed form for the planar chain).
Why 40 steps per period, not 20: mode 1 alone needs only ~T1/10 for 0.1 %, but a step load
excites every mode, and the phase error of modes 2-3 sets the error of the tip response:
against DOP853 (rtol 1e-10), 5R chain, 2500 N step, 1 s: 3.2 % of the peak at T1/20,
1.35 % at T1/30, 0.7 % at T1/40 (measured; ``scripts/bench_simulate.py`` tabulates it).
Modes with omega dt >> 1 stay bounded and barely damped by the scheme, at a wrong frequency,
as long as their amplitude is small. A motion that swings them at a finite amplitude (a
release from a bent pose that is not a mode-1 shape) is another matter: the default step
leaves the tip 12-20 % of the peak off DOP853 on the 5R and 8R releases from 0.1 rad per
joint, and at omega_max dt ~ 8 the nonlinear chain's energy grows under the scheme until
Newton fails (measured on the 8R release; at omega_max dt = 2 it holds to 1e-4). Such a
motion needs ``dt`` of at most 2 / omega_max (the error message says its value), and for
accuracy 0.5 / omega_max; the error-controlled integrators are cheaper there. A step whose
Newton fails is redone as two half steps, recursively up to ``max_halvings`` (3) times (then
SolveError asks for a smaller ``dt``).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from ..options.integrators import Gauss
from .gauss_newton import iteration_matrix, linear_predictor, omega_max
from .steps import equal_steps
from .system import (
    System,
    generalised_force,
    static_angle_rad,
    weight_angle_rad,
)
from .trajectory import hermite_step

# 2-stage Gauss-Legendre tableau (c, A, b = (1/2, 1/2)); for q'' = a the stage positions use
# A @ A and the end position b^T A
_R3 = math.sqrt(3.0)
_GL_C = np.array([0.5 - _R3 / 6.0, 0.5 + _R3 / 6.0])
_GL_A = np.array([[0.25, 0.25 - _R3 / 6.0], [0.25 + _R3 / 6.0, 0.25]])
_GL_AA = _GL_A @ _GL_A
_GL_BA = 0.5 * _GL_A.sum(axis=0)
_NEWTON_RTOL = 1e-8
_REFRESH_RATE = 0.03
# Newton's iterations per step, the rate above which the matrix is rebuilt at the stages'
# iterates, and the rebuilds per step
_MAX_ITERATIONS = 20
_SLOW_RATE = 0.3
_MAX_REBUILDS = 4
_SYSTEM_FORCE = object()  # GaussStepper's default force: the system's, from t0 on


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


class GaussStepper:
    """Equal 2-stage Gauss-Legendre steps, simplified Newton on the two stage accelerations.

    The stepper of ``Gauss``. A step whose Newton iteration fails (with a fresh iteration
    matrix) is redone as two half steps by a stepper of its own, recursively up to
    ``settings.max_halvings`` times. It evaluates the acceleration at every step's end (one
    ABA): the next step's predictor starts from it, and the quintic Hermite output uses it.

    Parameters
    ----------
    settings : Gauss
    system : System
    t0, t_bound : float
        Start and end time, s.
    y0 : ndarray, shape (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    dt_s : float
        Step, s; shortened to divide the run into equal steps.
    max_steps : int
        Refuse a step that would take more steps (BeamInputError).
    dense : bool
        Whether ``dense_output`` will be asked for (kept for the loop's call: the end's
        acceleration is evaluated either way).
    force : callable or None
        The tip force (N) of the time since ``t0`` (s) (default: the system's, from ``t0`` on);
        a halved step passes its own.
    depth : int
        Halvings above this stepper.
    origin_s : float
        The run's time at this stepper's t = 0, s (a halved step's start; for messages).
    """

    def __init__(self, settings: Gauss, system: System, t0: float, y0: np.ndarray,
                 t_bound: float, *, dt_s: float, max_steps: int, dense: bool,
                 force=_SYSTEM_FORCE, depth: int = 0, origin_s: float = 0.0):
        if force is _SYSTEM_FORCE:
            f = system.tip_force_N
            force = f if t0 == 0.0 or f is None else (lambda t: f(t0 + t))
        self.settings, self.system, self.force = settings, system, force
        self.depth, self.max_steps, self.dense = depth, max_steps, dense
        self.origin_s = origin_s
        self.t0_s, self.t_bound, self.n = t0, t_bound, y0.size // 2
        n, duration = self.n, t_bound - t0
        self.nsteps = equal_steps(duration, dt_s, max_steps)
        self.h = h = duration / self.nsteps
        self.hA, self.hhAA, self.hc = h * _GL_A, h * h * _GL_AA, h * _GL_C
        self.hhba = h * h * _GL_BA
        self.hc_col = self.hc[:, None]
        C = system.damping_Nms_per_rad
        self.Ct = None if C is None else np.ascontiguousarray(C.T)
        # the load stiffness d(J^T f)/dq of a tip force f (3,) for the iteration matrix (closed
        # form for a planar chain)
        _, _, self._tau_and_stiffness = generalised_force(
            system.pin_model, system.data, system.tip_frame_id, system.lengths_m)
        self.q, self.v = y0[:n].copy(), y0[n:].copy()
        self.a = self._accel(self.q, self.v, 0.0)
        # flat stage accelerations X = (A_1, A_2), the stacked stage states Z = (Q_1, Q_2, V_1,
        # V_2) = base + G X
        self.Xf = np.concatenate((self.a, self.a))
        self.X = self.Xf.reshape(2, n)
        self.G = np.vstack((self.hhAA, self.hA))
        self.base = np.empty((4, n))
        # linear forces K Q_i + C V_i of the stages as lin0 + L @ Xf (one matvec per iteration)
        self.L = np.zeros((2 * n, 2 * n))
        if system.schedule is None:
            self.L += np.kron(self.hhAA, np.diag(system.stiffness_Nm_per_rad))
        if C is not None:
            self.L += np.kron(self.hA, C)
        # maps an update of Xf to the updates of q1 and dt * v1, which carry on to the next step
        eye = np.eye(n)
        self.E = np.vstack((np.kron(self.hhba[None, :], eye),
                            np.kron(np.full((1, 2), 0.5 * h * h), eye)))
        self.B, self.r = None, np.empty(2 * n)
        # the counts: residuals (two RNEA per iteration) and accelerations (ABA), iteration
        # matrices, steps (a halved one as the half steps it took)
        self.rhs_evaluations, self.jacobian_updates, self.steps, self.k = 1, 0, 0, 0
        # Newton stops when the update moves (q1, dt v1) by less than rtol * this scale
        # (a nanoradian floor: a run from rest under a force that starts at zero has no scale)
        q0, v0 = self.q, self.v
        scale = max(float(np.abs(q0).max()), float(np.abs(v0).max()) * h, 1e-9)
        if force is not None:
            scale = max(scale, static_angle_rad(self._tau_ext(q0, force(0.0)),
                                                system.springs(q0)))
        self.scale = max(scale, weight_angle_rad(system, q0))
        self.tol2 = (_NEWTON_RTOL * self.scale) ** 2
        self.rho = 1.0  # contraction rate of the last iterations, carried across steps
        self.constant_force = system.constant_force and force is not None
        # the stages' tip forces, N
        self.F = np.zeros((2, 3))
        if self.constant_force:
            self.F[:] = force(0.0)
        self.t = self.t_old = t0
        self.y, self.done = y0.copy(), False

    def _tau_ext(self, q, f):
        """Return J(q)^T f of a tip force f (3,), N m, by Pinocchio's frame Jacobian.

        The cheapest call per residual; one coordinate's Jacobian comes back as a vector (the
        IndexError of a 1R under a tip force), hence the reshape.
        """
        sy = self.system
        J = pin.computeFrameJacobian(sy.pin_model, sy.data, q, sy.tip_frame_id,
                                     pin.LOCAL_WORLD_ALIGNED)
        return J.reshape(6, -1)[:3].T @ f

    def _accel(self, q, v, t):
        sy = self.system
        tau = -sy.springs(q) * q
        if sy.damping_Nms_per_rad is not None:
            tau -= sy.damping_Nms_per_rad @ v
        if self.force is not None:
            tau += self._tau_ext(q, self.force(t))
        return pin.aba(sy.pin_model, sy.data, q, v, tau)

    def _build(self, states) -> None:
        """Build the iteration matrix at the stages' ``states`` (see ``iteration_matrix``)."""
        self.B, self._start_jacobians = iteration_matrix(
            self.system, self._tau_and_stiffness, self.hA, self.hhAA, self.E, states)
        self.jacobian_updates += 1

    def _newton(self, q, v, t0, fresh: bool = False) -> bool:
        """Solve the stage accelerations of the step from (q, v) at t0; whether it converged.

        From the linearised step (``gauss_newton.linear_predictor``), simplified Newton with the
        matrix of an earlier state (``fresh``: of this step's start); when it contracts slowly
        (rate above ``_SLOW_RATE``: the stages have moved far from where the matrix was built)
        the matrix is rebuilt at the stages' current iterates, which is Newton's own and
        converges quadratically near the solution.
        """
        sy, n, X, Xf, r = self.system, self.n, self.X, self.Xf, self.r
        pm, data, stiffness = sy.pin_model, sy.data, sy.schedule
        n2 = 2 * n
        F = self.F
        if self.force is not None and not self.constant_force:
            F[0] = self.force(t0 + self.hc[0])
            F[1] = self.force(t0 + self.hc[1])
        f_a, f_b = (None, None) if self.force is None else (F[0], F[1])
        base = self.base
        base[:2] = q + self.hc_col * v
        base[2:] = v
        lin0 = np.zeros(n2)
        if stiffness is None:
            lin0 += (base[:2] * sy.stiffness_Nm_per_rad).reshape(-1)
        if self.Ct is not None:
            lin0 += np.concatenate((v @ self.Ct, v @ self.Ct))
        if self.B is None or fresh:
            self._build(((q, v, self.a, f_a), (q, v, self.a, f_b)))
        change = None
        if self.force is not None and not self.constant_force:
            tau0 = self._tau_ext(q, self.force(t0))
            change = (self._tau_ext(q, f_a) - tau0, self._tau_ext(q, f_b) - tau0)
        Xf[:] = linear_predictor(self.B, self._start_jacobians, self.a, v, self.hc, change)
        prev, rebuilds = math.inf, 0
        for _it in range(_MAX_ITERATIONS):
            Z = base + self.G @ X
            np.add(lin0, self.L @ Xf, out=r)
            r[:n] += pin.rnea(pm, data, Z[0], Z[2], X[0])
            r[n:] += pin.rnea(pm, data, Z[1], Z[3], X[1])
            if stiffness is not None:
                r[:n] += stiffness(Z[0]) * Z[0]
                r[n:] += stiffness(Z[1]) * Z[1]
            if self.force is not None:
                r[:n] -= self._tau_ext(Z[0], f_a)
                r[n:] -= self._tau_ext(Z[1], f_b)
            self.rhs_evaluations += 2
            out = self.B @ r
            Xf -= out[:n2]
            e = out[n2:]
            size2 = float(e @ e)
            measured = prev < math.inf
            if measured:
                self.rho = math.sqrt(size2 / prev) if prev > 0.0 else 0.0
            rho = self.rho
            # Hairer & Wanner's stopping rule: a contraction of rate rho leaves at most
            # rho / (1 - rho) times the last update; only with the rate of this step's own
            # iterations (an earlier step's, after Newton's quadratic convergence, can be
            # tiny and would pass a first update of any size)
            if size2 <= self.tol2 or (measured and rho < 1.0 and (rho / (1.0 - rho)) ** 2
                                      * size2 <= self.tol2):
                if rho > _REFRESH_RATE:
                    self.B = None  # slow convergence: rebuild the iteration matrix next step
                return True
            if not math.isfinite(size2):
                return False
            prev = size2
            if measured and rho > _SLOW_RATE and rebuilds < _MAX_REBUILDS:
                Z = base + self.G @ X
                self._build(((Z[0], Z[2], X[0], f_a), (Z[1], Z[3], X[1], f_b)))
                rebuilds += 1
                prev = math.inf  # the next rate is the new matrix's
        self.B = None
        return False

    def step(self) -> None:
        """Take the next equal step (as half steps when Newton fails on it)."""
        h, X = self.h, self.X
        self.k += 1
        t0 = (self.k - 1) * h
        q, v = self.q, self.v
        self._start = (q, v, self.a)
        # a diverging trial step is detected and halved: no overflow warnings for it
        with np.errstate(over="ignore", invalid="ignore"):
            # a failed Newton is retried once with the matrix of the step's start, then the
            # step is halved
            converged = self._newton(q, v, t0) or self._newton(q, v, t0, fresh=True)
            if not converged:
                self._halve(q, v, t0)
            else:
                self.q = q = q + h * v + self.hhba @ X
                self.v = v = v + 0.5 * h * (X[0] + X[1])
                # the end's acceleration: the output's Hermite data and the next predictor's
                self.a = self._accel(q, v, t0 + h)
                self.rhs_evaluations += 1
                self.scale = max(self.scale, float(np.abs(q).max()))
                self.tol2 = (_NEWTON_RTOL * self.scale) ** 2
        self.steps += 1
        self.t_old = self.t0_s + (self.k - 1) * h
        self.done = self.k == self.nsteps
        self.t = self.t_bound if self.done else self.t0_s + self.k * h
        self.y = np.concatenate((self.q, self.v))

    def _halve(self, q, v, t0) -> None:
        """Redo the step from (q, v) at t0 as two half steps (recursively)."""
        h, st = self.h, self.settings
        if self.depth >= st.max_halvings:
            raise SolveError(f"Gauss-Legendre: Newton did not converge at t = "
                             f"{self.origin_s + self.t0_s + t0 + h:.6g} "
                             f"s (dt = {h:.3g} s after {self.depth} halvings); try a smaller "
                             f"dt: at most 2 / omega_max = {2.0 / omega_max(self.system, q):.3g} s "
                             "for a motion that swings the stiffest mode")
        force = self.force
        sub_force = None if force is None else (lambda t, t0=t0: force(t0 + t))
        sub = GaussStepper(st, self.system, 0.0, np.concatenate((q, v)), h, dt_s=0.5 * h,
                           max_steps=self.max_steps, dense=self.dense, force=sub_force,
                           depth=self.depth + 1, origin_s=self.origin_s + self.t0_s + t0)
        while not sub.done:
            sub.step()
        self.q, self.v = sub.q.copy(), sub.v.copy()
        self.rhs_evaluations += sub.rhs_evaluations
        self.jacobian_updates += sub.jacobian_updates
        self.steps += sub.steps - 1
        self.a = sub.a.copy()
        self.B = None

    def dense_output(self):
        """Return the last step's quintic Hermite interpolant: times (m,) s -> states (m, 2n)."""
        start, end = self._start, (self.q, self.v, self.a)
        t_start, h = self.t_old, self.h
        return lambda t_s: hermite_step(t_start, h, start, end, t_s)
