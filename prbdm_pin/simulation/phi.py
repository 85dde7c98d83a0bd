"""The phi functions phi_1, phi_2, phi_3 of exponential integrators, for complex arguments."""

from __future__ import annotations

import math

import numpy as np

# Taylor coefficients 1 / (m + k)! of phi_k, k = 1, 2, 3, highest power first (Horner)
_PHI_TAYLOR = [[1.0 / math.factorial(m + k) for m in range(9, -1, -1)] for k in (1, 2, 3)]


def phi123(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """phi_1, phi_2, phi_3 of complex ``z`` (elementwise): phi_k(z) = sum_m z^m / (m + k)!.

    Taylor series (10 terms: truncation below 1e-16) for ``|z| < 0.1``; elsewhere the recurrence
    phi_{k+1} = (phi_k - 1/k!) / z, whose cancellation costs at most ``eps / |z|^3`` ~ 2e-13.
    """
    small = np.abs(z) < 0.1
    zb = np.where(small, 1.0, z)
    p1 = (np.exp(zb) - 1.0) / zb
    p2 = (p1 - 1.0) / zb
    p3 = (p2 - 0.5) / zb
    if small.any():
        zs = z[small]
        for p, coef in zip((p1, p2, p3), _PHI_TAYLOR, strict=True):
            acc = np.full(zs.shape, coef[0], dtype=complex)
            for c in coef[1:]:
                acc = acc * zs + c
            p[small] = acc
    return p1, p2, p3
