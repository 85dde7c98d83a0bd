"""Exponential Rosenbrock integrator exprb32 with step-size control (``method="exponential"``).

``"exponential"`` (default): the exponential Rosenbrock method exprb32 (Hochbruck, Ostermann
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
over a step. When the motion carries higher modes at a finite amplitude (a release from a bent
pose that is not a mode-1 shape), the remainder oscillates at their frequencies, h omega_k is
well above 1 at the nominal step, and a fixed step would be far off. The correction term
2 h phi_3(h J) D (exprb32 minus its embedded second-order scheme), measured mode by mode as
the joint-angle amplitude it would oscillate with (a stiff mode's velocity error shows in q
only later), is kept below ``_STEP_RTOL`` of the motion's scale (the largest joint angle so
far): a step over three times that is redone shorter, the next step follows the usual
(tol / err)^(1/3) rule, never longer than the nominal step (nor shorter than 1e-3 of it).
Motion the nominal step resolves (linear, or mode-1-like) keeps the equal nominal steps. A
step whose correction exceeds 5 % of the larger of the motion's scale and the step's travel
(or is not finite) is halved, up to 6 times in a row (a guard against divergence). Its
accuracy against DOP853, steps and cost are measured by ``scripts/bench_exponential_release.py``
and ``scripts/bench_simulate.py`` (the benchmarks page).
Limits: it is not symplectic. Linear motion keeps its energy exactly, but undamped nonlinear
motion drifts, the more the larger the amplitude: use ``"gauss"`` for long undamped runs at
large amplitude. With a ``stiffness_schedule`` the Jacobian leaves out dK/dq (the remainder
carries it). A time-varying force needs ``dt`` well below its shortest period: the step
control does not see the force's variation ahead of the step.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import scipy.linalg

from ..errors import BeamInputError, SolveError
from .phi import phi123
from .steps import Samples, StepSettings, equal_steps, output_times
from .system import System, generalised_force, static_angle_rad, symmetrised


def _eig_with_inverse(J: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues lam, eigenvectors V and V^-1 of a real matrix; SolveError when defective."""
    try:
        lam, V = np.linalg.eig(J)
        return lam, V, np.linalg.inv(V)
    except np.linalg.LinAlgError:
        raise SolveError(f"exponential integrator: defective or non-finite Jacobian at "
                         f"t = {t:.6g} s") from None


# a step whose correction 2 h phi_3(h J) D exceeds this fraction of the motion's scale (the
# largest joint angle so far) is halved (the divergence guard)
_LOCAL_TOL = 0.05
MAX_HALVINGS = 6
# step control: the correction's modal amplitude is kept near this fraction of the motion's
# scale; a step over REJECT_FACTOR times it is redone shorter (never below _MIN_STEP times the
# nominal step). 3e-4 keeps releases within 0.1 % of the peak over 1 s; rejecting only above 3x
# (the next step shrinks anyway) saves the rejected steps' evaluations on step loads.
_STEP_RTOL = 3e-4
# a coordinate without a spring gets one in the Jacobian at this fraction of the lowest
# flexible frequency (see _soft_springs)
_SOFT_RATIO = 1e-3
_MIN_STEP = 1e-3
REJECT_FACTOR = 3.0


def integrate(system: System, q0: np.ndarray, v0: np.ndarray, settings: StepSettings
              ) -> Samples:
    """Integrate with step-controlled exprb32 steps of at most ``settings.dt_s`` (s).

    From (q0 rad, v0 rad/s) over ``settings.duration_s``; samples every step, or the continuous
    extension every ``output_dt_s``.
    """
    # a diverging trial step is detected and halved: no overflow warnings for it
    with np.errstate(over="ignore", invalid="ignore"):
        return _run(system, q0, v0, settings)


