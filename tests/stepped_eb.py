"""Exact Euler-Bernoulli references for a two-segment clamped-free cantilever, independent of the
package: EI_1, rho A_1 on [0, a] and EI_2, rho A_2 on [a, L]."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from tolerances import EPS


def _basis(beta: float, x: float) -> np.ndarray:
    """Rows: w, w', w'', w''' of (cos, sin, cosh, sinh)(beta x)."""
    c, s, ch, sh = np.cos(beta * x), np.sin(beta * x), np.cosh(beta * x), np.sinh(beta * x)
    b = beta
    return np.array([
        [c, s, ch, sh],
        [-b * s, b * c, b * sh, b * ch],
        [-b**2 * c, -b**2 * s, b**2 * ch, b**2 * sh],
        [b**3 * s, -b**3 * c, b**3 * sh, b**3 * ch],
    ])


def stepped_determinant(omega: float, a: float, L: float, EI1: float, rA1: float, EI2: float,
                        rA2: float) -> float:
    """det of the 8x8 system: clamp (w, w' at 0), continuity of w, w', EI w'', (EI w'')' at a,
    free end (w'', w''' at L); segment 2 in the local coordinate x - a. Rows are scaled so the
    determinant stays finite."""
    b1 = (omega**2 * rA1 / EI1) ** 0.25
    b2 = (omega**2 * rA2 / EI2) ** 0.25
    A = np.zeros((8, 8))
    B0 = _basis(b1, 0.0)
    A[0, :4], A[1, :4] = B0[0], B0[1]
    Ba, C0 = _basis(b1, a), _basis(b2, 0.0)
    for r, (s1, s2) in enumerate(((1.0, 1.0), (1.0, 1.0), (EI1, EI2), (EI1, EI2))):
        A[2 + r, :4] = s1 * Ba[r]
        A[2 + r, 4:] = -s2 * C0[r]
    CL = _basis(b2, L - a)
    A[6, 4:], A[7, 4:] = CL[2], CL[3]
    A /= np.abs(A).max(axis=1, keepdims=True)
    return float(np.linalg.det(A))


def stepped_frequencies(n: int, a: float, L: float, EI1: float, rA1: float, EI2: float,
                        rA2: float) -> np.ndarray:
    """The lowest ``n`` natural frequencies (rad/s): sign changes of the determinant on a fine
    grid, each refined by brentq."""
    # uniform cantilevers have beta_n L ~ (n - 1/2) pi; a step shifts them by tens of percent
    c = np.sqrt(max(EI1 / rA1, EI2 / rA2))
    grid = np.linspace(0.2 * (1.875 / L) ** 2 * np.sqrt(min(EI1 / rA1, EI2 / rA2)),
                       3.0 * ((n + 0.5) * np.pi / L) ** 2 * c, 20000)
    f = [stepped_determinant(w, a, L, EI1, rA1, EI2, rA2) for w in grid]
    out = []
    for i in range(grid.size - 1):
        if np.sign(f[i]) != np.sign(f[i + 1]):
            # rtol: 45 EPS (1e-14), above brentq's floor (4 EPS), far below the 1e-6 the tests
            # compare these roots at
            out.append(brentq(stepped_determinant, grid[i], grid[i + 1],
                              args=(a, L, EI1, rA1, EI2, rA2), xtol=1e-14, rtol=45 * EPS))
            if len(out) == n:
                break
    return np.array(out)


def stepped_tip_compliance(a: float, L: float, EI1: float, EI2: float) -> float:
    """Linear tip deflection per unit tip force, m/N: the integral of (L - x)^2 / EI(x)."""
    seg1 = ((L**3) - (L - a) ** 3) / (3.0 * EI1)
    seg2 = (L - a) ** 3 / (3.0 * EI2)
    return seg1 + seg2
