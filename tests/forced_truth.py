"""An FRF and a driven trajectory of the clamped 1D beam truth with its E and rho scaled.

Imported as ``from forced_truth import ...``; not a test module.

The truth's modes are mass-normalised eigenvectors of its FE matrices. With E -> s_E E and
rho -> s_rho rho, omega_k^2 -> omega_k^2 s_E / s_rho and phi_k -> phi_k / sqrt(s_rho): the tip
reads c_k / sqrt(s_rho) per modal coordinate, a tip force drives mode k with b_k / sqrt(s_rho),
and the clamp's acceleration (the d'Alembert load -rho t a, proportional to rho) with
b_k sqrt(s_rho). The FRF is C (i omega I - A)^-1 B of that modal state space, solved at each
frequency; the trajectory is scipy's zero-order-hold discretisation of it (``cont2discrete``,
one matrix exponential of the whole system) stepped by ``dlsim``: neither is the calibration's
per-mode sum or per-mode recursion.
"""

from __future__ import annotations

import numpy as np
import scipy.signal as ss

__all__ = ["truth_state_space", "truth_frf", "truth_driven"]


def truth_state_space(plant, s_E: float, s_rho: float, zeta, inputs):
    """Return A, B, C (rows tip z, tip z rate) of the scaled truth's len(zeta) lowest modes.

    ``plant`` a ClampedModel; ``inputs`` names from its ``input_names``.
    """
    zeta = np.asarray(zeta, dtype=float)
    n = zeta.size
    w = np.asarray(plant.frequencies_rad_s[:n]) * np.sqrt(s_E / s_rho)
    cols = [plant.input_names.index(i) for i in inputs]
    power = np.array([1.0 if i.startswith("base_accel") else 0.0 for i in inputs])
    Bq = np.asarray(plant.input_matrix)[:n, cols] * s_rho ** (power - 0.5)
    c = np.asarray(plant.output_matrix[0, :n]) / np.sqrt(s_rho)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(w**2), -np.diag(2 * zeta * w)]])
    B = np.vstack([np.zeros_like(Bq), Bq])
    C = np.vstack([np.r_[c, np.zeros(n)], np.r_[np.zeros(n), c]])
    return A, B, C


def truth_frf(plant, s_E, s_rho, zeta, f_hz, inputs=("tip_force_z",)) -> np.ndarray:
    """Return H (N, 2, m): tip z and its rate per unit of each input at ``f_hz``."""
    A, B, C = truth_state_space(plant, s_E, s_rho, zeta, inputs)
    eye = np.eye(A.shape[0])
    return np.array([C @ np.linalg.solve(2j * np.pi * f * eye - A, B) for f in f_hz])


def truth_driven(plant, s_E, s_rho, zeta, t_s, u, inputs=("tip_force_z",)) -> np.ndarray:
    """Return tip z and its rate (N, 2) from rest under ``u`` (N, m) held between samples."""
    A, B, C = truth_state_space(plant, s_E, s_rho, zeta, inputs)
    dt = t_s[1] - t_s[0]  # uniform samples
    Ad, Bd, Cd, Dd, _ = ss.cont2discrete((A, B, C, np.zeros((2, B.shape[1]))), dt, "zoh")
    return ss.dlsim((Ad, Bd, Cd, Dd, dt), np.asarray(u, dtype=float), t=t_s)[1]
