"""An independent reference for the spinning chain: the rotating uniform Euler-Bernoulli
cantilever by cubic Hermite finite elements.

Not a test module (no ``test_`` prefix): test modules and the spin benchmark import it as
``from rotating_beam import ...`` (tests/ on ``sys.path``), and it imports nothing of the package.

The beam: uniform, length L (m), bending stiffness EI (N m^2), mass per length rho A (kg/m),
clamped at radius r (m) from the rotation axis, lying radially, turning at the constant rate
Omega (rad/s; the hub held at that rate: prescribed rotation). Small lateral vibration w(x, t)
about the straight radial pose, in the rotating frame:

- out of the plane of rotation (flapping): the centrifugal tension
  N(x) = rho A Omega^2 int_x^L (r + s) ds = rho A Omega^2 [r (L - x) + (L^2 - x^2) / 2]
  adds the geometric stiffness int N w'^2 dx:  K_e + Omega^2 K_g;
- in the plane of rotation (lead-lag): the same tension, less the centrifugal push on the
  lateral displacement itself, - rho A Omega^2 int w^2 dx:  K_e + Omega^2 (K_g - M).

Each element (length h) has the standard Hermite cubic stiffness EI/h^3 [...], the consistent
mass rho A h / 420 [...], and the geometric stiffness int N(x) N_i' N_j' dx integrated by
5-point Gauss-Legendre (exact: N is quadratic and N_i' N_j' quartic, degree 6 <= 9). The
frequencies solve (K - omega^2 M) phi = 0 for the rotating beam; the Southwell coefficients are
d(omega_k^2)/d(Omega^2) at rest (in plane K_in = K_out - 1: the -M term). Published check
(Hodges & Rutkowski, AIAA J. 19 (1981) 1459-1466, uniform cantilever, r = 0, out of plane, in
units of sqrt(EI / (rho A L^4))): at Omega = 1, 3.6816, 22.1810, 61.8418; at Omega = 12,
13.1702, 37.6031, 79.6145 (this module gives them to the table's 5 digits with 60 elements).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

__all__ = ["rotating_beam_frequencies", "southwell_coefficients", "BETA_L_CLAMPED"]

# clamped-free roots of cos(bL) cosh(bL) = -1 (Euler-Bernoulli): omega = (bL)^2 sqrt(EI/(rho A L^4))
BETA_L_CLAMPED = (1.8751040687119611, 4.6940911329741746, 7.8547574382376126)


def _element(h: float):
    k = np.array([[12.0, 6 * h, -12.0, 6 * h],
                  [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                  [-12.0, -6 * h, 12.0, -6 * h],
                  [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
    m = np.array([[156.0, 22 * h, 54.0, -13 * h],
                  [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                  [54.0, 13 * h, 156.0, -22 * h],
                  [-13 * h, -3 * h * h, -22 * h, 4 * h * h]]) * h / 420.0
    return k, m


def _shape_slopes(xi: np.ndarray, h: float) -> np.ndarray:
    # d/dx of the Hermite cubics at xi in [0, 1] (x = xi h)
    return np.stack([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2,
                     (6 * xi - 6 * xi**2) / h, -2 * xi + 3 * xi**2], axis=-1)


def _matrices(length_m: float, EI_Nm2: float, rho_A_kg_m: float, radius_m: float,
              plane: str, elements: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """K, M and the spin stiffness per Omega^2 (K_g, or K_g - M in plane) of the free dofs."""
    L, n = float(length_m), int(elements)
    h = L / n
    ke, me = _element(h)
    gx, gw = np.polynomial.legendre.leggauss(5)
    xi, wq = 0.5 * (gx + 1.0), 0.5 * gw
    ndof = 2 * (n + 1)
    K = np.zeros((ndof, ndof))
    M = np.zeros((ndof, ndof))
    G = np.zeros((ndof, ndof))
    for e in range(n):
        x = e * h + xi * h
        N = rho_A_kg_m * (radius_m * (L - x) + 0.5 * (L * L - x * x))  # per Omega^2
        B = _shape_slopes(xi, h)
        ge = np.einsum("q,qi,qj->ij", wq * h * N, B, B)
        s = slice(2 * e, 2 * e + 4)
        K[s, s] += EI_Nm2 * ke
        M[s, s] += rho_A_kg_m * me
        G[s, s] += ge
    if plane not in ("in", "out"):
        raise ValueError(f"plane = {plane!r}: 'in' or 'out'")
    S = G - (M if plane == "in" else 0.0)
    free = slice(2, None)  # clamped root: w = w' = 0
    return K[free, free], M[free, free], S[free, free]


def rotating_beam_frequencies(length_m: float, EI_Nm2: float, rho_A_kg_m: float,
                              spin_rad_s: float, radius_m: float = 0.0, plane: str = "out",
                              elements: int = 60, modes: int = 3) -> np.ndarray:
    """Return the first ``modes`` frequencies (rad/s) of the rotating uniform cantilever.

    ``plane`` is "out" (flapping, out of the plane of rotation) or "in" (lead-lag); see the
    module notes for the equations.
    """
    K, M, S = _matrices(length_m, EI_Nm2, rho_A_kg_m, radius_m, plane, elements)
    lam = sla.eigh(K + spin_rad_s**2 * S, M, eigvals_only=True,
                   subset_by_index=[0, modes - 1])
    return np.sqrt(lam)


def southwell_coefficients(radius_ratio: float = 0.0, plane: str = "out",
                           elements: int = 60, modes: int = 3) -> np.ndarray:
    """Return the Southwell coefficients d(omega_k^2)/d(Omega^2) at Omega = 0 (dimensionless).

    phi_k^T S phi_k over the mass-normalised modes phi_k of the beam at rest (first-order
    eigenvalue sensitivity), S the spin stiffness per Omega^2; ``radius_ratio`` is r / L.
    """
    K, M, S = _matrices(1.0, 1.0, 1.0, radius_ratio, plane, elements)
    _, Phi = sla.eigh(K, M, subset_by_index=[0, modes - 1])
    return np.einsum("ik,ij,jk->k", Phi, S, Phi)
