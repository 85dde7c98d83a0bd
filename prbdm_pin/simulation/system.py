"""The assembled equations of motion of a PRBDM: mass, springs, damping and the tip force.

    M(q) a + h(q, v) + K q + C v = J(q)^T F(t)

with h the Coriolis/centrifugal terms and the weight (gravity, when given), K the diagonal
joint stiffness (constant or a ``StiffnessSchedule``), C a damping matrix
(``prbdm_pin.simulation.damping``) and J the world-aligned linear Jacobian of the tip point.

Damping: ``damping="modal"`` (default), ``"eq5c"`` (the paper's Eq. 5c), ``"stiffness"``
(C = beta K, beta = 2 xi_1 / omega_1: what the MJCF and URDF exports carry as joint damping) or
``"modal_fit"`` (the diagonal joint damping fitted to per-mode ratios, ``.modal_fit``: what
they carry for a calibrated model; fitted at ``damping_pose``, the straight pose for theirs). C
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

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np
import pinocchio as pin

from ..chain import planar
from ..chain.pin_dynamics import planar_lengths
from ..errors import BeamInputError
from .damping import damping_matrix
from .hub_damping import plant_damping
from .inputs import InputForce
from .schedule import StiffnessSchedule


def vector(name: str, value, n: int) -> np.ndarray:
    """Return ``value`` as a fresh array of ``n`` finite numbers (zeros when None).

    Raises BeamInputError naming ``name`` otherwise.
    """
    if value is None:
        return np.zeros(n)
    try:
        a = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise BeamInputError(f"{name} = {value!r}: must be {n} numbers") from None
    if a.size != n or not np.all(np.isfinite(a)):
        raise BeamInputError(f"{name} = {value!r}: must be {n} finite numbers")
    return a.copy()


def force_function(tip_force) -> tuple[Callable[[float], np.ndarray] | None, bool]:
    """Return the tip force (N) as a function of time (s) and whether it is constant.

    The function is None when the force is absent or zero.
    """
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
    f = vector("tip_force", tip_force, 3)
    if not np.any(f):
        return None, True
    return (lambda t: f), True


def static_angle_rad(tau_Nm: np.ndarray | None, springs_Nm_per_rad: np.ndarray) -> float:
    """Return the largest joint angle the springs would yield to ``tau_Nm`` statically, rad.

    0 without a torque; a coordinate without a spring (the hub) is left out.
    """
    if tau_Nm is None:
        return 0.0
    k = np.asarray(springs_Nm_per_rad, dtype=float)
    sprung = k > 0.0
    return float(np.max(np.abs(tau_Nm[sprung] / k[sprung]), initial=0.0))


def symmetrised(upper: np.ndarray) -> np.ndarray:
    """Return the symmetric matrix whose upper triangle is ``upper``'s (Pinocchio fills it)."""
    return np.triu(upper) + np.triu(upper, 1).T


