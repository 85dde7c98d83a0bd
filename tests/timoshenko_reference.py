"""Closed-form clamped-free Timoshenko beam frequencies, independent of the package.

The uniform beam's equations kappa G A (w'' - psi') + rho A w^2 w = 0 and
E I psi'' + kappa G A (w' - psi) + rho I w^2 psi = 0 have, below the cut-off
omega_c = sqrt(kappa G A / (rho I)), the solutions cosh, sinh (alpha x) and cos, sin (beta x)
with alpha^2, -beta^2 the roots mu of

    kappa G A E I mu^2 + omega^2 (kappa G A rho I + rho A E I) mu + rho A omega^2 (rho I omega^2
    - kappa G A) = 0

(Huang 1961; Han, Benaroya & Wei 1999, J. Sound Vib. 225, 935-988, Sec. 6). The clamped root
(w = psi = 0) and the free tip (E I psi' = 0, kappa G A (w' - psi) = 0) make a 4 x 4 determinant
whose zeros in omega are the frequencies; brentq finds them between the sign changes of a scan.
Imported as ``from timoshenko_reference import ...``.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from tolerances import ROOT_RTOL

__all__ = ["timoshenko_cantilever_omega", "first_order_coefficients"]


def _det(omega: float, L: float, EI: float, kGA: float, rA: float, rI: float) -> float:
    w2 = omega * omega
    a2 = kGA * EI
    b1 = w2 * (kGA * rI + rA * EI)
    c0 = rA * w2 * (rI * w2 - kGA)
    disc = np.sqrt(b1 * b1 - 4.0 * a2 * c0)
    alpha = np.sqrt((-b1 + disc) / (2.0 * a2))
    beta = np.sqrt((b1 + disc) / (2.0 * a2))
    p = (kGA * alpha**2 + rA * w2) / (kGA * alpha)
    q = (rA * w2 - kGA * beta**2) / (kGA * beta)
    ch, sh = np.cosh(alpha * L), np.sinh(alpha * L)
    c, s = np.cos(beta * L), np.sin(beta * L)
    A = np.array([
        [1.0, 0.0, 1.0, 0.0],                                     # w(0) = 0
        [0.0, p, 0.0, -q],                                        # psi(0) = 0
        [p * alpha * ch, p * alpha * sh, q * beta * c, q * beta * s],   # psi'(L) = 0
        [(alpha - p) * sh, (alpha - p) * ch, -(beta + q) * s, (beta + q) * c],  # w' - psi = 0
    ])
    # scaled by the growing cosh so that the scan's sign changes are not lost to overflow
    return float(np.linalg.det(A)) / ch


def timoshenko_cantilever_omega(L: float, EI: float, kGA: float, rA: float, rI: float,
                                n: int) -> np.ndarray:
    """The n lowest frequencies (rad/s) of the uniform clamped-free Timoshenko beam."""
    cutoff = np.sqrt(kGA / rI)
    # the Euler-Bernoulli frequencies lie above them; scan up to past the n-th one
    top = ((n + 0.5) * np.pi / L) ** 2 * np.sqrt(EI / rA)
    top = min(top, cutoff * (1.0 - 1e-9))
    grid = np.linspace(top * 1e-4, top, 4000 * n)
    vals = np.array([_det(w, L, EI, kGA, rA, rI) for w in grid])
    idx = np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0.0)
    roots = [brentq(_det, grid[i], grid[i + 1], args=(L, EI, kGA, rA, rI), xtol=1e-300,
                    rtol=ROOT_RTOL) for i in idx[:n]]
    if len(roots) < n:
        raise ValueError(f"found {len(roots)} roots below {top:.6g} rad/s, asked {n}")
    return np.array(roots)


def first_order_coefficients(n: int) -> np.ndarray:
    """c_k = int phi'^2 / int phi^2 (L = 1) of the Euler-Bernoulli cantilever modes k = 1..n,
    by quadrature of the closed-form modes (equal to int phi'''^2 / int phi''^2)."""
    from scipy.integrate import quad

    out = []
    for k in range(1, n + 1):
        g = (k - 0.5) * np.pi
        b = brentq(lambda x: np.cos(x) * np.cosh(x) + 1.0, g - 0.5, g + 0.5, xtol=1e-300,
                   rtol=ROOT_RTOL)
        s = (np.cosh(b) + np.cos(b)) / (np.sinh(b) + np.sin(b))

        def phi(x, b=b, s=s):
            return np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))

        def dphi(x, b=b, s=s):
            return b * (np.sinh(b * x) + np.sin(b * x) - s * (np.cosh(b * x) - np.cos(b * x)))

        num = quad(lambda x: dphi(x) ** 2, 0.0, 1.0, limit=200)[0]
        den = quad(lambda x: phi(x) ** 2, 0.0, 1.0, limit=200)[0]
        out.append(num / den)
    return np.array(out)
