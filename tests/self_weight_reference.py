"""Independent references for a uniform cantilever under its own weight (test helper).

Written from the equations, without the package's finite elements or collocation:

* :func:`ritz_frequencies`: Rayleigh-Ritz on EI w'''' - (N(x) w')' + rho A w_tt = 0 with
  N(x) = g_x rho A (L - x) (tension for g_x > 0, the member hanging from its root), over the
  polynomials (x / L)^2 ... (x / L)^(n+1), which meet the clamped root; every integral in
  closed form (monomials). Upper bounds that converge from above as n grows.
* :func:`shoot_self_weight`: the inextensible elastica under its distributed weight and a dead
  tip force, by shooting on the root moment (``solve_ivp`` and ``brentq``): the internal force
  at arc length s is known, n(s) = F + rho A g (L - s), so M(0) is the only unknown.
* :data:`GREENHILL`: the standing uniform column buckles at rho A g L^3 / EI = (9/4) j^2, j the
  first zero of J_{-1/3} (Greenhill 1881; Timoshenko and Gere, Theory of Elastic Stability,
  2nd ed., section 2.13: 7.837).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import jv
from tolerances import EPS, REFERENCE_ATOL, REFERENCE_RTOL

__all__ = ["ritz_frequencies", "ritz_planform_frequencies", "shoot_self_weight", "GREENHILL",
           "GREENHILL_PUBLISHED"]

GREENHILL_PUBLISHED = 7.837  # Timoshenko and Gere, 4 digits
GREENHILL = 2.25 * brentq(lambda x: jv(-1.0 / 3.0, x), 1.0, 3.0, xtol=1e-15) ** 2


def ritz_frequencies(EI: float, rhoA: float, L: float, g_x: float, n_terms: int = 8,
                     n_modes: int = 3) -> np.ndarray:
    """Lowest ``n_modes`` frequencies (rad/s) of the prestressed uniform cantilever, Ritz."""
    a = np.arange(2, n_terms + 2, dtype=float)[:, None]
    b = a.T
    bend = a * (a - 1) * b * (b - 1) / (a + b - 3)  # int phi_i'' phi_j'' d xi
    geo = a * b * (1.0 / (a + b - 1) - 1.0 / (a + b))  # int (1 - xi) phi_i' phi_j' d xi
    mass = 1.0 / (a + b + 1)  # int phi_i phi_j d xi
    K = EI / L**3 * bend + g_x * rhoA * geo
    M = rhoA * L * mass
    lam = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[0, n_modes - 1])
    return np.sqrt(lam)


def ritz_planform_frequencies(x_m, half_width_m, t_m: float, E_Pa: float, rho: float,
                              g_x: float, tip_tension_N: float = 0.0, n_terms: int = 10,
                              n_modes: int = 2) -> np.ndarray:
    """Ritz frequencies (rad/s) of a clamped strip with a piecewise-linear half-width w(x).

    EI = E 2 w t^3 / 12, rho A = rho 2 w t, N(x) = g_x int_x^L rho A + tip tension; the same
    polynomials as :func:`ritz_frequencies`, every integral by Gauss-Legendre on each vertex
    interval (degree <= 2 (n+1) + 2 there: 2 n_terms points are exact).
    """
    x_m, w_m = np.asarray(x_m, float), np.asarray(half_width_m, float)
    L = x_m[-1]
    a = np.arange(2, n_terms + 2, dtype=float)
    gx, gw = np.polynomial.legendre.leggauss(2 * n_terms)
    K = np.zeros((n_terms, n_terms))
    M = np.zeros_like(K)
    # outboard mass at each vertex (trapezoids: exact for linear w), summed from the tip
    seg = rho * t_m * (w_m[:-1] + w_m[1:]) * np.diff(x_m)
    tail = np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])
    for i in range(x_m.size - 1):
        x0, x1 = x_m[i], x_m[i + 1]
        if x1 <= x0:
            continue  # a width step
        x = 0.5 * (x1 - x0) * gx + 0.5 * (x0 + x1)
        wq = 0.5 * (x1 - x0) * gw
        w = w_m[i] + (w_m[i + 1] - w_m[i]) * (x - x0) / (x1 - x0)
        N = g_x * (rho * t_m * (w + w_m[i + 1]) * (x1 - x) + tail[i + 1]) + tip_tension_N
        xi = x / L
        phi = xi[None] ** a[:, None]
        d1 = a[:, None] * xi[None] ** (a[:, None] - 1) / L
        d2 = a[:, None] * (a[:, None] - 1) * xi[None] ** (a[:, None] - 2) / L**2
        K += (d2 * (E_Pa * 2 * w * t_m**3 / 12 * wq)) @ d2.T + (d1 * (N * wq)) @ d1.T
        M += (phi * (rho * 2 * w * t_m * wq)) @ phi.T
    lam = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[0, n_modes - 1])
    return np.sqrt(lam)


def shoot_self_weight(EI: float, rhoA: float, L: float, g, F=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Tip position (x, 0, z), m, of the uniform elastica under its weight and a tip force."""
    g, F = np.asarray(g, float), np.asarray(F, float)

    def rhs(s, y):
        nx = F[0] + rhoA * g[0] * (L - s)
        nz = F[2] + rhoA * g[2] * (L - s)
        return [y[1] / EI, nx * np.sin(y[0]) - nz * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])]

    def run(m0):
        # the integrator's request (not a comparison bound: tests/tolerances.py), the
        # shooting reference's accuracy, below what the truth is compared at
        return solve_ivp(rhs, (0.0, L), [0.0, m0, 0.0, 0.0], rtol=REFERENCE_RTOL,
                         atol=REFERENCE_ATOL, method="DOP853")

    # the root moment lies between 0 and the straight member's |M(0)|, times a margin
    m_lin = abs(F[2]) * L + abs(rhoA * g[2]) * L**2 / 2.0 + abs(F[0]) * L
    lo, hi = -2.0 * m_lin - 1e-12, 2.0 * m_lin + 1e-12
    m0 = brentq(lambda m: run(m).y[1, -1], lo, hi, xtol=1e-14 * max(m_lin, 1.0), rtol=4 * EPS)
    y = run(m0).y[:, -1]
    return np.array([y[2], 0.0, y[3]])
