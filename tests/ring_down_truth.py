"""A free ring-down of the clamped 1D beam truth with its E and rho scaled: calibration data.

Imported as ``from ring_down_truth import ...``; not a test module.

The truth's modes are mass-normalised eigenvectors of its FE matrices (K from E, M from rho).
With E -> s_E E and rho -> s_rho rho, K -> s_E K and M -> s_rho M, so omega_k^2 -> omega_k^2
s_E / s_rho and the mass-normalised shapes phi_k -> phi_k / sqrt(s_rho): the tip reads
c_k / sqrt(s_rho) per modal coordinate. The response is stepped with the matrix exponential of
the modal state space (exact for a free linear system), not with the calibration's closed form.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

__all__ = ["truth_ring_down"]


def truth_ring_down(plant, s_E: float, s_rho: float, zeta, t_s: np.ndarray,
                    eta0: np.ndarray, rates: bool = False) -> np.ndarray:
    """Return the tip z (and, with ``rates``, its rate) of the scaled truth's first modes.

    ``plant`` a ClampedModel; ``zeta`` the ratio of each of the len(zeta) lowest modes;
    ``eta0`` their initial modal coordinates and rates (2 n,), sqrt(kg) m and per s.
    """
    zeta = np.asarray(zeta, dtype=float)
    n = zeta.size
    w = np.asarray(plant.frequencies_rad_s[:n]) * np.sqrt(s_E / s_rho)
    c = np.asarray(plant.output_matrix[0, :n]) / np.sqrt(s_rho)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(w**2), -np.diag(2 * zeta * w)]])
    dt = t_s[1] - t_s[0]  # uniform samples
    step = sla.expm(A * dt)
    x = np.array(eta0, dtype=float)
    X = np.empty((t_s.size, 2 * n))
    for i in range(t_s.size):
        X[i] = x
        x = step @ x
    tip = X[:, :n] @ c
    return np.column_stack([tip, X[:, n:] @ c]) if rates else tip[:, None]
