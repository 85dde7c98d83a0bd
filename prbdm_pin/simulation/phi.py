"""The phi functions phi_1 ... phi_4 of exponential integrators, for complex arguments."""

from __future__ import annotations

import math

import numpy as np


def _taylor(terms: int) -> list[list[float]]:
    """Taylor coefficients 1 / (m + k)! of phi_k, k = 1 ... 4, highest power first (Horner)."""
    return [[1.0 / math.factorial(m + k) for m in range(terms - 1, -1, -1)] for k in (1, 2, 3, 4)]


_PHI_TAYLOR_10 = _taylor(10)
# phi_1 ... phi_4's Taylor coefficients by ascending power, one column per function
_TAYLOR_18 = np.array(_taylor(18))[:, ::-1].T.astype(complex)
_POWERS_18 = np.arange(18)


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
        for p, coef in zip((p1, p2, p3), _PHI_TAYLOR_10, strict=False):
            acc = np.full(zs.shape, coef[0], dtype=complex)
            for c in coef[1:]:
                acc = acc * zs + c
            p[small] = acc
    return p1, p2, p3


def phi1234(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """phi_1 ... phi_4 of complex ``z`` (elementwise), as :func:`phi123`.

    Taylor series for ``|z| < 0.5`` (18 terms: truncation below 1e-22), summed as one matrix
    product of the powers; elsewhere the recurrence, whose cancellation in phi_4 costs at most
    ``eps / |z|^4`` ~ 3.6e-15.
    """
    z = np.asarray(z, dtype=complex)
    small = np.abs(z) < 0.5
    zb = np.where(small, 1.0, z)
    p1 = (np.exp(zb) - 1.0) / zb
    p2 = (p1 - 1.0) / zb
    p3 = (p2 - 0.5) / zb
    p4 = (p3 - 1.0 / 6.0) / zb
    if small.any():
        series = np.power.outer(z[small], _POWERS_18) @ _TAYLOR_18
        for k, p in enumerate((p1, p2, p3, p4)):
            p[small] = series[..., k]
    return p1, p2, p3, p4
