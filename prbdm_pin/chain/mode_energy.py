"""The planar chain's modes as motions of its links, and their kinetic energy's change.

The change of that energy when the link sections change is what every frequency derivative of
the chain is made of.

With mass-normalised modes phi_k (phi^T M phi = 1) and distinct eigenvalues lam_k = omega_k^2,
``d lam_k = phi_k^T (dK - lam_k dM) phi_k``. The mass term is the derivative of the mode's kinetic
energy ``phi^T M phi = sum_i m_i |v_i|^2 + I_i w_i^2`` (v_i, w_i: velocity of link i's centre of
mass and angular rate of link i in the mode), evaluated without forming dM.
:func:`chain_gradient.frequency_gradients` adds the lengths' term to it (a moving joint station);
:func:`section_frequency_gradients` is the term alone (a design variable that changes the
sections at fixed lengths and springs).
"""

from __future__ import annotations

import numpy as np

from .eigen import modes_from_mass
from .planar_mass import chain_points, planar_mass_matrices

__all__ = ["mode_motion", "kinetic_energy_change", "section_frequency_gradients"]


def mode_motion(lengths_m: np.ndarray, com_offset_m: np.ndarray, poses_rad: np.ndarray,
                Phi: np.ndarray, points: tuple | None = None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the links' motion in each mode.

    Parameters
    ----------
    lengths_m, com_offset_m : ndarray, shape (n+1,)
        Link lengths and centre-of-mass distances from each link's start, m.
    poses_rad : ndarray, shape (m, n)
        Joint angles, rad.
    Phi : ndarray, shape (m, n, n)
        Mode shapes (rad per unit modal coordinate), Phi[pose, joint, mode].
    points : tuple, optional
        ``planar_mass.chain_points`` of the same chain (stacked as one design) and poses when
        already computed.

    Returns
    -------
    w : ndarray, shape (m, mode, link)
        Angular rate of links 1..n (the sum of their joints' rates, rad).
    v : ndarray, shape (m, 2, mode, link)
        x and z of the velocity of their centres of mass,
        ``v_i = w_i C_i - sum_(j <= i) phi_j J_j`` (m).
    u : ndarray, shape (m, 2, 1, link)
        x and z of the links' axes.
    """
    if points is None:
        L = np.asarray(lengths_m, dtype=float)
        off = np.asarray(com_offset_m, dtype=float)
        points = chain_points(L[None], off[None], np.asarray(poses_rad, dtype=float))
    # the sign of z does not matter in a quadratic form
    axes, joints, coms = points
    joints, coms = joints[0, :, :, None, :], coms[0, :, :, None, :]  # (m, 2, 1, link)
    P = Phi.swapaxes(1, 2)
    w = np.add.accumulate(P, axis=2)
    v = w[:, None] * coms - np.add.accumulate(P[:, None] * joints, axis=3)
    return w, v, axes[:, :, None, 1:]


def kinetic_energy_change(motion: tuple[np.ndarray, ...], mass_kg: np.ndarray,
                          d_mass: np.ndarray, d_inertia: np.ndarray, d_offset: np.ndarray
                          ) -> np.ndarray:
    """Return d(phi^T M phi) of every mode at fixed link lengths for the given section changes.

    The section changes are the columns of ``d_mass`` (kg), ``d_inertia`` (kg m^2) and
    ``d_offset`` (m), each (n+1, cols) (row 0, the clamped link, does not move). ``motion``:
    :func:`mode_motion`; ``mass_kg``: the masses of links 1..n, (n,). Shape (m, mode, cols),
    kg m^2 per unit of each column.
    """
    w, v, u = motion
    e_mass = np.add.reduce(v * v, axis=1)  # |v|^2
    e_inertia = w * w
    e_offset = 2.0 * mass_kg * w * np.add.reduce(u * v, axis=1)
    return e_mass @ d_mass[1:] + e_inertia @ d_inertia[1:] + e_offset @ d_offset[1:]


def section_frequency_gradients(lengths_m: np.ndarray, mass_kg: np.ndarray,
                                com_offset_m: np.ndarray, inertia_yy_kg_m2: np.ndarray,
                                stiffness_Nm_per_rad: np.ndarray, poses_rad: np.ndarray,
                                d_mass: np.ndarray, d_com_offset: np.ndarray,
                                d_inertia_yy: np.ndarray):
    """Return squared frequencies and their derivatives for given changes of the link sections.

    The lengths and springs are held fixed: ``d lam_k = -lam_k d(phi_k^T M phi_k)``.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    mass_kg, com_offset_m, inertia_yy_kg_m2 : ndarray, shape (n+1,)
        The planar sections (``sections.planar_sections``): kg, m, kg m^2.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint springs, N m/rad.
    poses_rad : ndarray, shape (m, n)
        Joint angles where the frequencies are taken, rad.
    d_mass, d_com_offset, d_inertia_yy : ndarray, shape (n+1, nv)
        Derivatives of the sections per unit of each of nv variables (kg, m, kg m^2 per unit).

    Returns
    -------
    lam : ndarray, shape (m, n)
        omega^2, ascending, rad^2/s^2.
    d_sections : ndarray, shape (m, n, nv)
        d lam_k / d p_v at fixed springs, rad^2/s^2 per unit of p_v.
    d_stiffness : ndarray, shape (m, n, n)
        d lam_k / d k_j at [pose, k, j], rad^2/s^2 per N m/rad (phi_jk^2): a variable that
        also moves the springs adds ``d_stiffness @ dk/dp``.
    """
    L = np.asarray(lengths_m, dtype=float)
    Q = np.atleast_2d(np.asarray(poses_rad, dtype=float))
    mass = np.asarray(mass_kg, dtype=float)
    M = planar_mass_matrices(L, mass, com_offset_m, inertia_yy_kg_m2, Q)
    omega, Phi = modes_from_mass(M, np.asarray(stiffness_Nm_per_rad, dtype=float))
    lam = omega**2
    dE = kinetic_energy_change(mode_motion(L, com_offset_m, Q, Phi), mass[1:], d_mass,
                               d_inertia_yy, d_com_offset)
    return lam, -lam[..., None] * dE, Phi.swapaxes(1, 2) ** 2
