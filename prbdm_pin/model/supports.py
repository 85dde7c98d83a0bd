"""Supports other than the clamp and the hub: a free-floating bus, and the six-coordinate base.

A :class:`FreeBus` is a rigid body (a spacecraft bus) the beam's root is clamped to, floating
freely: momentum is shared between the bus and the member. Its Pinocchio model is the clamped
chain appended (``pinocchio.appendModel``) to a *six-coordinate base*: six 1-DOF joints in
series, ``bus_x``, ``bus_y``, ``bus_z`` (prismatic along world x, y, z) then ``bus_yaw``,
``bus_pitch``, ``bus_roll`` (revolute about z, y, x), the bus body on the last. The bus
orientation is R = Rz(yaw) Ry(pitch) Rx(roll) (roll-pitch-yaw, ZYX Euler angles).

Why six 1-DOF joints and not Pinocchio's free-flyer: the free-flyer has nq = 7 != nv = 6
(a quaternion), and every integrator of the package steps q with v (nq == nv). The six joints
keep nq == nv with v = dq/dt exactly, so the integrators, Pinocchio's ABA/RNEA derivatives and
the linearisation apply unchanged. Pinocchio's ``JointModelSphericalZYX`` would do the same in
one joint, but its ABA derivatives (Pinocchio 4.1) disagree with central differences of its own
ABA; the six 1-DOF joints agree to the differences' truncation. The price is the Euler angles'
singularity: at pitch = +/- pi/2 yaw and roll turn about the same axis and the mass matrix is
singular. A bus that tumbles that far needs a quaternion base; the models here are for small
attitude motions (pointing, slews well below 90 degrees in pitch).

With no body on the base (``bus=None``) the same six coordinates carry a prescribed base motion
(:mod:`prbdm_pin.simulation.base_motion`).

Coordinates: q = [x, y, z, yaw, pitch, roll, q_member...] (m, rad); the member's joints follow
in the clamped chain's order. The member's kinematics relative to the bus are the clamped
chain's: a member output of a bus model (``tip_z``, ``q[j]``...) is measured in the clamp frame
(the bus frame moved to ``root_m``), as on the clamped model.

Frequencies and modes: the six base coordinates have no spring, so the chain has six rigid
modes (omega = 0 exactly) and n flexible ones from the Schur complement
S = M_ff - M_fr M_rr^-1 M_rf (the member's mass with the base free), K_f phi_f = omega^2 S phi_f;
the base part of a flexible mode is phi_r = -M_rr^-1 M_rf phi_f (zero momentum), as
:mod:`prbdm_pin.model.hub` does for the hub's one rigid coordinate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..chain.eigen import eig_scaled, modes_from_mass
from ..errors import BeamInputError
from ..options.checks import check_float
from ..options.validate import real_vector

__all__ = ["FreeBus", "BASE_JOINTS", "N_BASE", "base_chain", "free_schur", "free_frequencies",
           "free_modes", "free_modes_of", "euler_rate_matrix"]

# the six base joints in series, in Pinocchio's order (q[0..5])
BASE_JOINTS = (("bus_x", pin.JointModelPX), ("bus_y", pin.JointModelPY),
               ("bus_z", pin.JointModelPZ), ("bus_yaw", pin.JointModelRZ),
               ("bus_pitch", pin.JointModelRY), ("bus_roll", pin.JointModelRX))
N_BASE = 6
BUS_FRAME = "bus"
# a symmetric matrix is taken as given when its asymmetry is at rounding level of its size
_SYMMETRY_RTOL = 1e-9


@dataclass(frozen=True)
class FreeBus:
    """A rigid bus floating freely, the beam's root clamped to it.

    Attributes
    ----------
    mass_kg : float
        Bus mass, kg (> 0; the member's mass is added by the chain).
    inertia_kg_m2 : tuple of 3 tuples of 3 floats
        Bus inertia tensor about its centre of mass, in the bus frame, kg m^2 (symmetric,
        positive definite); given as a 3 x 3 array or three principal moments (a diagonal
        tensor). Stored as tuples, so that buses compare and hash by value.
    com_m : tuple of 3 floats
        Bus centre of mass in the bus frame, m (default the frame's origin).
    root_m : tuple of 3 floats
        Where the beam's root is clamped, in the bus frame, m; the beam leaves along the bus
        frame's x axis (default the origin).

    The bus frame coincides with the world frame at q = 0.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> bus = pp.FreeBus(mass_kg=20.0, inertia_kg_m2=[1.0, 1.2, 0.8])
    >>> bus.mass_kg
    20.0
    """

    mass_kg: float
    inertia_kg_m2: np.ndarray
    com_m: np.ndarray = (0.0, 0.0, 0.0)
    root_m: np.ndarray = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        """Check the fields (BeamInputError naming the field; InputTypeError for non-numbers)."""
        m = check_float("FreeBus mass_kg", self.mass_kg, low=0.0, low_open=True, unit="kg")
        object.__setattr__(self, "mass_kg", m)
        object.__setattr__(self, "inertia_kg_m2", _inertia(self.inertia_kg_m2))
        for name in ("com_m", "root_m"):
            v = real_vector(f"FreeBus {name}", getattr(self, name), "m", 3)
            object.__setattr__(self, name, tuple(float(x) for x in v))

    def inertia(self) -> pin.Inertia:
        """Return the bus body as a Pinocchio inertia in the bus frame."""
        return pin.Inertia(self.mass_kg, np.array(self.com_m), np.array(self.inertia_kg_m2))


def _inertia(value) -> tuple[tuple[float, ...], ...]:
    """Return the bus inertia (symmetric positive definite, kg m^2) as 3 rows of 3 floats."""
    raw = np.asarray(value, dtype=object)
    if raw.shape == (3,):
        I = np.diag(real_vector("FreeBus inertia_kg_m2", value, "kg m^2", 3))
    elif raw.shape == (3, 3):
        I = real_vector("FreeBus inertia_kg_m2", raw.reshape(-1), "kg m^2", 9).reshape(3, 3)
    else:
        raise BeamInputError(f"FreeBus inertia_kg_m2 has shape {raw.shape}: must be 3 principal "
                             "moments or a 3 x 3 tensor (kg m^2)")
    scale = float(np.abs(I).max())
    if np.abs(I - I.T).max() > _SYMMETRY_RTOL * scale:
        raise BeamInputError(f"FreeBus inertia_kg_m2 = {I.tolist()}: must be symmetric (kg m^2)")
    I = 0.5 * (I + I.T)
    w = np.linalg.eigvalsh(I)
    if not w[0] > 0.0:
        raise BeamInputError(f"FreeBus inertia_kg_m2 = {I.tolist()}: must be positive definite "
                             f"(eigenvalues {w.tolist()} kg m^2)")
    return tuple(tuple(float(x) for x in row) for row in I)


def base_chain(chain: pin.Model, bus: FreeBus | None, name: str) -> pin.Model:
    """Return the clamped ``chain`` (its root at the world origin) on a six-coordinate base.

    ``bus`` gives the base its body and the root's place on it; None leaves the base massless
    with the root at its origin (a prescribed base motion). The chain's clamped link (the
    inertia on its universe) moves with the base. Gravity is the chain's.
    """
    base = pin.Model()
    base.name = name
    jid = 0
    for joint_name, joint in BASE_JOINTS:
        jid = base.addJoint(jid, joint(), pin.SE3.Identity(), joint_name)
    if bus is not None:
        base.appendBodyToJoint(jid, bus.inertia(), pin.SE3.Identity())
    fid = base.addBodyFrame(BUS_FRAME, jid, pin.SE3.Identity(), 0)
    root = np.zeros(3) if bus is None else np.array(bus.root_m)
    out = pin.appendModel(base, chain, fid, pin.SE3(np.eye(3), root))
    out.name = name
    out.gravity = chain.gravity
    return out


def free_schur(M: np.ndarray, n_free: int = N_BASE) -> np.ndarray:
    """Return S = M_ff - M_fr M_rr^-1 M_rf: the sprung coordinates' mass, the base free.

    The first ``n_free`` coordinates are free; ``M`` (nv, nv), kg m^2 (kg, kg m in the base
    rows).
    """
    Mrr, Mrf = M[:n_free, :n_free], M[:n_free, n_free:]
    S = M[n_free:, n_free:] - Mrf.T @ np.linalg.solve(Mrr, Mrf)
    return 0.5 * (S + S.T)


def free_frequencies(M: np.ndarray, stiffness_Nm_per_rad: np.ndarray, squared: bool = False,
                     n_free: int = N_BASE) -> np.ndarray:
    """Return the frequencies of a chain on a free base, rad/s ascending (omega^2 if squared).

    The ``n_free`` rigid modes' exact zeros first, then the flexible ones; ``M`` (nv, nv),
    springs (nv - n_free,), N m/rad.
    """
    s = 1.0 / np.sqrt(np.asarray(stiffness_Nm_per_rad, dtype=float))
    flex = eig_scaled(free_schur(np.asarray(M, dtype=float), n_free), s, squared)
    return np.concatenate([np.zeros(n_free), flex])


def free_modes(M: np.ndarray, stiffness_Nm_per_rad: np.ndarray, n_free: int = N_BASE
               ) -> tuple[np.ndarray, np.ndarray]:
    """Return the frequencies (rad/s, the rigid zeros first) and mass-normalised modes.

    The rigid modes move the base coordinates only (M_rr-orthonormal: the inverse of the
    Cholesky factor of M_rr); each flexible mode carries the base part that keeps its
    momentum zero. Modes as columns, shape (nv, nv).
    """
    M = np.asarray(M, dtype=float)
    omega_f, Phi_f = modes_from_mass(free_schur(M, n_free)[None], stiffness_Nm_per_rad)
    return np.concatenate([np.zeros(n_free), omega_f[0]]), free_modes_of(M, Phi_f[0], n_free)


def free_modes_of(M: np.ndarray, Phi_f: np.ndarray, n_free: int = N_BASE) -> np.ndarray:
    """Return all the modes (columns, (nv, nv)) from the flexible ones' member part ``Phi_f``.

    ``Phi_f`` (nv - n_free, nv - n_free) is S-orthonormal (S = :func:`free_schur`); the rigid
    modes are M_rr-orthonormal on the base, each flexible mode gets its base part
    -M_rr^-1 M_rf phi_f.
    """
    nv = M.shape[0]
    Phi = np.zeros((nv, nv))
    L = np.linalg.cholesky(M[:n_free, :n_free])
    Phi[:n_free, :n_free] = np.linalg.inv(L).T  # X^T M_rr X = I
    Phi[n_free:, n_free:] = Phi_f
    Phi[:n_free, n_free:] = -np.linalg.solve(M[:n_free, :n_free], M[:n_free, n_free:] @ Phi_f)
    return Phi


def bus_pose_rad(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the base position (m) and (roll, pitch, yaw) (rad) of coordinates ``q``."""
    q = np.asarray(q, dtype=float)
    return q[..., :3], q[..., [5, 4, 3]]


def euler_rate_matrix(roll_pitch_yaw_rad: np.ndarray) -> np.ndarray:
    """Return E with omega_body = E [roll', pitch', yaw']' for R = Rz(yaw) Ry(pitch) Rx(roll).

    Singular at pitch = +/- pi/2 (the Euler angles' singularity, see the module notes).
    """
    r, p, _ = roll_pitch_yaw_rad
    cr, sr, cp, sp = math.cos(r), math.sin(r), math.cos(p), math.sin(p)
    return np.array([[1.0, 0.0, -sp], [0.0, cr, sr * cp], [0.0, -sr, cr * cp]])
