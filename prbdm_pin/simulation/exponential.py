"""Exponential Rosenbrock integrator exprb32 with step-size control (``Exponential``).

``Exponential()`` (``method="exponential"``; the default ``Auto()`` picks it or the compiled
DOP853 per problem, ``simulation.default_rule``): the exponential Rosenbrock method
exprb32 (Hochbruck, Ostermann & Schweitzer 2009) with step-size control; nominal (largest) step
``dt_s`` (default: lowest natural period at ``q0`` / 10). The dynamics y' = F(t, y),
y = (q, v), are linearised, F ~ F_n + J (y - y_n) + b (t - t_n), with J from
``pin.computeABADerivatives`` plus the springs, the damping and the load stiffness (closed form
for the planar chain). That linear system is propagated exactly, mode by mode, through
the eigen-decomposition of J (phi functions of h lambda): every linear mode, however stiff,
keeps its exact frequency and damping. The nonlinear remainder is evaluated once, at the
predicted end point, and enters as a forcing that grows quadratically over the step (third
order). Two dynamics evaluations per step; the eigen-decomposition is rebuilt only when a
joint angle has moved by more than ``refresh_rad`` (0.01 rad) since the last one (in between,
the Jacobian's change enters as a linearly growing forcing). Output at ``output_dt`` uses the
method's own continuous extension (exact for the linear part).
Step control: the remainder's quadratic model holds only while the remainder varies slowly
over a step. When the motion carries higher modes at a finite amplitude (a release from a bent
pose that is not a mode-1 shape), the remainder oscillates at their frequencies, h omega_k is
well above 1 at the nominal step, and a fixed step would be far off. The correction term
2 h phi_3(h J) D (exprb32 minus its embedded second-order scheme), measured mode by mode as
the joint-angle amplitude it would oscillate with (a stiff mode's velocity error shows in q
only later), is kept below ``step_rtol`` (3e-4) of the motion's scale (the largest joint angle
so far): a step over ``reject_factor`` (3) times that is redone shorter, the next step follows
the usual (tol / err)^(1/3) rule, never longer than the nominal step (nor shorter than
``min_step_ratio``, 1e-3, of it). Motion the nominal step resolves (linear, or mode-1-like)
keeps the equal nominal steps. A step whose correction exceeds ``divergence_tol`` (5 %) of the
larger of the motion's scale and the step's travel (or is not finite) is halved, up to
``max_halvings`` (6) times in a row (a guard against divergence); the fields are those of
:class:`~prbdm_pin.options.integrators.Exponential`. Its accuracy against DOP853, steps and
cost are measured by ``scripts/bench_exponential_release.py`` and ``scripts/bench_simulate.py``
(the benchmarks page).
``Exponential(order=4)`` takes exprb43 instead (``exponential_rb43``, which says why).
Limits: it is not symplectic. Linear motion keeps its energy exactly, but undamped nonlinear
motion drifts, the more the larger the amplitude: use ``"gauss"`` for long undamped runs at
large amplitude. With a ``stiffness_schedule`` the Jacobian leaves out dK/dq (the remainder
carries it). A time-varying force needs ``dt`` well below its shortest period: the step
control does not see the force's variation ahead of the step.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import SolveError
from ..options.integrators import Exponential
from .exponential_linear import continuous_extension, eig_with_inverse, soft_springs
from .exponential_rb43 import rb43_phis, rb43_step
from .phi import phi123
from .steps import equal_steps
from .system import System, generalised_force, static_angle_rad, symmetrised, weight_angle_rad


class ExponentialStepper:
    """exprb32 steps of at most a nominal step, step controlled (the stepper of ``Exponential``).

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
    (``step_rtol``, ``reject_factor``), capped at the nominal step. A step whose correction is
    large (``divergence_tol``) or not finite is halved, up to ``max_halvings`` times in a row.

    Parameters
    ----------
    settings : Exponential
    system : System
    t0, t_bound : float
        Start and end time, s.
    y0 : ndarray, shape (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    dt_s : float
        Nominal (largest) step, s; shortened to divide the run into equal steps.
    max_steps : int
        Refuse a nominal step that would take more steps (BeamInputError).
    """

    def __init__(self, settings: Exponential, system: System, t0: float, y0: np.ndarray,
                 t_bound: float, *, dt_s: float, max_steps: int):
        self.settings = settings
        self.system = system
        pm, data = system.pin_model, system.data
        n = y0.size // 2
        q0, v0 = y0[:n], y0[n:]
        k_const, stiffness = system.stiffness_Nm_per_rad, system.schedule
        force = system.tip_force_N
        duration = t_bound - t0
        self.n, self.t_bound = n, t_bound
        self.h0 = h0 = duration / equal_steps(duration, dt_s, max_steps)
        self._tau_ext, _, self._tau_and_load_stiffness = generalised_force(
            pm, data, system.tip_frame_id, system.lengths_m)
        self._Jm = np.zeros((2 * n, 2 * n))
        self._Jm[:n, n:] = np.eye(n)
        const_spring = -np.diag(k_const) if stiffness is None else None
        # the Jacobian's stiffness carries a weak spring on a coordinate that has none (the hub)
        soft = soft_springs(pm, data, q0, k_const)
        if soft is not None and const_spring is not None:
            const_spring = const_spring - np.diag(soft)
        self._const_spring = const_spring
        self._minus_C = None if system.damping_Nms_per_rad is None \
            else -system.damping_Nms_per_rad
        self._varying = force is not None and not system.constant_force
        self._f_const = force(0.0) if force is not None else None
        self._half_minv = None
        # the motion's scale: largest joint angle so far, at least the static deflection angle
        # of the initial force and the first step's travel (over the sprung coordinates: a
        # hub's rigid rotation is large, propagated exactly, and would loosen the tolerance of
        # the panel's bending), with a nanoradian floor as Gauss's and the trapezoidal rule's: a
        # rigid spin of a hub or a free bus with the member straight bends it by nothing but
        # roundings, and a tolerance relative to a 1e-300 scale chased those past max_steps
        self._flex = k_const > 0.0
        flex = self._flex
        scale = max(float(np.abs(q0[flex]).max()), float(np.abs(v0[flex]).max()) * h0, 1e-9)
        springs0 = k_const if stiffness is None else stiffness(q0)
        if force is not None:
            scale = max(scale, static_angle_rad(self._tau_ext(q0, force(0.0)), springs0))
        if system.inputs is not None:
            scale = max(scale, static_angle_rad(system.inputs.torque(0.0, q0, v0), springs0))
        self._scale = max(scale, weight_angle_rad(system, q0))
        # the decomposition of the last Jacobian and the phi functions of its step
        self._lin_q = None
        self._phi_h = None
        self.t = self.t_old = t0
        self.y = y0.copy()
        self._h = h0
        self._halvings = 0
        self._rejected = False
        self._record = None
        self.done = not t_bound - t0 > 1e-9 * h0
        self.steps = self.rhs_evaluations = self.jacobian_updates = 0

    def _torque(self, t, q, v, f):
        sy = self.system
        tau = -(sy.stiffness_Nm_per_rad if sy.schedule is None else sy.schedule(q)) * q
        if sy.damping_Nms_per_rad is not None:
            tau -= sy.damping_Nms_per_rad @ v
        if f is not None:
            tau += self._tau_ext(q, f)
        if sy.inputs is not None:
            tau += sy.inputs.torque(t, q, v)
        return tau

    def _attempt(self, t, y, h):
        """Take one exprb32 step of length h from (t, y).

        Returns the end state, the correction's size in q, its reference (the guard's), its
        modal amplitude and the dense-output record.
        """
        sy, n, Jm = self.system, self.n, self._Jm
        pm, data = sy.pin_model, sy.data
        k_const, stiffness, inputs = sy.stiffness_Nm_per_rad, sy.schedule, sy.inputs
        force = sy.tip_force_N
        q, v = y[:n], y[n:]
        f = force(t) if self._varying else self._f_const
        tau = -(k_const if stiffness is None else stiffness(q)) * q
        if sy.damping_Nms_per_rad is not None:
            tau -= sy.damping_Nms_per_rad @ v
        Kt = self._const_spring if stiffness is None else -np.diag(stiffness(q))
        if f is not None:
            tau_f, k_f = self._tau_and_load_stiffness(q, f)
            tau += tau_f
            Kt = Kt + k_f
        Dt = self._minus_C
        if inputs is not None:
            tau += inputs.torque(t, q, v)
            k_u, c_u = inputs.jacobians(t, q, v)
            if k_u is not None:
                Kt = Kt + k_u
            if c_u is not None:
                Dt = c_u if Dt is None else Dt + c_u
        dadq, dadv, Minv = pin.computeABADerivatives(pm, data, q, v, tau)
        self.rhs_evaluations += 1
        if self._half_minv is None:
            # some Pinocchio versions fill only the upper triangle of M^-1
            self._half_minv = n > 1 and not np.any(np.tril(Minv, -1))
        if self._half_minv:
            Minv = symmetrised(Minv)
        Fn = np.concatenate((v, data.ddq))
        Jm[n:, :n] = dadq + Minv @ Kt
        Jm[n:, n:] = dadv if Dt is None else dadv + Minv @ Dt
        if self._lin_q is None or np.abs(q - self._lin_q).max() > self.settings.refresh_rad:
            self._lam, self._V, self._Vinv = eig_with_inverse(Jm, t)
            self._J = Jm.copy()
            # the largest joint angle each mode's unit coordinate swings through
            self._vq = np.abs(self._V[:n]).max(axis=0)
            self._lin_q = q.copy()
            self._phi_h = None
            self.jacobian_updates += 1
            b = np.zeros(2 * n)
        else:
            # the Jacobian's change since the decomposition acts like a forcing that grows
            # linearly over the step, (J_n - J) (y - y_n) ~ (J_n - J) F_n s
            b = (Jm - self._J) @ Fn
        lam, Vc, Vinv, J = self._lam, self._V, self._Vinv, self._J
        rb43 = self.settings.order == 4
        if self._phi_h != h:
            if rb43:
                self._phi = rb43_phis(h, lam)
            else:
                hp1, hhp2, hp3 = phi123(h * lam)
                self._phi = (h * hp1, h * h * hhp2, 2.0 * h * hp3)
            self._phi_h = h
        if self._varying:
            # the force's rate by a short forward difference (no evaluation before t = 0)
            delta = 1e-6 * h
            b[n:] += Minv @ self._tau_ext(q, (force(t + delta) - f) / delta)
        rate = None if inputs is None else inputs.time_rate(t, q, v)
        if rate is not None:
            b[n:] += Minv @ rate
        if rb43:
            def remainder(c, U):
                qU, vU = U[:n], U[n:]
                tc = t + c * h
                aU = pin.aba(pm, data, qU, vU,
                             self._torque(tc, qU, vU, force(tc) if self._varying else f))
                self.rhs_evaluations += 1
                return np.concatenate((vU - Fn[:n], aU - Fn[n:])) - J @ (U - y) - c * h * b

            y1, err, ze, record = rb43_step(y, t, h, lam, Vc, Vinv, Fn, b, self._phi, remainder)
            ref = max(self._scale, float(np.abs(y1[:n] - q).max()))
            return y1, float(np.abs(err[:n]).max()), ref, float(self._vq @ np.abs(ze)), record
        hp1, hhp2, hp3 = self._phi
        c1 = Vinv @ Fn
        cb = Vinv @ b
        U = y + (Vc @ (hp1 * c1 + hhp2 * cb)).real
        qU, vU = U[:n], U[n:]
        aU = pin.aba(pm, data, qU, vU,
                     self._torque(t + h, qU, vU, force(t + h) if self._varying else f))
        self.rhs_evaluations += 1
        D = np.concatenate((vU - Fn[:n], aU - Fn[n:])) - J @ (U - y) - h * b
        cd = Vinv @ D
        zc = hp3 * cd
        corr = (Vc @ zc).real
        size = float(np.abs(corr[:n]).max())
        ref = max(self._scale, float(np.abs(U[:n] - q).max()))
        # the correction's modal content as the joint-angle amplitude it would oscillate with:
        # a velocity error of a stiff mode shows in q only later, over its oscillation
        amp = float(self._vq @ np.abs(zc))
        return U + corr, size, ref, amp, (t, h, lam, Vc, c1, cd, cb)

    def step(self) -> None:
        """Take one accepted step (redoing rejected and diverging trials).

        Step control: the correction 2 h phi_3(h J) D is the difference between exprb32 and
        its embedded second-order scheme, an upper estimate of the local error. The step never
        exceeds the nominal step h0, so motion the scheme resolves at h0 (linear, or
        mode-1-like) keeps the equal steps h0.
        """
        st, h0 = self.settings, self.h0
        t, y, h = self.t, self.y, self._h
        # a diverging trial step is detected and halved: no overflow warnings for it
        with np.errstate(over="ignore", invalid="ignore"):
            while True:
                left = self.t_bound - t
                if h >= left * (1.0 - 1e-9):
                    h = left
                elif h > 0.5 * left:
                    h = 0.5 * left  # no sliver of a last step
                y1, size, ref, amp, record = self._attempt(t, y, h)
                if not (size <= st.divergence_tol * ref):  # also catches NaN
                    # the divergence guard: halve the step, at most max_halvings times in a row
                    if self._halvings >= st.max_halvings:
                        raise SolveError(f"exponential integrator: no acceptable step at "
                                         f"t = {t:.6g} s after {self._halvings} halvings "
                                         f"(dt = {h:.3g} s); try method='gauss' or a smaller dt")
                    self._halvings += 1
                    h *= 0.5
                    continue
                self._halvings = 0
                err = amp / (st.step_rtol * self._scale)
                if err > st.reject_factor and h > h0 * st.min_step_ratio:
                    h = max(h * max(0.2, 0.9 * err ** (-1.0 / st.order)), h0 * st.min_step_ratio)
                    self._rejected = True
                    continue
                break
        self._scale = max(self._scale, float(np.abs(y1[:self.n][self._flex]).max()))
        self.steps += 1
        self._record = record
        self._y_start, self.t_old, self.y = y, t, y1
        self.t = t + h
        self.done = not self.t_bound - self.t > 1e-9 * h0
        if self.done:
            self.t = self.t_bound  # the last node is the end itself, not its rounding
        # the estimate is of order h^order (exprb32's embedded second-order step, exprb43's
        # third-order one)
        p = st.order
        grow = 2.0 if err <= (0.9 / 2.0) ** p else 0.9 * err ** (-1.0 / p)
        if self._rejected:
            grow = min(grow, 1.0)  # no growth right after a rejection (Hairer & Wanner)
            self._rejected = False
        self._h = min(h0, h * grow)

    def dense_output(self):
        """Return the last step's continuous extension: times (m,) s -> states (m, 2n)."""
        y_start, record = self._y_start, self._record
        return lambda t_s: continuous_extension(y_start, record, t_s)