def _run(system: System, q0: np.ndarray, v0: np.ndarray, settings: StepSettings) -> Samples:
    """Exponential Rosenbrock method exprb32, step controlled, nominal step ``dt``.

    The method is that of Hochbruck, Ostermann & Schweitzer (2009).

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
    (``_STEP_RTOL``, ``REJECT_FACTOR``), capped at the nominal step. A step whose correction is
    large (``_LOCAL_TOL``) or not finite is halved, up to ``MAX_HALVINGS`` times in a row.
    """
    pm, data = system.pin_model, system.data
    k_const, stiffness = system.stiffness_Nm_per_rad, system.schedule
    C, force = system.damping_Nms_per_rad, system.tip_force_N
    inputs = system.inputs
    duration, output_dt = settings.duration_s, settings.output_dt_s
    max_steps, refresh_rad = settings.max_steps, settings.refresh_rad
    n = q0.size
    h0 = duration / equal_steps(duration, settings.dt_s, max_steps)
    n2 = 2 * n
    tau_ext, _, tau_and_load_stiffness = generalised_force(pm, data, system.tip_frame_id,
                                                           system.lengths_m)
    Jm = np.zeros((n2, n2))
    Jm[:n, n:] = np.eye(n)
    const_spring = -np.diag(k_const) if stiffness is None else None
    # the Jacobian's stiffness carries a weak spring on a coordinate that has none (the hub)
    soft = _soft_springs(pm, data, q0, k_const)
    if soft is not None and const_spring is not None:
        const_spring = const_spring - np.diag(soft)
    minus_C = None if C is None else -C
    aba, aba_derivatives = pin.aba, pin.computeABADerivatives
    varying = force is not None and not system.constant_force
    f_const = force(0.0) if force is not None else None
    half_minv = None
    # step records for the dense output: start time, step, start state, decomposition, coefs
    records = []
    counts = {"fev": 0, "decomp": 0, "steps": 0}
    # the motion's scale: largest joint angle so far, at least the static deflection angle of the
    # initial force and the first step's travel
    # (over the sprung coordinates: a hub's rigid rotation is large, propagated exactly, and
    # would loosen the tolerance of the panel's bending)
    flex = k_const > 0.0
    scale = [max(float(np.abs(q0[flex]).max()), float(np.abs(v0[flex]).max()) * h0, 1e-300)]
    springs0 = k_const if stiffness is None else stiffness(q0)
    if force is not None:
        scale[0] = max(scale[0], static_angle_rad(tau_ext(q0, force(0.0)), springs0))
    if inputs is not None:
        scale[0] = max(scale[0], static_angle_rad(inputs.torque(0.0, q0, v0), springs0))

    def torque(t, q, v, f):
        tau = -(k_const if stiffness is None else stiffness(q)) * q
        if C is not None:
            tau -= C @ v
        if f is not None:
            tau += tau_ext(q, f)
        if inputs is not None:
            tau += inputs.torque(t, q, v)
        return tau

    # the decomposition of the last Jacobian and the phi functions of its step
    cache = {"q": None, "h": None}

    def attempt(t, y, h):
        """Take one exprb32 step of length h from (t, y).

        Returns the end state, the correction's size in q, its reference (the guard's) and the
        dense-output record.
        """
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
        Dt = minus_C
        if inputs is not None:
            tau += inputs.torque(t, q, v)
            k_u, c_u = inputs.jacobians(t, q, v)
            if k_u is not None:
                Kt = Kt + k_u
            if c_u is not None:
                Dt = c_u if Dt is None else Dt + c_u
        dadq, dadv, Minv = aba_derivatives(pm, data, q, v, tau)
        counts["fev"] += 1
        if half_minv is None:
            # some Pinocchio versions fill only the upper triangle of M^-1
            half_minv = n > 1 and not np.any(np.tril(Minv, -1))
        if half_minv:
            Minv = symmetrised(Minv)
        Fn = np.concatenate((v, data.ddq))
        Jm[n:, :n] = dadq + Minv @ Kt
        Jm[n:, n:] = dadv if Dt is None else dadv + Minv @ Dt
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
            hp1, hhp2, hp3 = phi123(h * lam)
            cache["phi"] = (h * hp1, h * h * hhp2, 2.0 * h * hp3)
            cache["h"] = h
        hp1, hhp2, hp3 = cache["phi"]
        if varying:
            # the force's rate by a short forward difference (no evaluation before t = 0)
            delta = 1e-6 * h
            b[n:] += Minv @ tau_ext(q, (force(t + delta) - f) / delta)
        rate = None if inputs is None else inputs.time_rate(t, q, v)
        if rate is not None:
            b[n:] += Minv @ rate
        c1 = Vinv @ Fn
        cb = Vinv @ b
        U = y + (Vc @ (hp1 * c1 + hhp2 * cb)).real
        qU, vU = U[:n], U[n:]
        aU = aba(pm, data, qU, vU, torque(t + h, qU, vU, force(t + h) if varying else f))
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
        scale[0] = max(scale[0], float(np.abs(y1[:n][flex]).max()))
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
        if not (size <= _LOCAL_TOL * ref):  # also catches NaN
            # the divergence guard: halve the step, at most MAX_HALVINGS times in a row
            if halvings >= MAX_HALVINGS:
                raise SolveError(f"exponential integrator: no acceptable step at "
                                 f"t = {t:.6g} s after {halvings} halvings (dt = {h:.3g} s); "
                                 "try method='gauss' or a smaller dt")
            halvings += 1
            h *= 0.5
            continue
        halvings = 0
        err = amp / (_STEP_RTOL * scale[0])
        if err > REJECT_FACTOR and h > h0 * _MIN_STEP:
            h = max(h * max(0.2, 0.9 * err ** (-1.0 / 3.0)), h0 * _MIN_STEP)
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
    if output_dt is not None:
        t_nodes, Y = _continuous_extension(t_nodes, Y, records, duration, output_dt)
    return Samples(t_nodes, Y[:, :n].copy(), Y[:, n:].copy(), counts["steps"], counts["fev"],
                   counts["decomp"])


