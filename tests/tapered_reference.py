"""References for members of varying section, independent of the package.

Kirchhoff's Bessel-function solutions for a complete taper (a wedge tapering to an edge, a cone
to a point) and a self-contained cubic-Hermite FE (numpy, Gauss quadrature exact for the
polynomial laws) with Richardson extrapolation for partial tapers.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from scipy.optimize import brentq
from scipy.special import iv, jv
from tolerances import ROOT_RTOL


def complete_taper_lambda1(order: int) -> float:
    """lambda_1 = omega L^2 sqrt(rho A_0 / (E I_0)) of a clamped complete taper.

    ``order`` 1: a wedge (A ~ xi, I ~ xi^3 from the tip), root of J_1 I_2 + I_1 J_2 = 0;
    2: a cone (A ~ xi^2, I ~ xi^4), root of J_2 I_3 + I_2 J_3 = 0; lambda = (z / 2)^2
    (Kirchhoff; Conway, Becker & Dubil; Blevins: 5.315 and 8.719).
    """
    n = int(order)

    def f(z):
        return jv(n, z) * iv(n + 1, z) + iv(n, z) * jv(n + 1, z)

    lo, hi = {1: (3.0, 6.0), 2: (5.0, 6.5)}[n]  # brackets of the first root only
    z = brentq(f, lo, hi, xtol=1e-15, rtol=ROOT_RTOL)
    return (z / 2.0) ** 2


def _hermite_element(h: float):
    """Gauss points (on [0, 1]), weights and the shape functions' values and 2nd derivatives."""
    g, wg = np.polynomial.legendre.leggauss(6)  # exact to degree 11: the quartic EI and more
    s = 0.5 * (g + 1.0)
    wg = 0.5 * wg * h
    N = np.array([1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3,
                  h * (-s**2 + s**3)])
    B = np.array([-6 + 12 * s, h * (-4 + 6 * s), 6 - 12 * s, h * (-2 + 6 * s)]) / h**2
    return s, wg, N, B


def hermite_lambda1(ratio: float, power: int, n: int) -> float:
    """lambda_1 of a clamped-free member with A ~ r(x), I ~ r(x)^(power + 1) ... see below.

    The section scale r(x) = 1 - (1 - ratio) x / L (x from the root, L = 1) gives
    A = A_0 r^power and I = I_0 r^(power + 2): power 1 is a thickness taper at constant width
    (A ~ t, I ~ t^3), power 2 a cone (A ~ D^2, I ~ D^4). ``n`` equal elements.
    """
    L = 1.0
    h = L / n
    s, wg, N, B = _hermite_element(h)
    K = np.zeros((2 * n + 2, 2 * n + 2))
    M = np.zeros_like(K)
    for e in range(n):
        x = (e + s) * h
        r = 1.0 - (1.0 - ratio) * x / L
        ei, ra = r ** (power + 2), r**power
        d = slice(2 * e, 2 * e + 4)
        K[d, d] += (B * ei * wg) @ B.T
        M[d, d] += (N * ra * wg) @ N.T
    # the largest mu of M phi = mu K phi: K phi = lam M phi loses ~EPS lam_max / lam_1 to
    # rounding on the lowest mode (1e-5 at 400 elements), the inverse problem does not
    m = K.shape[0] - 3
    mu = scipy.linalg.eigh(M[2:, 2:], K[2:, 2:], eigvals_only=True, subset_by_index=[m, m])
    return float(np.sqrt(1.0 / mu[0]) * L**2)


def richardson_lambda1(ratio: float, power: int, n: int = 100) -> tuple[float, float]:
    """Richardson-extrapolated lambda_1 from n and 2n elements (error O(h^4)) and its estimate.

    Returns (lambda_1, |extrapolated - finest|), the latter a bound on the remaining error.
    """
    a, b = hermite_lambda1(ratio, power, n), hermite_lambda1(ratio, power, 2 * n)
    ext = b + (b - a) / 15.0
    return ext, abs(ext - b)
