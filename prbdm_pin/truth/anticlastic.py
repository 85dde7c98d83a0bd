"""Ashwell's anticlastic restraint of a bent plate strip in closed form, with its derivatives.

The module also gives the curvature a section takes under a bending moment.

A free-edged strip of half-width a and thickness t bent to curvature kappa deflects across its
width by f(y) = nu kappa a^2 g(y / a), with g'''' + 4 eta^4 g = 0, g''(+-1) = -1, g'''(+-1) = 0 and
``eta = a (3 (1 - nu^2))^(1/4) sqrt(|kappa| / t)`` (see ``elastica``'s module docstring). Its
even solution gives, with x = 2 eta::

    g'(1) = -rho / eta,   rho(eta) = (cosh x - cos x) / (sinh x + sin x),

and the strain energy per unit length at the optimal f is D a kappa^2 (1 + nu^2 g'(1)) with
D = E t^3 / (12 (1 - nu^2)). Its derivative in kappa (eta grows as ``sqrt(|kappa|)``) is the
moment M = EI kappa r with EI = E 2 a t^3 / 12 and::

    r(eta, nu) = (1 + nu^2 Phi(eta)) / (1 - nu^2),   Phi = -3 rho / (4 eta) - rho' / 4,
    rho' = 4 sinh x sin x / (sinh x + sin x)^2.

Phi(0) = -1 (r = 1, the beam), Phi -> -3 / (4 eta) as eta grows (r -> 1 / (1 - nu^2), the plate's
cylindrical bending, with an algebraic tail); near 0, 1 + Phi = (8 / 45) eta^4 + O(eta^8).

The hyperbolic functions are written with q = exp(-x) so that nothing overflows and the small
quantities keep their relative accuracy: 2 q (sinh x + sin x) = -expm1(-2 x) + 2 q sin x and
2 q (cosh x - cos x) = expm1(-x)^2 + 4 q sin^2(x / 2).
"""

from __future__ import annotations

import numpy as np

__all__ = ["anticlastic_factor", "anticlastic_terms", "eta_per_root_curvature",
           "section_curvature", "section_state"]

# below it 1 + Phi is (8 / 45) eta^4 to a relative 2e-5 eta^4 (the closed form's cancellation
# in 1 + Phi is larger there)
_SERIES_ETA = 1e-2