def _soft_springs(pm, data, q0: np.ndarray, k_const: np.ndarray) -> np.ndarray | None:
    """Return soft springs (N m/rad) for the coordinates without a spring, for the Jacobian.

    They put each coordinate without a spring (a hub) at ``_SOFT_RATIO`` times the lowest
    flexible frequency; None when every coordinate has a spring.

    A free coordinate with no damping makes the Jacobian defective (a Jordan block at 0: the
    rigid rotation's angle grows with its rate), and an eigen-decomposition of it is
    meaningless. With the soft spring the rigid mode becomes a slow oscillation with distinct
    eigenvalues; the dynamics themselves keep no spring: the difference, -k_soft q, is part
    of the remainder the method evaluates at every step, and its effect shrinks with
    (omega_soft h)^2.
    """
    free = k_const == 0.0
    if not np.any(free):
        return None
    M = symmetrised(pin.crba(pm, data, q0))
    sprung = ~free
    w2 = scipy.linalg.eigh(np.diag(k_const[sprung]), _schur(M, free), eigvals_only=True)
    soft = np.zeros_like(k_const)
    soft[free] = (_SOFT_RATIO ** 2 * float(w2[0])) * np.diag(M)[free]
    return soft


def _schur(M: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Return the sprung coordinates' mass with the free ones left to move, kg m^2."""
    a, b = M[np.ix_(~free, ~free)], M[np.ix_(~free, free)]
    return a - b @ np.linalg.solve(M[np.ix_(free, free)], b.T)


def _continuous_extension(t_nodes: np.ndarray, Y: np.ndarray, records: list, duration: float,
                          output_dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Return sample times every ``output_dt`` (s) and the states (q, v) there.

    Each step's formula with h replaced by the offset from its start (exact for the linear
    part).
    """
    t_out = output_times(duration, output_dt)
    starts = t_nodes[:-1]
    idx = np.clip(np.searchsorted(starts, t_out, side="right") - 1, 0, len(starts) - 1)
    hs = np.array([r[1] for r in records])[idx][:, None]
    s_col = np.minimum(t_out - starts[idx], hs[:, 0])[:, None]
    lam = np.array([r[2] for r in records])[idx]
    Vs = np.array([r[3] for r in records])[idx]
    C_all = np.array([r[4:] for r in records])[idx]
    p1, p2, p3 = phi123(s_col * lam)
    coef = (s_col * p1 * C_all[:, 0] + (2.0 * s_col**3 / hs**2) * p3 * C_all[:, 1]
            + s_col**2 * p2 * C_all[:, 2])
    return t_out, Y[idx] + np.einsum("sij,sj->si", Vs, coef).real
