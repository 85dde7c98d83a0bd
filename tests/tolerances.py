"""Tolerances of the checks at rounding level, each derived from machine epsilon and a
conditioning figure of what it checks.

Imported as ``from tolerances import ...`` (pytest puts this folder on ``sys.path``, as for
``reference``); not a test module, so test modules share it without importing each other.

A result computed in double precision is off by about EPS times the condition number of what
computes it: for a sum, the number of terms times the largest term over the result; for an
eigenvalue, the spread of the spectrum; for a linear solve, the matrix's condition number. The
order of those roundings is the BLAS kernel's choice (``OPENBLAS_CORETYPE``), so a bound at the
last bits one machine produced fails on another: each bound here is the first-order figure times
a small multiplier for the constants that figure drops.

Where a test's bound was already wider than that, it was kept, not tightened, written in EPS and
rounded up: 1e-15, 1e-14, 1e-13 and 1e-12 became 5, 50, 500 and 5000 EPS, and the comment beside
it gives the figure and says "kept". A check exact by construction (the same arithmetic on both
sides, a structural zero, a lossless round trip through a file) says so; its bound is slack,
kept the same way. A solver's own precision request (quadrature, integrator, root finder) is
written in EPS at its old value (450 EPS for 1e-13).
"""

from __future__ import annotations

import numpy as np

__all__ = ["EPS", "REFERENCE_ATOL", "REFERENCE_RTOL", "ROOT_RTOL", "eig_rtol",
           "hermite_basis_cond"]

EPS = float(np.finfo(float).eps)  # 2.2e-16: one rounding, relative
# What an independent reference asks of its own solvers (not a comparison bound): an
# integrator's relative and absolute error per step, 4500 and 45 EPS (1e-12 and 1e-14), and a
# scalar root's, 8 EPS (twice brentq's floor of 4 EPS). Each reference is then accurate to a few
# thousand roundings, far inside the bounds the package is compared at (1e-9 and wider).
REFERENCE_RTOL = 4500 * EPS
REFERENCE_ATOL = 45 * EPS
ROOT_RTOL = 8 * EPS


def eig_rtol(omega: np.ndarray) -> float:
    """Relative tolerance on the frequencies w of one pencil K phi = w^2 M phi between two of
    its solves, one of which is ill-conditioned for some modes (an unscaled solve for the lowest
    w, a scaled one for the highest).

    LAPACK bounds every eigenvalue's error by p(n) EPS |lambda_max| with p(n) a modest function
    of the dimension (taken as n), so the w^2 at the other end of the spectrum is good to
    n EPS (w_max / w_min)^2 relative and w = sqrt(w^2) to half that. Zero frequencies (a rigid
    mode) are left out of the spread.
    """
    w = np.abs(np.asarray(omega, dtype=float)).ravel()
    n = w.size
    w = w[w > 0.0]
    return 0.5 * n * EPS * float(w.max() / w.min()) ** 2


def hermite_basis_cond(stations_m: np.ndarray) -> float:
    """Largest 2-norm condition number of the cubic Hermite elements' Vandermonde matrices
    (value and slope of 1, x, x^2, x^3 at both ends) on the mesh ``stations_m``, in global
    coordinates.

    scikit-fem's ``ElementLineHermite`` (an ``ElementGlobal``) builds each element's basis by
    inverting this matrix, so every entry of the finite-element mass and stiffness matrices
    carries a relative error of up to EPS times this figure (5.8e8 for 200 elements on [0, 1]
    m: 1.3e-7), which moves the beam truth's frequencies and statics by as much.
    """
    x = np.asarray(stations_m, dtype=float)
    a, b = x[:-1], x[1:]
    one, zero = np.ones_like(a), np.zeros_like(a)
    V = np.stack([np.stack([one, a, a**2, a**3], -1), np.stack([zero, one, 2 * a, 3 * a**2], -1),
                  np.stack([one, b, b**2, b**3], -1), np.stack([zero, one, 2 * b, 3 * b**2], -1)],
                 axis=1)
    return float(np.linalg.cond(V).max())
