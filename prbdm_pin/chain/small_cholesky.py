"""A compiled Cholesky solve of a small symmetric positive definite system (numba).

The one factorisation the compiled chain dynamics (:mod:`prbdm_pin.kernel.dynamics`) solve
M a = f with (the batched planar kernel, :mod:`.planar_batch_kernel`, solves many designs side
by side with its own L D L^T, the designs innermost): for the n <= 16
coordinates of a chain, a loop written out costs less than a LAPACK call's overhead from
compiled code, and it reports a matrix that is not positive definite instead of raising.
Imported on first use only (the package's import and the CLI do not load numba).
"""

from __future__ import annotations

import math

import numba

__all__ = ["cholesky_solve", "cholesky_substitute"]


@numba.njit(cache=True)
def cholesky_solve(M, L, b, out):
    """Solve M x = b (M symmetric positive definite) by its Cholesky factor L; False if not SPD."""
    n = b.size
    for j in range(n):
        s = M[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            return False
        d = math.sqrt(s)
        L[j, j] = d
        for i in range(j + 1, n):
            s = M[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / d
    cholesky_substitute(L, b, out)
    return True


@numba.njit(cache=True)
def cholesky_substitute(L, b, out):
    """Solve L L^T x = b into ``out`` by the factor L of :func:`cholesky_solve` (lower).

    A further right-hand side of the same matrix, without factoring it again.
    """
    n = b.size
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * out[k]
        out[i] = s / L[i, i]
    for i in range(n - 1, -1, -1):
        s = out[i]
        for k in range(i + 1, n):
            s -= L[k, i] * out[k]
        out[i] = s / L[i, i]
