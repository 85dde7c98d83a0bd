"""A free-floating rigid bus carrying the clamped truth: hybrid coordinates [z_b, theta_b, eta].

The bus (mass m_b, inertia I_b about +y through its centre of mass O) floats freely; the beam's
root is clamped to it at ``root_m`` = r along x from O. In the plane the beam bends in, the bus
translates along z (z_b) and turns about +y (theta_b, the PRBDM joints' sense: a point at x from
O moves by -x theta_b); the beam's deflection is

    w(x) = z_b - (r + x) theta_b + sum_k phi_k(x) eta_k

with the clamped truth's mass-normalised modes phi_k. The kinetic energy gives the mass matrix

    M = [[m_b + m, -(m r + S_1), t^T], [-(m r + S_1), I_b + J_beam, -d^T], [t, -d, I]],

with m, S_1 the beam's mass and first moment about its root, J_beam = int rho t (r + x)^2 dA,
t_k = int rho t phi_k dA and d_k = int rho t (r + x) phi_k dA; K = diag(0, 0, omega_k^2). The
motions the planar chain does not have (translation along x and y, turns about x and z) carry
no bending at first order and are left out. Inputs by virtual work: a tip force F_z does
F_z (z_b - (r + L) theta_b + sum b_k eta_k), a force on the bus along z and a torque on it about
+y act on z_b and theta_b, a strain actuator's moment pair (internal) on the eta_k only. Outputs:
the tip's z relative to the bus (its frame: the flexible part sum c_k eta_k), the bus's z and
angle and their rates.

The two rigid motions are taken out exactly (not left to the eigensolver): with R the rigid
coordinates, every flexible mode has phi_R = -M_RR^-1 M_Rf phi_f and
K_f phi_f = omega^2 S phi_f, S = M_ff - M_fR M_RR^-1 M_Rf. Modal damping gives each flexible
mode the same ratio and the rigid ones none, as ``prbdm_pin.linearize(..., damping="modal")``.
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
from .hybrid import _check_number, beam_inertia_kg_m2

__all__ = ["BUS_OUTPUT_NAMES", "BusModel", "bus_input_names", "bus_matrices", "bus_model",
           "bus_from_gains", "rigid_modes"]

BUS_OUTPUT_NAMES = ("tip_z", "tip_z_rate", "bus_position_z", "bus_attitude_y", "bus_rate_y")
N_RIGID = 2


def bus_input_names(n_actuators: int) -> tuple[str, ...]:
    """Return the input names: tip force, bus force and torque, strains.

    ``tip_force_z``, ``bus_force_z``, ``bus_torque_y``, ``strain[0..a-1]``.
    """
    return ("tip_force_z", "bus_force_z", "bus_torque_y",
            *(f"strain[{i}]" for i in range(n_actuators)))


@dataclass(frozen=True, eq=False)
class BusModel:
    """The free bus and clamped-mode model as second-order matrices and as a state space.

    Coordinates q = [z_b (m), theta_b (rad), eta_1..eta_N (sqrt(kg) m)]; state x = [q, dq/dt].

    Attributes
    ----------
    bus_mass_kg, bus_inertia_kg_m2, root_m, damping_ratio : float
    mass, stiffness, damping : ndarray, shape (N+2, N+2)
        M, K = diag(0, 0, omega_k^2), D (modal: zeta on every flexible mode, none on the rigid).
    input_matrix : ndarray, shape (N+2, 3+a)
        Generalised forces per unit input (``input_names``).
    output_matrix : ndarray, shape (3, N+2)
        Tip z relative to the bus (m), bus z (m), bus angle about +y (rad), from q.
    A, B, C, D : ndarray
        dx/dt = A x + B u, y = C x + D u (D = 0); the rows of C are ``output_names``.
    frequencies_rad_s : ndarray, shape (N+2,)
        The two rigid zeros, then the free bus-and-beam frequencies, rad/s.
    input_names, output_names : tuple of str
    """

    bus_mass_kg: float
    bus_inertia_kg_m2: float
    root_m: float
    damping_ratio: float
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
    output_names: tuple[str, ...] = BUS_OUTPUT_NAMES


def bus_matrices(gains: ModalGains, bus_mass_kg: float, bus_inertia_kg_m2: float,
                 root_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mass, stiffness, input and output matrices of the bus and clamped-mode model.

    Parameters
    ----------
    gains : ModalGains
    bus_mass_kg : float
        m_b > 0, kg.
    bus_inertia_kg_m2 : float
        I_b > 0 about +y through the bus's centre of mass, kg m^2.
    root_m : float
        r >= 0, the beam root's distance from the bus's centre of mass along x, m.

    Returns
    -------
    M, K : ndarray, shape (N+2, N+2)
    Bq : ndarray, shape (N+2, 3+a)
        Columns: tip force (N), bus force along z (N), bus torque about +y (N m), actuator
        moments (N m).
    Cq : ndarray, shape (3, N+2)
        Rows: tip z relative to the bus (m), bus z (m), bus angle (rad).
    """
    m_b = _check_number("bus_mass_kg", bus_mass_kg, "kg")
    I_b = _check_number("bus_inertia_kg_m2", bus_inertia_kg_m2, "kg m^2")
    r = _check_number("root_m", root_m, "m")
    if m_b <= 0.0 or I_b <= 0.0:
        raise BeamInputError(f"bus_mass_kg = {bus_mass_kg!r}, bus_inertia_kg_m2 = "
                             f"{bus_inertia_kg_m2!r}: a free bus needs a mass and an inertia "
                             "> 0 (a massless bus is the free-free beam's limit, not a support)")
    n = gains.omega_rad_s.size
    t = np.asarray(gains.translation_sqrt_kg, dtype=float)
    d = r * t + gains.moment_sqrt_kg_m
    M = np.eye(n + 2)
    M[0, 0] = m_b + gains.mass_kg
    M[0, 1] = M[1, 0] = -(r * gains.mass_kg + gains.first_moment_kg_m)
    M[1, 1] = I_b + beam_inertia_kg_m2(gains, r)
    M[0, 2:] = M[2:, 0] = t
    M[1, 2:] = M[2:, 1] = -d
    K = np.diag(np.concatenate([[0.0, 0.0], gains.omega_rad_s**2]))
    a = gains.actuators_m.shape[0]
    Bq = np.zeros((n + 2, 3 + a))
    Bq[0, 0], Bq[1, 0], Bq[2:, 0] = 1.0, -(r + gains.length_m), gains.tip_force_per_sqrt_kg
    Bq[0, 1] = 1.0
    Bq[1, 2] = 1.0
    Bq[2:, 3:] = gains.strain_per_sqrt_kg_m.T
    Cq = np.zeros((3, n + 2))
    Cq[0, 2:] = gains.tip_z_per_sqrt_kg
    Cq[1, 0] = 1.0
    Cq[2, 1] = 1.0
    return M, K, Bq, Cq


