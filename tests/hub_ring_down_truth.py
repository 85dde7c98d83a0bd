"""A free ring-down of the 1D beam truth on a hub, its E and rho scaled apart: calibration data.

Imported as ``from hub_ring_down_truth import ...``; not a test module.

The truth is computed for the beam with its material scaled (E -> s_E E, rho -> s_rho rho) and
put on the hub in Likins' hybrid coordinates (``truth.plant.hybrid_matrices``: the clamped
truth's modes, the hub's J_h unscaled). Its modes are the generalized eigenvectors of that
(K, M), solved here with scipy; the rigid rotation (lambda = 0) moves as a + b t, each flexible
mode rings with its own ratio, stepped by the matrix exponential of its 2 x 2 state space
(exact for a free linear system), not by the calibration's closed form.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.linalg as sla

__all__ = ["hub_truth", "hub_ring_down"]


def hub_truth(beam, s_E: float, s_rho: float, hub_inertia_kg_m2: float, radius_m: float,
              modes: int = 8):
    """Return the scaled truth's hybrid (M, K, Cq) on the hub (Cq rows: tip z, hub angle)."""
    from prbdm_pin.truth import compute_truth
    from prbdm_pin.truth.plant import hybrid_matrices, truth_modal_gains

    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * s_E,
                              rho_kg_m3=beam.material.rho_kg_m3 * s_rho)
    scaled = dataclasses.replace(beam, material=mat)
    truth = compute_truth(scaled, model="beam", modes=modes, static=False, error_tol_pct=None)
    M, K, _, Cq = hybrid_matrices(truth_modal_gains(truth, scaled), hub_inertia_kg_m2, radius_m)
    return M, K, Cq


def hub_ring_down(M, K, Cq, zeta, t_s, q0, v0, rates: bool = False) -> np.ndarray:
    """Return (N, 2) tip z and hub angle (with ``rates`` also their rates, (N, 4)).

    ``zeta`` the ratios of the len(zeta) lowest flexible modes (the others are not excited:
    their modal coordinates start at zero); ``q0``, ``v0`` the initial hybrid coordinates and
    rates (projected on the rigid mode and those flexible modes).
    """
    lam, Phi = sla.eigh(K, M)
    zeta = np.asarray(zeta, dtype=float)
    n = zeta.size
    eta0, deta0 = Phi.T @ M @ q0, Phi.T @ M @ v0  # modal coordinates (Phi^T M Phi = I)
    t = np.asarray(t_s, dtype=float)
    Q = np.outer(eta0[0] + deta0[0] * t, Phi[:, 0])  # the rigid rotation, undamped and free
    V = np.outer(np.full(t.size, deta0[0]), Phi[:, 0])
    dt = t[1] - t[0]  # uniform samples
    for k in range(1, n + 1):
        w = np.sqrt(lam[k])
        step = sla.expm(np.array([[0.0, 1.0], [-w**2, -2.0 * zeta[k - 1] * w]]) * dt)
        x = np.array([eta0[k], deta0[k]])
        X = np.empty((t.size, 2))
        for i in range(t.size):
            X[i] = x
            x = step @ x
        Q += np.outer(X[:, 0], Phi[:, k])
        V += np.outer(X[:, 1], Phi[:, k])
    y = Q @ Cq.T
    return np.hstack([y, V @ Cq.T]) if rates else y
