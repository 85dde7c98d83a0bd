"""The clamped truth on a hub that turns about x or z: a rigid rotation beside the bending modes.

The beam bends about y (deflecting in z). A hub about z turns it in the xy-plane and one about x
about its own axis; neither rotation moves a point of the undeformed strip along z, so at first
order (no spin) the rotation and the bending modes do not couple: the mass matrix of
q = [theta_hub, eta_1..eta_N] is block diagonal, diag(J_h + J_axis, I), with the undeformed
strip's inertia about the hub axis

    J_z = int rho t ((r + x)^2 + y^2) dA,    J_x = int rho t (y^2 + t^2 / 12) dA,

(the hub axis through the origin, the root at r along x; the second term of J_x is the section's
own inertia through the thickness). Inputs and outputs as the hub about y
(:mod:`~prbdm_pin.truth.plant.hybrid`): a tip force along z and the clamp's acceleration along z
load the modes only (their moments about x vanish on the planform, symmetric about y = 0), the
hub torque turns the hub only, and the tip's z does not see the rotation.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ...errors import BeamInputError
from ...io.records import readonly_array as _ro
from ...member.geometry import Beam
from .gains import ModalGains
from .hybrid import HybridModel, _check_number, hub_modal_damping, input_names

__all__ = ["DECOUPLED_AXES", "axis_inertia_kg_m2", "decoupled_hub_from_gains"]

DECOUPLED_AXES = ("x", "z")
# Gauss-Legendre on each interval where the half-width is linear: the integrands are polynomials
# of degree <= 3 in x there, which 3 points integrate exactly
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(3)


def axis_inertia_kg_m2(beam: Beam, radius_m: float, axis: str) -> float:
    """Return the undeformed strip's inertia about the hub axis ``axis`` (``"x"`` or ``"z"``).

    Parameters
    ----------
    beam : Beam
    radius_m : float
        The root's distance from the hub axis along x, m.
    axis : {"x", "z"}

    Returns
    -------
    float
        kg m^2 (module notes).
    """
    if axis not in DECOUPLED_AXES:
        raise BeamInputError(f"axis = {axis!r}: must be one of {', '.join(DECOUPLED_AXES)}")
    a, b = beam.intervals_m
    x = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * _NODES[None, :]
    wq = 0.5 * (b - a)[:, None] * _WEIGHTS[None, :]
    w = beam.half_width_at(x)
    t, rho = beam.uniform_thickness_m("the hub truth"), beam.material.rho_kg_m3
    # per unit length: int y^2 dy over the width = 2 w^3 / 3, the width itself 2 w
    y2 = 2.0 * w**3 / 3.0
    if axis == "z":
        per_length = (radius_m + x) ** 2 * 2.0 * w + y2
    else:
        per_length = y2 + 2.0 * w * t**2 / 12.0
    return float(rho * t * np.sum(wq * per_length))


def decoupled_hub_from_gains(gains: ModalGains, beam: Beam, hub_inertia_kg_m2: float,
                             hub_radius_m: float, axis: str, damping_ratio: float = 0.02,
                             damping: str = "modal") -> HybridModel:
    """Return the hub model of ``gains`` on a hub about ``axis`` (``"x"`` or ``"z"``).

    Parameters
    ----------
    gains : ModalGains
        The clamped truth's modal gains (``truth_modal_gains``).
    beam : Beam
        Its beam (the planform integrals of the hub's inertia).
    hub_inertia_kg_m2 : float
        J_h >= 0 about the hub axis, kg m^2.
    hub_radius_m : float
        r >= 0, the root's distance from the hub centre along x, m.
    axis : {"x", "z"}
    damping_ratio : float
        zeta in [0, 1) of every bending mode (the rotation is undamped); the ``"clamped"`` and
        ``"modal"`` forms coincide here, the modes being uncoupled.
    damping : {"clamped", "modal"}
        Recorded as the model's form.

    Returns
    -------
    HybridModel
        Coordinates [theta_hub, eta]; inputs and outputs as :func:`hybrid_model`'s.
    """
    J_h = _check_number("hub_inertia_kg_m2", hub_inertia_kg_m2, "kg m^2")
    r = _check_number("hub_radius_m", hub_radius_m, "m")
    zeta = _check_number("damping_ratio", damping_ratio, "1", upper=1.0)
    J_b = axis_inertia_kg_m2(beam, r, axis)
    n = gains.omega_rad_s.size
    a = gains.actuators_m.shape[0]
    M = np.eye(n + 1)
    M[0, 0] = J_h + J_b
    K = np.diag(np.concatenate([[0.0], gains.omega_rad_s**2]))
    Bq = np.zeros((n + 1, 3 + a))
    Bq[1:, 0] = gains.tip_force_per_sqrt_kg
    Bq[0, 1] = 1.0
    Bq[1:, 2:2 + a] = gains.strain_per_sqrt_kg_m.T
    Bq[1:, -1] = -gains.translation_sqrt_kg  # the clamp's acceleration along z
    Cq = np.zeros((2, n + 1))
    Cq[0, 1:] = gains.tip_z_per_sqrt_kg
    Cq[1, 0] = 1.0
    D = hub_modal_damping(M, K, zeta)
    MinvK, MinvD, MinvB = np.hsplit(scipy.linalg.solve(M, np.hstack([K, D, Bq]),
                                                       assume_a="pos"), [n + 1, 2 * n + 2])
    A = np.block([[np.zeros((n + 1, n + 1)), np.eye(n + 1)], [-MinvK, -MinvD]])
    B = np.vstack([np.zeros_like(Bq), MinvB])
    z = np.zeros(n + 1)
    C = np.vstack([np.hstack([Cq[0], z]), np.hstack([z, Cq[0]]),
                   np.hstack([Cq[1], z]), np.hstack([z, Cq[1]])])
    return HybridModel(
        hub_inertia_kg_m2=J_h, hub_radius_m=r, damping_ratio=zeta, beam_inertia_kg_m2=J_b,
        participation_sqrt_kg_m=_ro(np.zeros(n)), mass=_ro(M), stiffness=_ro(K),
        damping=_ro(D), input_matrix=_ro(Bq), output_matrix=_ro(Cq), A=_ro(A), B=_ro(B),
        C=_ro(C), D=_ro(np.zeros((C.shape[0], B.shape[1]))),
        frequencies_rad_s=_ro(np.concatenate([[0.0], gains.omega_rad_s])),
        input_names=input_names(a), damping_form=str(damping),
    )