def rigid_modes(M: np.ndarray, omega2: np.ndarray, n_rigid: int = N_RIGID
                ) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and mass-normalised modes of a system whose first coordinates are rigid.

    Parameters
    ----------
    M : ndarray (n, n)
        Mass matrix, the ``n_rigid`` rigid coordinates first.
    omega2 : ndarray (n - n_rigid,)
        The flexible coordinates' stiffness (diagonal, here the clamped omega_k^2, 1/s^2).
    n_rigid : int
        Number of rigid (spring-free) coordinates.

    Returns
    -------
    omega : ndarray (n,)
        Exact zeros for the rigid modes, then the flexible frequencies (rad/s, ascending).
    Phi : ndarray (n, n)
        Modes as columns, Phi^T M Phi = I.
    """
    R, F = slice(0, n_rigid), slice(n_rigid, None)
    M_RR, M_Rf = M[R, R], M[R, F]
    G = scipy.linalg.solve(M_RR, M_Rf, assume_a="pos")  # M_RR^-1 M_Rf
    S = M[F, F] - M_Rf.T @ G
    lam, Pf = scipy.linalg.eigh(np.diag(omega2), 0.5 * (S + S.T))
    n = M.shape[0]
    Phi = np.zeros((n, n))
    # the rigid modes: M_RR^-1/2 on the rigid coordinates (mass-normalised, M-orthogonal to
    # every flexible mode by construction)
    Phi[R, R] = np.linalg.inv(np.linalg.cholesky(M_RR)).T
    Phi[F, F] = Pf
    Phi[R, F] = -G @ Pf
    return np.concatenate([np.zeros(n_rigid), np.sqrt(np.clip(lam, 0.0, None))]), Phi


def bus_from_gains(gains: ModalGains, bus_mass_kg: float, bus_inertia_kg_m2: float,
                   root_m: float = 0.0, damping_ratio: float = 0.02) -> BusModel:
    """Return the free-bus plant of ``gains`` (see :func:`bus_model`)."""
    zeta = _check_number("damping_ratio", damping_ratio, "1", upper=1.0)
    M, K, Bq, Cq = bus_matrices(gains, bus_mass_kg, bus_inertia_kg_m2, root_m)
    omega, Phi = rigid_modes(M, np.diag(K)[N_RIGID:])
    MP = M @ Phi[:, N_RIGID:]
    D = (MP * (2.0 * zeta * omega[N_RIGID:])) @ MP.T
    D = 0.5 * (D + D.T)
    n = M.shape[0]
    MinvK, MinvD, MinvB = np.hsplit(scipy.linalg.solve(M, np.hstack([K, D, Bq]),
                                                       assume_a="pos"), [n, 2 * n])
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-MinvK, -MinvD]])
    B = np.vstack([np.zeros_like(Bq), MinvB])
    z = np.zeros(n)
    # rows: tip z (bus frame), its rate, bus z, bus angle, bus rate
    C = np.vstack([np.hstack([Cq[0], z]), np.hstack([z, Cq[0]]), np.hstack([Cq[1], z]),
                   np.hstack([Cq[2], z]), np.hstack([z, Cq[2]])])
    return BusModel(
        bus_mass_kg=float(bus_mass_kg), bus_inertia_kg_m2=float(bus_inertia_kg_m2),
        root_m=float(root_m), damping_ratio=zeta, mass=_ro(M), stiffness=_ro(K),
        damping=_ro(D), input_matrix=_ro(Bq), output_matrix=_ro(Cq), A=_ro(A), B=_ro(B),
        C=_ro(C), D=_ro(np.zeros((C.shape[0], B.shape[1]))), frequencies_rad_s=_ro(omega),
        input_names=bus_input_names(gains.actuators_m.shape[0]),
    )


def bus_model(truth: TruthResult, beam: Beam, bus_mass_kg: float, bus_inertia_kg_m2: float,
              root_m: float = 0.0, actuators: Sequence[tuple[float, float]] = (),
              damping_ratio: float = 0.02) -> BusModel:
    """Return the clamped truth on a free-floating rigid bus, in hybrid coordinates, as a plant.

    Parameters
    ----------
    truth : TruthResult
        A ``"plate"``, ``"plate-morley"`` or ``"beam"`` truth of ``beam``; its selected modes
        are the flexible coordinates.
    beam : Beam
    bus_mass_kg : float
        The bus's mass, kg (> 0).
    bus_inertia_kg_m2 : float
        Its inertia about +y through its centre of mass, kg m^2 (> 0).
    root_m : float
        The beam root's distance from the bus's centre of mass along x, m (>= 0).
    actuators : sequence of (x_a, x_b)
        Strain actuators' stations, m (see ``truth_modal_gains``).
    damping_ratio : float
        zeta in [0, 1) of every flexible mode; the rigid motions undamped.

    Returns
    -------
    BusModel
    """
    # the scalars first: a bad one should not cost a modal solve
    for name, value, unit in (("bus_mass_kg", bus_mass_kg, "kg"),
                              ("bus_inertia_kg_m2", bus_inertia_kg_m2, "kg m^2"),
                              ("root_m", root_m, "m")):
        _check_number(name, value, unit)
    _check_number("damping_ratio", damping_ratio, "1", upper=1.0)
    gains = truth_modal_gains(truth, beam, actuators)
    return bus_from_gains(gains, bus_mass_kg, bus_inertia_kg_m2, root_m, damping_ratio)
