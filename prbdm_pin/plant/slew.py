"""A rest-to-rest slew of a hub with a flexible panel, on any plant in a common form.

``SlewPlant`` holds what every plant of the slew shares, whatever its states: inputs
(hub torque, N m; one strain actuator's moment, N m), outputs (hub angle, rad; hub rate, rad/s;
tip z, m; tip z rate, m/s), the stiffness of its coordinates (for the strain energy) and the
hub's coordinate first, so that the rigid rotation by theta is the state theta e_0 (K e_0 = 0:
it is an equilibrium under zero input on a PRBDM and on the truth's hybrid model alike).

The slew to ``angle_rad`` is regulated as the error e = x - angle e_0 from e(0) = -angle e_0,
with the cost

    J = int (theta_e / angle)^2 + w (1/2 q^T K q) / E + (tau / tau_0)^2 + (M / M_0)^2 dt,

scaled from the design plant (``slew_scales``): the bandwidth omega_c = ``bandwidth_ratio``
omega_1 (its first flexible mode), tau_0 = J_tot omega_c^2 angle (a rigid slew at omega_c: with
w = 0 the LQR places the rigid mode at omega_c with damping 1/sqrt 2), M_0 = ``strain_ratio``
tau_0 and E = J_tot (omega_c angle)^2 / 2. The strain energy is coordinate free, so the same J
is evaluated on every plant. The tip vibration is the elastic tip deflection
w = tip_z + (r + L) theta (tip_z less the rigid rotation's share).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from .lqg import Compensator, closed_loop, initial_response, lqg_compensator, quadratic_cost

__all__ = ["INPUTS", "OUTPUTS", "SlewPlant", "SlewDesign", "SlewScales", "SlewResponse",
           "plant_from_linear", "plant_from_hybrid", "slew_scales", "slew_controller",
           "slew_response", "settling_time_s"]

INPUTS = ("hub_torque", "strain[0]")
OUTPUTS = ("hub_angle", "hub_rate", "tip_z", "tip_z_rate")


@dataclass(frozen=True, eq=False)
class SlewPlant:
    """A linear hub plant with the slew's inputs ``INPUTS`` and outputs ``OUTPUTS``.

    Attributes
    ----------
    A, B, C : ndarray
        x = [q, dq/dt], q[0] the hub angle (rad); shapes (2 nq, 2 nq), (2 nq, 2), (4, 2 nq).
    stiffness : ndarray (nq, nq)
        K of q (zero hub row and column), SI units of q.
    inertia_kg_m2 : float
        M[0, 0]: the hub's and the undeformed panel's inertia about the hub axis, kg m^2.
    arm_m : float
        r + L, the tip's distance from the hub axis, m.
    frequencies_rad_s : ndarray
        Undamped flexible frequencies (hub free), ascending, rad/s.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    stiffness: np.ndarray
    inertia_kg_m2: float
    arm_m: float
    frequencies_rad_s: np.ndarray


def plant_from_linear(lin, arm_m: float) -> SlewPlant:
    """Return the slew plant of a PRBDM ``LinearModel`` linearised on a hub.

    Its inputs are ``INPUTS`` and outputs ``OUTPUTS`` (in that order); ``arm_m`` = r + L, m.
    """
    if not lin.hub or lin.input_names != INPUTS or lin.output_names != OUTPUTS:
        raise BeamInputError(f"lin: must be a hub model with inputs {INPUTS} and outputs "
                             f"{OUTPUTS}, got {lin.input_names} and {lin.output_names}")
    w = np.sort(lin.modal().omega_rad_s)[1:]
    return SlewPlant(lin.A, lin.B, lin.C, lin.stiffness_Nm_per_rad,
                     float(lin.mass_kg_m2[0, 0]), float(arm_m), w)


def plant_from_hybrid(h, actuator: int = 0) -> SlewPlant:
    """Return the slew plant of the truth's ``HybridModel`` ``h`` with its strain actuator.

    Its inputs and outputs are picked and put in the slew's order.
    """
    cols = [h.input_names.index("hub_torque"), h.input_names.index(f"strain[{actuator}]")]
    rows = [h.output_names.index(name) for name in OUTPUTS]
    arm = -float(h.output_matrix[0, 0])  # tip z = -(r + L) theta + ...
    return SlewPlant(h.A, h.B[:, cols], h.C[rows], h.stiffness, float(h.mass[0, 0]), arm,
                     h.frequencies_rad_s[1:])


@dataclass(frozen=True)
class SlewDesign:
    """The slew and the controller's tuning (see the module notes).

    Attributes
    ----------
    angle_rad : float
        Slew angle, rad.
    bandwidth_ratio : float
        omega_c / omega_1 of the design plant.
    vibration_weight : float
        w, the strain energy's weight.
    strain_ratio : float
        M_0 / tau_0: the strain actuator's moment scale against the hub torque's.
    input_noise, sensor_noise : float
        Kalman filter: input noise intensity per (tau_0^2, M_0^2), and measurement noise
        intensity per the outputs' slew scales squared (angle, omega_c angle and (r + L) times
        these), s; larger sensor noise makes a slower, more robust estimator.
    """

    angle_rad: float = 0.1
    bandwidth_ratio: float = 0.3
    vibration_weight: float = 30.0
    strain_ratio: float = 0.3
    input_noise: float = 1.0
    sensor_noise: float = 1.0

    def __post_init__(self) -> None:
        """Check every field (BeamInputError naming it)."""
        for name in ("angle_rad", "bandwidth_ratio", "vibration_weight", "strain_ratio",
                     "input_noise", "sensor_noise"):
            v = getattr(self, name)
            if not np.isfinite(v) or v < 0.0 or (v == 0.0 and name != "vibration_weight"):
                raise BeamInputError(f"SlewDesign {name} = {v!r}: must be finite and > 0")


