"""What a clamped truth model hands the plant gains: per computed mode, mass-normalised.

Both backends (``beam_fields``: the 1D Euler-Bernoulli beam, ``plate_fields``: the Kirchhoff
plate) fill one ``ModeFields`` for every computed mode; ``gains`` then checks it against the
truth, fixes the signs and keeps the selected modes. Units: the modes are normalised to
phi^T M phi = 1, so a modal coordinate eta is in sqrt(kg) m and phi in 1/sqrt(kg).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ModeFields", "section_rotation_sign"]


def section_rotation_sign() -> float:
    """d(section rotation about +y) / d(dw/dx) = -1.

    A rotation by a positive angle about +y turns e_x into (cos a, 0, -sin a): the PRBDM's
    joints (``planar``: link axis (cos phi, 0, -sin phi), dz_tip/dq < 0) and the hub both
    rotate this way, so the section rotation of a deflection w(x) is -dw/dx.
    """
    return -1.0


@dataclass(frozen=True, eq=False)
class ModeFields:
    """Input, output and inertia terms of every computed mode of a clamped model.

    Attributes
    ----------
    model : str
        ``"beam"``, ``"plate-argyris"`` or ``"plate-morley"``.
    omega_rad_s : ndarray, shape (k,)
        Clamped natural frequencies, rad/s.
    node_uz : ndarray, shape (k, n)
        Nodal z deflection of each mode (for matching with the truth's stored shapes).
    tip_force_per_sqrt_kg : ndarray, shape (k,)
        Generalised force per newton of tip force F_z: phi at the tip (1D), or phi averaged over
        the free edge (plate: the uniform edge load of the static truth).
    tip_z_per_sqrt_kg : ndarray, shape (k,)
        Tip z displacement per unit modal coordinate: phi at the tip centre (L, 0).
    strain_per_sqrt_kg_m : ndarray, shape (a, k)
        Generalised force per N m of each actuator's moment pair: the width-averaged section
        rotation about +y at x_b minus that at x_a.
    translation_sqrt_kg : ndarray, shape (k,)
        Integral of rho t phi dA.
    moment_sqrt_kg_m : ndarray, shape (k,)
        Integral of rho t x phi dA (x from the root).
    mass_kg, first_moment_kg_m, second_moment_kg_m2 : float
        Integrals of rho t, rho t x and rho t x^2 over the planform (the model's own quadrature).
    corner_per_sqrt_kg : ndarray, shape (2, k), or None
        phi at the tip corners (L, +w(L)) (left) and (L, -w(L)) (right): the generalised force
        per newton of a z point force there, and the corner's z per unit modal coordinate. None
        for a model without width (the 1D beam).
    """

    model: str
    omega_rad_s: np.ndarray
    node_uz: np.ndarray
    tip_force_per_sqrt_kg: np.ndarray
    tip_z_per_sqrt_kg: np.ndarray
    strain_per_sqrt_kg_m: np.ndarray
    translation_sqrt_kg: np.ndarray
    moment_sqrt_kg_m: np.ndarray
    mass_kg: float
    first_moment_kg_m: float
    second_moment_kg_m2: float
    corner_per_sqrt_kg: np.ndarray | None = None
