"""The derivative rules shared by the truth sensitivities: eigenvalues, adjoint statics, materials.

For K(p) phi = lam M(p) phi, d lam / dp = phi^T (dK - lam dM) phi / (phi^T M phi) (any scaling of
phi); for K(p) u = f(p) and the output delta = c^T u, d delta / dp = a^T (df - dK u) with the
adjoint K a = c. Both need only the derivatives of the forms v^T K w, v^T M w, v^T f with fixed
vectors, which the models provide: in closed form for thickness and material, by shape
derivatives for the planform.
"""

from __future__ import annotations

import numpy as np

from ..errors import TruthError
from ..member.geometry import Beam

__all__ = ["COMPLEX_STEP", "VELOCITY_STEP", "GAP_TOL", "check_gaps", "material_forms",
           "omega_derivative", "tip_derivative"]

# Shape derivatives of the element integrals (plate and 1D beam) by complex step: the nodes move
# by i COMPLEX_STEP V (V their velocity, m per unit of the variable, at most ~1) and the
# derivative is the imaginary part / COMPLEX_STEP, with an error of COMPLEX_STEP^2 times third
# derivatives, far below rounding, and no subtraction. (Fourth-order central differences, used
# before, met the large higher derivatives of the plate's integrals at its small corner
# elements: second-order ones lost 1e-4..1e-2 at 1e-5 steps and rounding took over below 1e-6.)
COMPLEX_STEP = 1e-20
# the node velocities are central differences of the mesh's map to the moved planform, which is
# affine in every design variable, with steps VELOCITY_STEP x the variable's scale
# (``Design.scales``): inside every variable's bounds; rounding eps / VELOCITY_STEP relative
VELOCITY_STEP = 1e-2


# a selected eigenvalue closer than this (relative) to another computed one is refused: the
# derivative of a repeated eigenvalue is not defined by one mode, and the computed mode of a
# near-repeated one mixes its neighbour in by about eps / gap
GAP_TOL = 1e-6


def check_gaps(name: str, lam_all: np.ndarray, index: np.ndarray, mode_offset: int = 1) -> None:
    """Raise TruthError when a selected eigenvalue ``lam_all[index]`` is (nearly) repeated."""
    lam_all = np.asarray(lam_all, dtype=float)
    for rank, i in enumerate(index, start=mode_offset):
        others = np.delete(lam_all, i)
        j = int(np.argmin(np.abs(others - lam_all[i])))
        gap = abs(others[j] - lam_all[i]) / lam_all[i]
        if gap < GAP_TOL:
            jj = j + (j >= i)
            raise TruthError(
                f"{name!r}: selected mode {rank} (mode {i + 1}, {np.sqrt(lam_all[i]):.9g} rad/s) "
                f"and mode {jj + 1} ({np.sqrt(lam_all[jj]):.9g} rad/s) are {gap:.1e} apart "
                f"(relative eigenvalue gap below {GAP_TOL:g}): a repeated eigenvalue has no "
                "derivative of its own; move the design slightly or select other modes")


def material_forms(kind: str, beam: Beam, plate: bool, qk: np.ndarray, qm: np.ndarray,
                   qk1: np.ndarray | None = None, qk2: np.ndarray | None = None):
    """Return the derivatives (d(v^T K w), d(v^T M w)) of the forms ``qk``, ``qm``.

    The derivatives are with respect to a thickness or material variable ``kind``.

    Both models have K proportional to E t^3 and M to rho t. The plate's K is
    D [(1 - nu) K1 + nu K2] with D = E t^3 / (12 (1 - nu^2)): its nu derivative needs the
    geometric forms ``qk1`` = v^T K1 w, ``qk2`` = v^T K2 w; the 1D beam does not depend on nu.
    """
    mat = beam.material
    zero = np.zeros_like(np.asarray(qk, dtype=float))
    if kind == "thickness":
        t = beam.uniform_thickness_m("the truth derivatives")
        return 3.0 * qk / t, qm / t
    if kind == "E":
        return qk / mat.E_Pa, zero
    if kind == "rho":
        return zero, qm / mat.rho_kg_m3
    if kind == "nu":
        if not plate:
            return zero, zero
        nu = mat.nu
        D = mat.E_Pa * beam.uniform_thickness_m("the truth derivatives")**3 / (12.0 * (1.0 - nu**2))
        return 2.0 * nu / (1.0 - nu**2) * qk + D * (qk2 - qk1), zero
    raise ValueError(f"kind = {kind!r}: not a thickness or material variable")


def omega_derivative(omega: np.ndarray, dqk: np.ndarray, dqm: np.ndarray, qk: np.ndarray,
                     qm: np.ndarray) -> np.ndarray:
    """Return d omega = omega / 2 (dqk / qk - dqm / qm), rad/s per unit of the variable.

    The derivative of the Rayleigh quotient R = qk / qm at the fixed mode, written relative to
    its own forms: the same as (dqk - lam dqm) / (2 omega qm) at an exact eigenpair (qk = lam qm),
    but free of the solve's rounding in lam, so that a form scaled by p^k gives exactly k / p.
    """
    return 0.5 * omega * (dqk / qk - dqm / qm)


def tip_derivative(tip_z: float, d_load: float, dqk: float, qk: float) -> float:
    """Return d delta = delta (a^T df - a^T dK u) / (a^T K u), m per unit of the variable.

    The adjoint rule a^T (df - dK u) scaled by delta / (a^T K u), which is 1 at an exact solution
    (K u = f, K a = c: a^T K u = c^T u = delta), for the reason of ``omega_derivative``.
    """
    return tip_z * (d_load - dqk) / qk