@dataclass(frozen=True)
class SlewScales:
    """The cost's scales, taken from the design plant.

    omega_c (rad/s), tau_0 (N m), M_0 (N m), E (J).
    """

    omega_c_rad_s: float
    torque_Nm: float
    moment_Nm: float
    energy_J: float


def slew_scales(plant: SlewPlant, design: SlewDesign) -> SlewScales:
    """Return the scales of ``design`` on the design plant ``plant``."""
    wc = design.bandwidth_ratio * float(plant.frequencies_rad_s[0])
    tau = plant.inertia_kg_m2 * wc**2 * design.angle_rad
    return SlewScales(wc, tau, design.strain_ratio * tau,
                      0.5 * plant.inertia_kg_m2 * (wc * design.angle_rad) ** 2)


def _weights(plant: SlewPlant, design: SlewDesign, s: SlewScales):
    nq = plant.stiffness.shape[0]
    Q = np.zeros((2 * nq, 2 * nq))
    Q[0, 0] = 1.0 / design.angle_rad**2
    Q[:nq, :nq] += design.vibration_weight * 0.5 * plant.stiffness / s.energy_J
    R = np.diag([1.0 / s.torque_Nm**2, 1.0 / s.moment_Nm**2])
    return Q, R


def slew_controller(plant: SlewPlant, design: SlewDesign, scales: SlewScales) -> Compensator:
    """Return the LQG compensator of ``design`` on ``plant`` (outputs' errors to inputs)."""
    Q, R = _weights(plant, design, scales)
    th, wc, arm = design.angle_rad, scales.omega_c_rad_s, plant.arm_m
    Wn = design.input_noise * np.diag([scales.torque_Nm**2, scales.moment_Nm**2])
    Vn = design.sensor_noise * np.diag([th, wc * th, arm * th, arm * wc * th]) ** 2
    return lqg_compensator(plant.A, plant.B, plant.C, Q, R, Wn, Vn)


@dataclass(frozen=True, eq=False)
class SlewResponse:
    """A slew of ``plant`` under a compensator.

    Attributes
    ----------
    t_s, hub_angle_rad, tip_vibration_m : ndarray
        Time, hub angle and elastic tip deflection w = tip_z + (r + L) theta.
    input_peak : ndarray (2,)
        max ``|hub torque|`` (N m) and max ``|strain moment|`` (N m).
    cost : float
        J of the module notes (``inf`` when the loop is unstable).
    max_real_pole_rad_s : float
        Largest real part of the closed loop's poles.
    """

    t_s: np.ndarray
    hub_angle_rad: np.ndarray
    tip_vibration_m: np.ndarray
    input_peak: np.ndarray
    cost: float
    max_real_pole_rad_s: float


def slew_response(plant: SlewPlant, comp: Compensator, design: SlewDesign,
                  scales: SlewScales, t_s: np.ndarray) -> SlewResponse:
    """Return the slew of ``plant`` under ``comp`` on the uniform grid ``t_s`` (s), exact."""
    A_cl = closed_loop(plant.A, plant.B, plant.C, comp)
    n = plant.A.shape[0]
    x0 = np.zeros(A_cl.shape[0])
    x0[0] = -design.angle_rad
    X = initial_response(A_cl, x0, t_s)
    y = X[:, :n] @ plant.C.T
    G = np.hstack([comp.D @ plant.C, comp.C])  # u = G [e; x_k]
    u = X @ G.T
    Q, R = _weights(plant, design, scales)
    Q_cl = G.T @ R @ G
    Q_cl[:n, :n] += Q
    return SlewResponse(
        t_s=np.asarray(t_s), hub_angle_rad=y[:, 0] + design.angle_rad,
        tip_vibration_m=y[:, 2] + plant.arm_m * y[:, 0], input_peak=np.abs(u).max(axis=0),
        cost=quadratic_cost(A_cl, Q_cl, x0),
        max_real_pole_rad_s=float(np.max(np.linalg.eigvals(A_cl).real)))


def settling_time_s(t_s: np.ndarray, y: np.ndarray, final: float, band: float) -> float:
    """Return the first time (s) after which ``|y - final| <= band`` for good.

    ``inf`` if the last sample is outside the band.
    """
    out = np.flatnonzero(np.abs(np.asarray(y) - final) > band)
    if out.size == 0:
        return float(t_s[0])
    if out[-1] == len(y) - 1:
        return float("inf")
    return float(t_s[out[-1] + 1])