def _phi(eta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return 1 + Phi(eta) and eta Phi'(eta) for eta > 0 (closed form; see the module docstring)."""
    x = 2.0 * eta
    q = np.exp(-x)
    s, c = np.sin(x), np.cos(x)
    den = -np.expm1(-2.0 * x) + 2.0 * q * s  # 2 q (sinh x + sin x)
    num = np.expm1(-x) ** 2 + 4.0 * q * np.sin(0.5 * x) ** 2  # 2 q (cosh x - cos x)
    one_q2 = -np.expm1(-2.0 * x)  # 1 - q^2
    rho = num / den
    d_rho = 8.0 * q * one_q2 * s / den**2  # d rho / d eta
    # d^2 rho / d eta^2 = 16 ((C s + S c)(S + s) - 2 S s (C + c)) / (S + s)^3, C, S of x
    bracket = (((1.0 + q * q) * s + one_q2 * c) * den
               - 2.0 * one_q2 * s * (1.0 + q * q + 2.0 * q * c))
    dd_rho = 16.0 * q * bracket / den**3
    one_phi = 1.0 - 0.75 * rho / eta - 0.25 * d_rho
    eta_dphi = 0.75 * rho / eta - 0.75 * d_rho - 0.25 * eta * dd_rho
    return one_phi, eta_dphi


def anticlastic_terms(eta: np.ndarray, nu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the anticlastic factor r(eta, nu) and its derivatives eta dr/deta and dr/dnu.

    Parameters
    ----------
    eta : array_like
        ``a (3 (1 - nu^2))^(1/4) sqrt(|kappa| / t)``, dimensionless (its sign is ignored).
    nu : float
        Poisson's ratio.

    Returns
    -------
    r, eta_dr_deta, dr_dnu : ndarray
        r = M / (EI kappa) (1), eta times its derivative in eta (1) and its derivative in nu at
        fixed eta (1).
    """
    e = np.abs(np.asarray(eta, dtype=float))
    small = e < _SERIES_ETA
    safe = np.where(small, 1.0, e)
    one_phi, eta_dphi = _phi(safe)
    e4 = e**4
    one_phi = np.where(small, 8.0 / 45.0 * e4, one_phi)
    eta_dphi = np.where(small, 32.0 / 45.0 * e4, eta_dphi)
    nu2 = nu * nu
    r = 1.0 + nu2 / (1.0 - nu2) * one_phi
    return r, nu2 / (1.0 - nu2) * eta_dphi, 2.0 * nu * one_phi / (1.0 - nu2) ** 2


def anticlastic_factor(eta: np.ndarray, nu: float) -> np.ndarray:
    """Return the moment ratio r = M / (EI kappa) of a bent free-edged plate strip.

    This is Ashwell's anticlastic restraint: 1 at eta = 0, rising to 1 / (1 - nu^2) as eta
    grows.

    Parameters
    ----------
    eta : array_like
        ``a (3 (1 - nu^2))^(1/4) sqrt(|kappa| / t)`` with a the half-width (m), kappa the curvature
        (1/m), t the thickness (m); dimensionless.
    nu : float
        Poisson's ratio.

    Returns
    -------
    ndarray
        r (1), the shape of ``eta``.
    """
    return anticlastic_terms(eta, nu)[0]


def eta_per_root_curvature(half_width_m: np.ndarray, thickness_m: float,
                           nu: float) -> np.ndarray:
    """Return ``eta / sqrt(|kappa|) = a (3 (1 - nu^2))^(1/4) / sqrt(t)``, in sqrt(m)."""
    return np.asarray(half_width_m) * (3.0 * (1.0 - nu * nu)) ** 0.25 / np.sqrt(thickness_m)


def section_curvature(moment_Nm: np.ndarray, ei_Nm2: np.ndarray, half_width_m: np.ndarray,
                      thickness_m: float, nu: float) -> np.ndarray:
    """Return the curvature kappa (1/m) with M = EI kappa r(eta(kappa)) for each section.

    Parameters
    ----------
    moment_Nm, ei_Nm2, half_width_m : ndarray
        Bending moment (N m), bending stiffness EI (N m^2) and half-width (m) of each section.
    thickness_m, nu : float
        Thickness (m) and Poisson's ratio.

    Returns
    -------
    ndarray
        kappa, 1/m.
    """
    m = np.asarray(moment_Nm, dtype=float)
    ei = np.asarray(ei_Nm2, dtype=float)
    k_eta = eta_per_root_curvature(half_width_m, thickness_m, nu)
    kappa = m / ei
    # Newton on EI kappa r - M, whose slope EI (r + eta r_eta / 2) stays near EI
    for _ in range(40):
        r, eta_dr, _ = anticlastic_terms(k_eta * np.sqrt(np.abs(kappa)), nu)
        new = kappa - (kappa * r - m / ei) / (r + 0.5 * eta_dr)
        done = np.max(np.abs(new - kappa), initial=0.0) <= 1e-13 * max(
            np.max(np.abs(new), initial=0.0), 1e-300)
        kappa = new
        if done:
            break
    return kappa


def section_state(moment_Nm: np.ndarray, ei_Nm2: np.ndarray, half_width_m: np.ndarray,
                  thickness_m: float, nu: float, anticlastic: bool
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return the curvature of each section under its moment and the anticlastic terms there.

    Parameters
    ----------
    moment_Nm, ei_Nm2, half_width_m : ndarray
        Bending moment (N m), bending stiffness EI (N m^2) and half-width (m) of each section.
    thickness_m, nu : float
        Thickness (m) and Poisson's ratio.
    anticlastic : bool
        With Ashwell's restraint (else r = 1 and its derivatives vanish).

    Returns
    -------
    kappa, r, eta_dr_deta, dr_dnu : ndarray
        Curvature (1/m) and ``anticlastic_terms`` at it (1); d kappa / d M at fixed section is
        1 / (EI (r + eta_dr_deta / 2)).
    """
    m = np.asarray(moment_Nm, dtype=float)
    if not anticlastic:
        kappa = m / ei_Nm2
        return kappa, np.ones_like(kappa), np.zeros_like(kappa), np.zeros_like(kappa)
    kappa = section_curvature(m, ei_Nm2, half_width_m, thickness_m, nu)
    eta = eta_per_root_curvature(half_width_m, thickness_m, nu) * np.sqrt(np.abs(kappa))
    return (kappa, *anticlastic_terms(eta, nu))
