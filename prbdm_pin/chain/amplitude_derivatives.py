"""The planar chain's tip amplitude per mode and its derivatives in stations and springs.

The amplitude of mode k is a_k = J phi_k (1/sqrt(kg)): phi_k its mass-normalised mode at the
straight pose (phi^T M phi = 1, M in kg m^2) and J the tip's z per joint angle there (m/rad,
``planar.tip_terms``), J_j = c (L - x_j) with c = +-1 the chain's sign convention, so
dJ_j / dx_i = -c delta_ij.

A mode's derivative for distinct eigenvalues is its expansion over all n modes (exact here:
they span the chain's n coordinates),

    d phi_k = sum_(j != k) phi_j phi_j^T (dK - lam_k dM) phi_k / (lam_k - lam_j)
              - 1/2 (phi_k^T dM phi_k) phi_k,

with dK = e_i e_i^T for spring k_i (dM = 0) and dM for station x_i (dK = 0 at fixed springs).
The bilinear forms phi_j^T dM phi_k come from the mass form's derivative
(:func:`.chain_derivatives.mass_form_gradient`) by polarisation:
2 phi_j^T dM phi_k = (phi_j + phi_k)^T dM (phi_j + phi_k) - phi_j^T dM phi_j - phi_k^T dM phi_k.
A repeated eigenvalue has no such derivative (:mod:`.chain_derivatives`' notes).
"""

from __future__ import annotations

import numpy as np

from .chain_derivatives import mass_form_gradient
from .eigen import modes_from_mass
from .planar import tip_terms
from .sections_derivatives import SectionGradient

__all__ = ["tip_amplitudes", "tip_amplitude_gradients"]


def tip_amplitudes(lengths_m: np.ndarray, modes: np.ndarray) -> np.ndarray:
    """Return the tip z amplitude of each mode (column of ``modes``, rad/sqrt(kg m^2)).

    ``lengths_m`` (n+1,) m; at the straight pose; 1/sqrt(kg), shape (cols,).
    """
    n = modes.shape[0]
    return tip_terms(lengths_m, np.zeros(n), np.zeros(3))[1][2] @ modes


def tip_amplitude_gradients(lengths_m: np.ndarray, sections: SectionGradient,
                            stiffness_Nm_per_rad: np.ndarray, mass_matrix: np.ndarray,
                            points: tuple):
    """Return the tip amplitudes of every mode at the straight pose and their derivatives.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    sections : SectionGradient
        ``planar_sections_gradient`` of the same lengths.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint springs, N m/rad.
    mass_matrix : ndarray, shape (n, n)
        ``planar_mass_matrices`` at the straight pose, kg m^2.
    points : tuple
        ``planar_mass.chain_points`` of the chain (as a stack of one) at the straight pose.

    Returns
    -------
    a : ndarray, shape (n,)
        a_k, ascending modes, 1/sqrt(kg).
    d_station : ndarray, shape (n, n)
        d a_k / d x_i at [k, i], 1/sqrt(kg) per m.
    d_stiffness : ndarray, shape (n, n)
        d a_k / d k_i at [k, i], 1/sqrt(kg) per N m/rad.
    """
    L = np.asarray(lengths_m, dtype=float)
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    n = k.size
    omega, Phi = modes_from_mass(mass_matrix[None], k)
    lam, Phi = omega[0] ** 2, Phi[0]
    J = tip_terms(L, np.zeros(n), np.zeros(3))[1][2]
    a = J @ Phi
    # the mass form of phi_j + phi_k for every pair (j, k), then polarised
    pairs = (Phi[:, :, None] + Phi[:, None, :]).reshape(n, n * n)
    Q = mass_form_gradient(L, sections, np.zeros((1, n)), pairs[None], points)[0]
    Q = Q.reshape(n, n, n)  # [j, k, i]: d (phi_j + phi_k)^T M (phi_j + phi_k) / d x_i
    diag = np.einsum("kki->ki", Q) / 4.0  # (2 phi_k)^T dM (2 phi_k) / 4
    B = 0.5 * (Q - diag[:, None, :] - diag[None, :, :])  # phi_j^T dM_i phi_k at [j, k, i]
    gap = lam[None, :] - lam[:, None]  # lam_k - lam_j at [j, k]
    np.fill_diagonal(gap, np.inf)  # the j = k term is the normalisation's alone
    # the coefficient of phi_j in d phi_k: [j, k, i]
    c_station = -lam[None, :, None] * B / gap[..., None]
    c_station[np.arange(n), np.arange(n)] = -0.5 * diag
    # phi_j^T e_i e_i^T phi_k = Phi[i, j] Phi[i, k] at [j, k, i]
    c_spring = np.einsum("ij,ik->jki", Phi, Phi) / gap[..., None]
    # J d phi_k = sum_j a_j c[j, k, i]; the lever arm J_i = c (L - x_i) moves with station i
    d_station = np.einsum("j,jki->ki", a, c_station) - np.sign(J[-1]) * Phi.T
    d_stiffness = np.einsum("j,jki->ki", a, c_spring)
    return a, d_station, d_stiffness