def mass_matrix(pm: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q) (n, n), kg m^2, by CRBA in the workspace ``data``."""
    return symmetrised(pin.crba(pm, data, q))


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
        e[i] = 0.5 * v @ mass_matrix(pm, data, q) @ v + 0.5 * np.sum(k * q * q)
    return e if np.ndim(q_rad) == 2 else e[0]


@dataclass(frozen=True, eq=False)
class System:
    """The equations of motion an integrator steps, with the workspace it evaluates them in.

    Attributes
    ----------
    pin_model : pin.Model
        The chain.
    data : pin.Data
        Pinocchio workspace of ``pin_model``, written by every evaluation (one per run).
    tip_frame_id : int
        Frame of the tip point the force acts on.
    lengths_m : ndarray (n + 1,) or None
        Base offset and link lengths of a planar chain (closed-form tip kinematics), m; None when
        the chain is not planar.
    stiffness_Nm_per_rad : ndarray (n,)
        The model's constant joint stiffness, N m/rad.
    schedule : callable q -> (n,) or None
        Pose-dependent joint stiffness, N m/rad; None for the constant springs.
    damping_Nms_per_rad : ndarray (n, n) or None
        Damping matrix C, N m s/rad; None when undamped.
    tip_force_N : callable t -> (3,) or None
        World-frame tip force, N, of time, s; None when there is none.
    constant_force : bool
        Whether ``tip_force_N`` is constant in time.
    inputs : InputForce or None
        The plant inputs (torques, strain actuators, hub torque, tip forces) and what drives
        them; None without inputs.
    """

    pin_model: pin.Model
    data: pin.Data
    tip_frame_id: int
    lengths_m: np.ndarray | None
    stiffness_Nm_per_rad: np.ndarray
    schedule: Callable[[np.ndarray], np.ndarray] | None
    damping_Nms_per_rad: np.ndarray | None
    tip_force_N: Callable[[float], np.ndarray] | None
    constant_force: bool
    inputs: InputForce | None = None

    def springs(self, q: np.ndarray) -> np.ndarray:
        """Joint stiffness (n,) at pose ``q`` (rad), N m/rad."""
        return self.stiffness_Nm_per_rad if self.schedule is None else self.schedule(q)

    def tau_external(self, q: np.ndarray, t: float, v: np.ndarray | None = None
                     ) -> np.ndarray | None:
        """Return the generalised force of the tip force and the inputs at (q rad, v rad/s).

        J(q)^T F(t) plus the inputs' force, (nv,), N m, by Pinocchio's frame Jacobian; None
        when there is none.
        """
        out = None
        if self.tip_force_N is not None:
            J = pin.computeFrameJacobian(self.pin_model, self.data, q, self.tip_frame_id,
                                         pin.LOCAL_WORLD_ALIGNED)
            # the binding returns a one-joint chain's 6 x 1 Jacobian as a vector
            out = J.reshape(6, -1)[:3].T @ self.tip_force_N(t)
        if self.inputs is not None:
            tau = self.inputs.torque(t, q, np.zeros_like(q) if v is None else v)
            out = tau if out is None else out + tau
        return out


def assemble_system(model, q0: np.ndarray, *, damping_ratios: np.ndarray, damping: str,
                    schedule: StiffnessSchedule | None,
                    tip_force_N: Callable[[float], np.ndarray] | None, constant_force: bool,
                    damping_pose: np.ndarray | None,
                    inputs: Callable[[Callable], InputForce] | None = None,
                    gravity_m_s2: np.ndarray | None = None) -> System:
    """Assemble the system of ``model`` (``PrbdmModel``) in a fresh workspace.

    The damping matrix of the ratios ``damping_ratios`` (form ``damping``) frozen at
    ``damping_pose`` (rad, default the
    start pose ``q0``), the springs of ``schedule`` (default the model's) and the tip force
    ``tip_force_N`` (N, of time in s); ``inputs`` makes the plant inputs' force from the tip
    terms (q, F) -> (J^T F, d(J^T F)/dq) of this chain. ``gravity_m_s2`` (m/s^2, world) goes
    into a copy of the Pinocchio model, so every dynamics call (ABA, RNEA and their
    derivatives) carries the weight and its stiffness.
    """
    pm = model.pin_model
    if gravity_m_s2 is not None and np.any(gravity_m_s2):
        pm = pin.Model(pm)
        pm.gravity = pin.Motion(np.concatenate([np.asarray(gravity_m_s2, dtype=float),
                                                np.zeros(3)]))
    data = pm.createData()
    fid = int(model.tip_frame_id)
    # one spring per coordinate; a hub's is zero
    k_const = np.diag(model.stiffness_matrix()).copy()
    springs = None if schedule is None else schedule.at
    C = None
    if np.any(damping_ratios > 0.0):
        qc = q0 if damping_pose is None else vector("damping_pose", damping_pose, q0.size)
        if getattr(model, "n_free", model.hub is not None):  # a hub's or a bus's rigid modes
            C = plant_damping(model, mass_matrix(pm, data, qc), damping_ratios, damping)
        else:
            k_c = k_const if springs is None else springs(qc)
            C = damping_matrix(mass_matrix(pm, data, qc), np.diag(k_c), damping_ratios, damping)
    try:
        lengths = planar_lengths(pm, fid)
    except BeamInputError:
        lengths = None
    forces = None
    if inputs is not None:
        forces = inputs(generalised_force(pm, data, fid, lengths)[2])
    return System(pm, data, fid, lengths, k_const, springs, C, tip_force_N, constant_force,
                  forces)


def weight_angle_rad(system: System, q: np.ndarray) -> float:
    """Return the largest joint angle the springs would yield to the weight at ``q``, rad.

    0 without gravity: what sets the scale of a motion that starts at rest under gravity.
    """
    if not np.any(system.pin_model.gravity.linear):
        return 0.0
    g = pin.computeGeneralizedGravity(system.pin_model, system.data, q)
    return static_angle_rad(g, system.springs(q))


def tip_positions(model, data: pin.Data, Q: np.ndarray, lengths: np.ndarray | None
                  ) -> np.ndarray:
    """Return the tip positions (s, 3), m, at the output samples only.

    Closed form for a planar chain (``lengths``, m; None otherwise).
    """
    pm, fid = model.pin_model, int(model.tip_frame_id)
    tip = np.empty((len(Q), 3))
    if lengths is not None:
        return planar.tip_positions(lengths, Q)
    for i, q in enumerate(Q):
        pin.framesForwardKinematics(pm, data, q)
        tip[i] = data.oMf[fid].translation
    return tip


def generalised_force(pm, data, fid, lengths):
    """Return tau_ext(q, f) = J(q)^T f, its derivative, and a function returning both.

    The derivative d tau_ext / dq is the load stiffness.

    Closed form for the planar chain (link i at world angle phi_i = q_1 + ... + q_i); Pinocchio's
    frame Jacobian and forward differences otherwise.
    """
    if lengths is not None:
        return (partial(planar.generalised_force, lengths),
                partial(planar.load_stiffness, lengths),
                partial(planar.force_and_load_stiffness, lengths))

    lwa = pin.LOCAL_WORLD_ALIGNED

    def tau_ext(q, f):
        return pin.computeFrameJacobian(pm, data, q, fid, lwa).reshape(6, -1)[:3].T @ f

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
