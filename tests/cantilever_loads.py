"""Closed-form and independently computed references for a uniform cantilever under loads.

Imported as ``from cantilever_loads import ...`` (pytest puts this folder on ``sys.path``); not
a test module. Nothing here uses the package: Euler-Bernoulli formulas, the chain polygon of an
end moment worked out by hand, the clamped-free modal sum, and the elastica under self weight
by shooting (scipy's solve_ivp and brentq).
"""

from __future__ import annotations

import numpy as np
from reference import BETA_L
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from tolerances import REFERENCE_ATOL, REFERENCE_RTOL, ROOT_RTOL

__all__ = ["strip_properties", "equal_lengths", "polygon_arc_tip", "arc_tip",
           "partial_load_tip", "base_transmissibility", "elastica_self_weight"]


def strip_properties(beam) -> tuple[float, float, float]:
    """Return (L m, EI N m^2, rho A kg/m) of a uniform rectangular strip."""
    b, t = 2.0 * float(beam.half_width_m[0]), float(beam.thickness_m)
    return (float(beam.length_m), beam.material.E_Pa * b * t**3 / 12.0,
            beam.material.rho_kg_m3 * b * t)


def equal_lengths(L: float, n: int) -> np.ndarray:
    """n joints on equal links of L / n, the two end links half as long (m)."""
    return np.r_[0.5, np.ones(n - 1), 0.5] * L / n


def arc_tip(L: float, phi: float) -> np.ndarray:
    """Tip (x, z) of the continuum rolled by an end moment through the angle phi (rad) up."""
    return L * np.array([np.sin(phi) / phi, (1.0 - np.cos(phi)) / phi])


def polygon_arc_tip(L: float, n: int, phi: float) -> np.ndarray:
    """Tip (x, z) of the chain of :func:`equal_lengths` with every joint turned by phi / n.

    Link j points at the angle j theta (theta = phi / n); the links are h/2, h, ..., h, h/2
    (h = L / n), so the tip is h times the trapezoid sum of e^(i j theta), j = 0..n, which
    sums to (e^(i phi) - 1) (-i / 2) cot(theta / 2): the continuum's arc scaled by
    (theta / 2) cot(theta / 2).
    """
    theta = phi / n
    return arc_tip(L, phi) * (0.5 * theta / np.tan(0.5 * theta))


def partial_load_tip(L: float, EI: float, q: float, a: float, b: float) -> float:
    """Tip deflection (m, along the load) of a cantilever under q N/m over [a, b] (linear).

    The load over [0, c] deflects the tip by q c^3 (4 L - c) / (24 EI); [a, b] is the
    difference of [0, b] and [0, a].
    """
    def inner(c):
        return q * c**3 * (4.0 * L - c) / (24.0 * EI)
    return inner(b) - inner(a)


def _modes(L: float, EI: float, rhoA: float, n: int):
    """Clamped-free modes: omega (rad/s), tip value and int rho A phi dx of mass-normalised
    shapes, (n,) each. Roots beyond the sixth from their asymptote (2 r - 1) pi / 2 (off by
    e^(-beta L), below 1e-9 from the seventh on)."""
    r = np.arange(1, n + 1)
    bl = np.where(r <= BETA_L.size, np.r_[BETA_L, np.zeros(max(0, n - BETA_L.size))][:n],
                  (2 * r - 1) * np.pi / 2)
    beta = bl / L
    omega = bl**2 * np.sqrt(EI / (rhoA * L**4))
    a = 1.0 / np.sqrt(rhoA * L)
    tip = np.empty(n)
    integral = np.empty(n)
    for i, x in enumerate(bl):
        if x < 20.0:  # cosh and sinh cancel beyond: take the limit forms (sigma -> 1)
            sigma = (np.cosh(x) + np.cos(x)) / (np.sinh(x) + np.sin(x))
            tip[i] = a * (np.cosh(x) - np.cos(x) - sigma * (np.sinh(x) - np.sin(x)))
            integral[i] = a * (np.sinh(x) - np.sin(x) - sigma * (np.cosh(x) + np.cos(x) - 2.0))
        else:
            tip[i] = 2.0 * a * (-1.0) ** (i + 2)  # (-1)^(r + 1)
            integral[i] = 2.0 * a
        integral[i] /= beta[i]
    return omega, tip, rhoA * integral


def base_transmissibility(L: float, EI: float, rhoA: float, omega_rad_s: np.ndarray,
                          zeta: float = 0.0, n_modes: int = 400) -> np.ndarray:
    """Tip displacement relative to the base per base acceleration, m per m/s^2, complex.

    rho A w_rel'' + EI w_rel'''' = -rho A a: the relative tip is -sum_r phi_r(L) Gamma_r a /
    (omega_r^2 - omega^2 + 2 i zeta omega_r omega), Gamma_r = int rho A phi_r dx (the
    participation factor of mass-normalised modes). The terms fall as 1 / r^3 at a fixed
    frequency: 400 modes leave ~1e-8 of the DC value (-rho A L^4 / (8 EI)).
    """
    om, tip, gam = _modes(L, EI, rhoA, n_modes)
    w = np.atleast_1d(np.asarray(omega_rad_s, dtype=float))[:, None]
    return -np.sum(tip * gam / (om**2 - w**2 + 2j * zeta * om * w), axis=1)


def elastica_self_weight(L: float, EI: float, q: float) -> np.ndarray:
    """Tip (x, z) of the inextensible elastica of a cantilever under q N/m (per length) down.

    theta(s) the tangent's angle below x: x' = cos theta, z' = -sin theta, EI theta' = M with
    M' = -q (L - s) cos theta (the weight beyond s), theta(0) = 0 and M(L) = 0; shooting on
    theta'(0) with brentq, solve_ivp (DOP853, rtol 1e-12).
    """
    def rhs(s, y):
        th, k, x, z = y
        return [k, -q * (L - s) * np.cos(th) / EI, np.cos(th), -np.sin(th)]

    def shoot(k0):
        # the reference's own accuracy (integrator and root tolerances, not comparison bounds):
        # far below the 1e-3 L the chain is compared at
        sol = solve_ivp(rhs, (0.0, L), [0.0, k0, 0.0, 0.0], method="DOP853",
                        rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL)
        return sol.y[:, -1]

    # the linear root curvature: the large deflection's is less (theta'(L) >= 0 there); step
    # down from it to the first theta'(L) < 0 (a small start curls the strip up past the
    # vertical under a heavy load, so 0 does not bracket)
    hi = q * L**2 / (2.0 * EI)
    lo = 0.8 * hi
    while shoot(lo)[1] >= 0.0:
        hi, lo = lo, 0.8 * lo
    k0 = brentq(lambda k: shoot(k)[1], lo, hi, xtol=1e-14, rtol=ROOT_RTOL)
    end = shoot(k0)
    return np.array([end[2], end[3]])
