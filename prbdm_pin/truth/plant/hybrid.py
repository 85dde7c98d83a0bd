"""A rigid hub carrying the clamped truth: Likins' hybrid coordinates [theta_hub, eta_1..eta_N].

The hub (inertia J_h about the bending axis y) holds the beam's root at radius r from its axis.
theta_hub is a rotation about +y (the PRBDM joints' sense, see ``gains``), so the rigid motion
moves a point at x by z = -(r + x) theta and the deflection is w = -(r + x) theta + sum phi_k eta_k.
The kinetic energy gives the mass matrix

    M = [[J_h + J_beam, -d^T], [-d, I]],  J_beam = int rho t (r + x)^2 dA,
    d_k = int rho t (r + x) phi_k dA,

the strain energy K = diag(0, omega_k^2), and the virtual work the input matrix: a hub torque
acts on theta; a tip force F_z does F_z (-(r + L) theta + sum b_k eta_k); a strain actuator (an
internal moment pair, no work on a rigid rotation) acts on the eta_k only; an acceleration a of
the hub's axis along +z (``base_accel_z``, m/s^2) loads every mass element with -rho t a
(d'Alembert, in the axis' frame), which does a (m r + S_1) on theta (S_1 = int rho t x dA) and
-a int rho t phi_k dA on eta_k; the outputs are then relative to the axis.

Damping (``damping``): ``"clamped"`` damps the clamped modes, D = diag(0, 2 zeta omega_k) in
these coordinates, so the hub-stiffened modes get ratios that differ from zeta (and are coupled);
``"modal"`` damps the coupled flexible modes, D = M Phi_f diag(2 zeta Omega_k) Phi_f^T M with
the hub-stiffened frequencies Omega_k and mass-normalised modes Phi_f: each flexible mode gets
zeta exactly and the rigid rotation none, the definition ``prbdm_pin.linearize(...,
damping="modal")`` uses on a PRBDM hub model.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...errors import BeamInputError
from ...io.records import readonly_array as _ro
from ...member.geometry import Beam
from ..result import TruthResult
from .gains import ModalGains, truth_modal_gains

__all__ = ["DAMPING_KINDS", "OUTPUT_NAMES", "HybridModel", "beam_inertia_kg_m2",
           "hybrid_matrices", "hub_frequencies_rad_s", "hub_modal_damping",
           "hybrid_from_gains", "hybrid_model", "input_names"]

OUTPUT_NAMES = ("tip_z", "tip_z_rate", "hub_angle", "hub_rate")
DAMPING_KINDS = ("clamped", "modal")


def input_names(n_actuators: int) -> tuple[str, ...]:
    """Return the input names (tip force, hub torque, strains, the axis' acceleration).

    ``tip_force_z``, ``hub_torque``, ``strain[0..a-1]``, ``base_accel_z``.
    """
    return ("tip_force_z", "hub_torque", *(f"strain[{i}]" for i in range(n_actuators)),
            "base_accel_z")


@dataclass(frozen=True, eq=False)
class HybridModel:
    """The hub and clamped-mode model as second-order matrices and as a state space.

    Generalised coordinates q = [theta_hub (rad), eta_1..eta_N (sqrt(kg) m)]; state
    x = [q, dq/dt]. Inputs u (``input_names``): tip force F_z (N), hub torque about +y (N m),
    actuator moments (N m), the axis' acceleration along +z (m/s^2). Outputs y
    (``output_names``): tip z (m, relative to the axis), its rate (m/s), hub angle (rad), hub
    rate (rad/s).

    Attributes
    ----------
    hub_inertia_kg_m2, hub_radius_m, damping_ratio : float
    damping_form : str
        ``"clamped"`` or ``"modal"`` (see the module notes).
    beam_inertia_kg_m2 : float
        J_beam, the undeformed beam's inertia about the hub axis.
    participation_sqrt_kg_m : ndarray, shape (N,)
        d_k = int rho t (r + x) phi_k dA.
    mass, stiffness, damping : ndarray, shape (N+1, N+1)
        M, K = diag(0, omega_k^2), D (no damping on the rigid rotation; diag(0, 2 zeta
        omega_k) in the ``"clamped"`` form); SI units of q (kg m^2, sqrt(kg) m, 1; N m/rad,
        1/s^2; 1/s).
    input_matrix : ndarray, shape (N+1, 2+a)
        Generalised forces per unit input.
    output_matrix : ndarray, shape (2, N+1)
        Tip z and hub angle from q.
    A, B, C, D : ndarray
        dx/dt = A x + B u, y = C x + D u (D = 0).
    frequencies_rad_s : ndarray, shape (N+1,)
        Undamped hub-stiffened frequencies, rad/s, from the rigid mode (0) up.
    input_names, output_names : tuple of str
    """

    hub_inertia_kg_m2: float
    hub_radius_m: float
    damping_ratio: float
    beam_inertia_kg_m2: float
    participation_sqrt_kg_m: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    input_matrix: np.ndarray
    output_matrix: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    frequencies_rad_s: np.ndarray
    input_names: tuple[str, ...]
    output_names: tuple[str, ...] = OUTPUT_NAMES
    damping_form: str = "clamped"


def _check_number(name: str, value: object, unit: str, upper: float = np.inf) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise BeamInputError(f"{name} = {value!r}: must be a number in {unit}")
    v = float(value)
    if not np.isfinite(v) or v < 0.0 or v >= upper:
        bound = "" if upper == np.inf else f" and < {upper:g}"
        raise BeamInputError(f"{name} = {value!r}: must be finite, >= 0{bound} ({unit})")
    return v


def beam_inertia_kg_m2(gains: ModalGains, hub_radius_m: float) -> float:
    """Return the undeformed beam's inertia about the hub axis, kg m^2.

    J_beam = int rho t (r + x)^2 dA with r = ``hub_radius_m``, m.
    """
    r = hub_radius_m
    return gains.mass_kg * r**2 + 2.0 * r * gains.first_moment_kg_m + gains.second_moment_kg_m2


def hybrid_matrices(gains: ModalGains, hub_inertia_kg_m2: float, hub_radius_m: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mass, stiffness, input and output matrices of the hub and clamped-mode model.

    Parameters
    ----------
    gains : ModalGains
    hub_inertia_kg_m2 : float
        J_h >= 0, kg m^2.
    hub_radius_m : float
        r >= 0: the root's distance from the hub axis, m.

    Returns
    -------
    M, K : ndarray, shape (N+1, N+1)
    Bq : ndarray, shape (N+1, 3+a)
        Columns: tip force (N), hub torque (N m), actuator moments (N m), the axis'
        acceleration along +z (m/s^2).
    Cq : ndarray, shape (2, N+1)
        Rows: tip z (m), hub angle (rad).
    """
    J_h = _check_number("hub_inertia_kg_m2", hub_inertia_kg_m2, "kg m^2")
    r = _check_number("hub_radius_m", hub_radius_m, "m")
    n = gains.omega_rad_s.size
    d = r * gains.translation_sqrt_kg + gains.moment_sqrt_kg_m
    M = np.eye(n + 1)
    M[0, 0] = J_h + beam_inertia_kg_m2(gains, r)
    M[0, 1:] = M[1:, 0] = -d  # z = -(r + x) theta for a rotation about +y
    K = np.diag(np.concatenate([[0.0], gains.omega_rad_s**2]))
    arm = r + gains.length_m
    a = gains.actuators_m.shape[0]
    Bq = np.zeros((n + 1, 3 + a))
    Bq[0, 0], Bq[1:, 0] = -arm, gains.tip_force_per_sqrt_kg
    Bq[0, 1] = 1.0
    Bq[1:, 2:2 + a] = gains.strain_per_sqrt_kg_m.T
    # the axis' acceleration: d'Alembert's -rho t a on every element (module notes)
    Bq[0, -1] = r * gains.mass_kg + gains.first_moment_kg_m
    Bq[1:, -1] = -gains.translation_sqrt_kg
    Cq = np.zeros((2, n + 1))
    Cq[0, 0], Cq[0, 1:] = -arm, gains.tip_z_per_sqrt_kg
    Cq[1, 0] = 1.0
    return M, K, Bq, Cq


def hub_frequencies_rad_s(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Return the undamped frequencies (rad/s, ascending) of K v = omega^2 M v.

    The symmetric generalised eigenproblem (M never inverted); the rigid mode's rounding is
    clipped to 0.

    Parameters
    ----------
    M : ndarray (N + 1, N + 1)
        Mass matrix of q = [theta_hub (rad), eta (sqrt(kg) m)] (``hybrid_matrices``): kg m^2
        on the hub, sqrt(kg) m on the coupling, identity on the modes.
    K : ndarray (N + 1, N + 1)
        Stiffness matrix in the same coordinates: diag(0, omega_k^2), omega_k in rad/s.

    Returns
    -------
    ndarray (N + 1,)
        Frequencies, rad/s, the rigid 0 first.
    """
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None))


def _check_damping(damping: object) -> str:
    if damping not in DAMPING_KINDS:
        raise BeamInputError(f"damping = {damping!r}: must be one of {', '.join(DAMPING_KINDS)}")
    return str(damping)


def hub_modal_damping(M: np.ndarray, K: np.ndarray, damping_ratio: float) -> np.ndarray:
    """Return the modal damping D = M Phi_f diag(2 zeta omega_f) Phi_f^T M of the hub system.

    Phi_f are the flexible modes (mass-normalised, the rigid mode taken out exactly): each
    flexible mode of (K, M) gets the ratio ``damping_ratio``, the rigid rotation none; the PRBDM
    plant's ``"modal"`` form.

    Parameters
    ----------
    M, K : ndarray (N + 1, N + 1)
        Mass and stiffness matrices of the hybrid coordinates (units as in
        :func:`hub_frequencies_rad_s`); the hub coordinate first, without a spring.
    damping_ratio : float
        zeta of every flexible mode, dimensionless.

    Returns
    -------
    ndarray (N + 1, N + 1)
        The damping matrix in the same coordinates (N m s/rad on the hub).
    """
    from ...model.hub import hub_modes

    omega, Phi = hub_modes(M, np.diag(K)[1:])
    MP = M @ Phi[:, 1:]
    D = (MP * (2.0 * damping_ratio * omega[1:])) @ MP.T
    return 0.5 * (D + D.T)


def hybrid_from_gains(gains: ModalGains, hub_inertia_kg_m2: float, hub_radius_m: float,
                      damping_ratio: float = 0.02, damping: str = "clamped") -> HybridModel:
    """Return the hub model of ``gains`` (see ``hybrid_model``).

    Parameters
    ----------
    gains : ModalGains
        The clamped truth's modal gains (``truth_modal_gains``).
    hub_inertia_kg_m2 : float
        J_h >= 0 about the hub axis, kg m^2.
    hub_radius_m : float
        r >= 0, the beam root's distance from the hub axis, m.
    damping_ratio : float
        zeta in [0, 1), dimensionless.
    damping : {"clamped", "modal"}
        Which modes get ``damping_ratio`` (see ``hybrid_model``).

    Returns
    -------
    HybridModel
    """
    zeta = _check_number("damping_ratio", damping_ratio, "1", upper=1.0)
    kind = _check_damping(damping)
    M, K, Bq, Cq = hybrid_matrices(gains, hub_inertia_kg_m2, hub_radius_m)
    n = M.shape[0]
    if kind == "clamped":
        D = np.diag(np.concatenate([[0.0], 2.0 * zeta * gains.omega_rad_s]))
    else:
        D = hub_modal_damping(M, K, zeta)
    MinvK, MinvD, MinvB = np.hsplit(scipy.linalg.solve(M, np.hstack([K, D, Bq]),
                                                       assume_a="pos"), [n, 2 * n])
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-MinvK, -MinvD]])
    B = np.vstack([np.zeros_like(Bq), MinvB])
    z = np.zeros_like(Cq)
    C = np.vstack([np.hstack([Cq[0], z[0]]), np.hstack([z[0], Cq[0]]),
                   np.hstack([Cq[1], z[1]]), np.hstack([z[1], Cq[1]])])
    return HybridModel(
        hub_inertia_kg_m2=float(hub_inertia_kg_m2),
        hub_radius_m=float(hub_radius_m),
        damping_ratio=zeta,
        beam_inertia_kg_m2=beam_inertia_kg_m2(gains, float(hub_radius_m)),
        participation_sqrt_kg_m=_ro(-M[0, 1:]),
        mass=_ro(M), stiffness=_ro(K), damping=_ro(D), input_matrix=_ro(Bq),
        output_matrix=_ro(Cq), A=_ro(A), B=_ro(B), C=_ro(C),
        D=_ro(np.zeros((C.shape[0], B.shape[1]))),
        frequencies_rad_s=_ro(hub_frequencies_rad_s(M, K)),
        input_names=input_names(gains.actuators_m.shape[0]),
        damping_form=kind,
    )


def hybrid_model(truth: TruthResult, beam: Beam, hub_inertia_kg_m2: float, hub_radius_m: float,
                 actuators: Sequence[tuple[float, float]] = (),
                 damping_ratio: float = 0.02, damping: str = "clamped") -> HybridModel:
    """Return the clamped truth on a rotating rigid hub, in hybrid coordinates, as a plant.

    Parameters
    ----------
    truth : TruthResult
        A ``"plate"``, ``"plate-morley"`` or ``"beam"`` truth of ``beam``; its selected modes
        are the flexible coordinates.
    beam : Beam
    hub_inertia_kg_m2 : float
        J_h >= 0 about the hub axis (parallel to y), kg m^2.
    hub_radius_m : float
        r >= 0, the beam root's distance from the hub axis, m.
    actuators : sequence of (x_a, x_b)
        Strain actuators' stations, m (see ``truth_modal_gains``).
    damping_ratio : float
        zeta in [0, 1), none on the rigid rotation.
    damping : {"clamped", "modal"}
        ``"clamped"``: zeta on every clamped mode (D = diag(0, 2 zeta omega_k) in the hybrid
        coordinates; the hub-stiffened modes then get somewhat less). ``"modal"``: zeta on every
        hub-stiffened flexible mode (``hub_modal_damping``), the form of the PRBDM plant's
        ``damping="modal"``, for comparing the two plants at equal damping.

    Returns
    -------
    HybridModel
    """
    # the scalar inputs first: a bad one should not cost a modal solve
    _check_number("hub_inertia_kg_m2", hub_inertia_kg_m2, "kg m^2")
    _check_number("hub_radius_m", hub_radius_m, "m")
    _check_number("damping_ratio", damping_ratio, "1", upper=1.0)
    _check_damping(damping)
    gains = truth_modal_gains(truth, beam, actuators)
    return hybrid_from_gains(gains, hub_inertia_kg_m2, hub_radius_m, damping_ratio, damping)
