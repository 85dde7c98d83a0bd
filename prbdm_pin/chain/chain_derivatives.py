"""Analytic derivatives of the planar chain's frequencies and static tip in stations and springs.

The outputs are the natural frequencies and the large-deflection static tip. Variables: the n
joint stations x_j = L_0 + ... + L_(j-1) (m; the free coordinates of the link lengths on their
simplex, L_i = x_(i+1) - x_i with x_0 = 0, x_(n+1) = L) and the n springs k_j (N m/rad). Each
link's mass, centre of mass and inertia move with the stations through the exact section integrals
(:mod:`.section_gradients`).

Frequencies: with mass-normalised modes phi_k (phi^T M phi = 1) and distinct eigenvalues
lam_k = omega_k^2, ``d lam_k = phi_k^T (dK - lam_k dM) phi_k``. The mass term is the derivative of
the mode's kinetic energy ``phi^T M phi = sum_i m_i |v_i|^2 + I_i w_i^2`` (v_i, w_i: velocity of
link i's centre of mass and angular rate of link i in the mode), evaluated without forming dM.
For a repeated eigenvalue the modes are any basis of the eigenspace and the single-mode formula
does not hold: the derivatives of the repeated group are the eigenvalues of the matrix
``Phi_g^T (dK - lam dM) Phi_g`` over its modes, which depend on the direction of the change. A
symmetric planar chain with a diagonal K of positive springs has simple frequencies in practice;
this module does not test for coincidence.

Static tip: the equilibrium g(q, p) = K q - J(q)^T F = 0 gives ``H dq = -dg/dp`` with H the
potential's Hessian ``K - d(J^T F)/dq`` (positive definite at a stable equilibrium), and the tip
``dp_tip = J dq + dp_tip/dp`` at fixed q.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.linalg.lapack import dgesv as _gesv

from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.validate import check_joints, real_vector
from .eigen import modes_from_mass
from .layout import validate_lengths
from .mode_energy import kinetic_energy_change, mode_motion
from .planar import tip_terms
from .planar_mass import chain_points, planar_mass_matrices
from .sections_derivatives import SectionGradient, planar_sections_gradient
from .spring_checks import check_springs
from .statics import static_deflection_planar
from .stiffness import validate_stiffness

__all__ = ["ModelGradient", "model_gradient", "frequency_gradients", "mass_form_gradient",
           "static_tip_gradient"]


def frequency_gradients(lengths_m: np.ndarray, sections: SectionGradient,
                        stiffness_Nm_per_rad: np.ndarray, poses_rad: np.ndarray,
                        mass_matrices: np.ndarray | None = None, points: tuple | None = None):
    """Squared frequencies and their derivatives at each pose, from the closed-form chain.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    sections : SectionGradient
        ``planar_sections_gradient`` of the same lengths.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint springs, N m/rad.
    poses_rad : ndarray, shape (m, n)
        Joint angles where the frequencies are taken, rad.
    mass_matrices : ndarray, shape (m, n, n), optional
        ``planar_mass_matrices`` at the poses when already computed, kg m^2.
    points : tuple, optional
        ``planar_mass.chain_points`` of the chain (as a stack of one) at the poses when already
        computed.

    Returns
    -------
    lam : ndarray, shape (m, n)
        omega^2, ascending, rad^2/s^2.
    d_station : ndarray, shape (m, n, n)
        d lam_k / d x_j at [pose, k, j], rad^2/s^2 per m.
    d_stiffness : ndarray, shape (m, n, n)
        d lam_k / d k_j at [pose, k, j], rad^2/s^2 per N m/rad (phi_jk^2).
    """
    L = np.asarray(lengths_m, dtype=float)
    Q = np.atleast_2d(np.asarray(poses_rad, dtype=float))
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    s = sections
    if points is None:
        points = chain_points(L[None], s.com_offset_m[None], Q)
    M = mass_matrices if mass_matrices is not None else planar_mass_matrices(
        L, s.mass_kg, s.com_offset_m, s.inertia_yy_kg_m2, Q, points)
    omega, Phi = modes_from_mass(M, k)  # Phi[pose, joint, mode]
    lam = omega**2
    dE = mass_form_gradient(L, s, Q, Phi, points)
    d_station = -lam[..., None] * dE
    d_stiffness = Phi.swapaxes(1, 2) ** 2
    return lam, d_station, d_stiffness


def mass_form_gradient(lengths_m: np.ndarray, sections: SectionGradient, poses_rad: np.ndarray,
                       vectors: np.ndarray, points: tuple) -> np.ndarray:
    """Return d(v^T M v) / d x_j at fixed v for each column v of ``vectors``, kg m^2 per m.

    M moves with the stations through the link sections and the chain's geometry (module
    notes); ``vectors`` (m, n, cols) in rad, one set per pose of ``poses_rad`` (m, n);
    ``points``: ``planar_mass.chain_points`` of the chain at those poses. Shape (m, cols, n).
    """
    s = sections
    n = vectors.shape[1]
    w, v, u = motion = mode_motion(lengths_m, s.com_offset_m, poses_rad, vectors, points)
    m1 = s.mass_kg[1:]
    dE = kinetic_energy_change(motion, m1, s.d_mass_kg_per_m, s.d_inertia_yy_kg_m,
                               s.d_com_offset)
    # the chain's geometry at fixed sections: link l's length moves every centre of mass
    # beyond it, G_l = 2 w_l u_l . sum_(i > l) m_i v_i (l = 1..n-1; L_0 and L_n do not enter r)
    if n > 1:
        # x and z of the sum over i >= l (np.add.accumulate: cumsum without its wrapper)
        t = np.add.accumulate((m1 * v)[..., ::-1], axis=3)[..., ::-1]
        G = 2.0 * w[..., :-1] * np.add.reduce(u[..., :-1] * t[..., 1:], axis=1)
        # L_l = x_(l+1) - x_l: station j (index j - 1) lengthens link j - 1, shortens link j
        dE[..., 1:] += G
        dE[..., :-1] -= G
    return dE


def static_tip_gradient(lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                        tip_force_N: np.ndarray, q_rad: np.ndarray):
    """Differentiate the equilibrium pose and tip in the stations and springs.

    The sections are held fixed (the statics do not see the masses); the derivatives come from
    implicit differentiation of K q = J(q)^T F.

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint springs, N m/rad.
    tip_force_N : ndarray, shape (3,)
        Dead tip force, N (world).
    q_rad : ndarray, shape (n,)
        The equilibrium (``statics.static_deflection_planar``), rad.

    Returns
    -------
    tip_m : ndarray, shape (3,)
        The tip position at the equilibrium, m (world).
    d_q : ndarray, shape (n, 2n)
        dq / d(x, k): rad per m (first n columns), rad per N m/rad (last n).
    d_tip : ndarray, shape (3, 2n)
        d p_tip / d(x, k): m per m, m per N m/rad.
    """
    L = np.asarray(lengths_m, dtype=float)
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    F = np.asarray(tip_force_N, dtype=float)
    q = np.asarray(q_rad, dtype=float)
    n = k.size
    tip, J, T, c, sn = tip_terms(L, q, F)
    H = -T
    H.flat[:: n + 1] += k
    # d(J^T F)_m / dL_i = -F_x sin phi_i - F_z cos phi_i for links i >= m (links 1..n; link 0
    # does not enter), and the tip's d p / dL_i = (cos phi_i, 0, -sin phi_i) (link 0: e_x)
    dJtF = np.zeros((n, n + 1))
    dJtF[:, 1:] = np.where(_upper_mask(n), -float(F[0]) * sn - float(F[2]) * c, 0.0)
    dtip_dL = np.zeros((3, n + 1))
    dtip_dL[0, 0] = 1.0
    dtip_dL[0, 1:] = c
    dtip_dL[2, 1:] = -sn
    # station j (column j - 1) lengthens link j - 1 and shortens link j: d/dx = d/dL_(j-1) -
    # d/dL_j
    dg = np.zeros((n, 2 * n))
    np.subtract(dJtF[:, 1:], dJtF[:, :-1], out=dg[:, :n])  # -(d(J^T F)/dx)
    dg.flat[n:: 2 * n + 1] = q  # d(K q)/dk = diag(q)
    # LAPACK's LU solve directly (np.linalg.solve's, without its batched wrapper)
    _, _, dq, info = _gesv(H, dg)
    if info != 0:
        raise np.linalg.LinAlgError("static tip gradient: singular Hessian at the equilibrium")
    dq = -dq
    dtip = J @ dq
    dtip[:, :n] += dtip_dL[:, :-1] - dtip_dL[:, 1:]
    return tip, dq, dtip


@lru_cache(maxsize=64)
def _upper_mask(n: int) -> np.ndarray:
    """Return np.triu's mask, k >= m for m, k < n: link k + 1 lies beyond joint m + 1."""
    out = np.triu(np.ones((n, n), dtype=bool))
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class ModelGradient:
    """A chain's frequencies and static tip with their derivatives.

    The variables are ``variables`` = ("x[1]", ..., "x[n]", "k[0]", ..., "k[n-1]"): the joint
    stations (m; moving x_j lengthens link j - 1 and shortens link j, the beam length fixed) and
    the joint springs (N m/rad), with ``variable_units`` ("m" or "N m/rad").

    Attributes
    ----------
    variables : tuple of str
        The variables' names, in column order of the derivatives.
    variable_units : tuple of str
        Each variable's unit, "m" or "N m/rad".
    pose_rad : ndarray, shape (n,)
        The joint angles where the frequencies are taken, rad.
    omega_rad_s : ndarray, shape (n,)
        Natural frequencies at ``pose_rad``, ascending.
    d_omega_rad_s : ndarray, shape (n, 2n)
        d omega_k / d variable (rad/s per the variable's unit).
    tip_force_N : ndarray, shape (3,), or None
        The dead tip force of the static part, N (world); None without a load.
    tip_position_m, static_pose_rad : ndarray, shape (3,), (n,), or None
        The tip (m) and the joint angles (rad) under ``tip_force_N``; None without a load.
    d_tip_position_m : ndarray, shape (3, 2n), or None
        d p_tip / d variable (m per the variable's unit); None without a load.
    d_static_pose_rad : ndarray, shape (n, 2n), or None
        d q / d variable (rad per the variable's unit); None without a load.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -10.0])
    >>> l, k = np.array([0.2, 0.5, 0.3]), np.array([2500.0, 1200.0])  # m, N m/rad
    >>> g = pp.model_gradient(beam, l, k)
    >>> isinstance(g, pp.ModelGradient), g.variable_units
    (True, ('m', 'm', 'N m/rad', 'N m/rad'))
    >>> g.d_omega_rad_s.shape, g.d_tip_position_m.shape
    ((2, 4), (3, 4))
    >>> g.omega_rad_s.round(1), pp.build_model(beam, l, k).natural_frequencies().round(1)  # rad/s
    (array([ 59. , 320.9]), array([ 59. , 320.9]))
    """

    variables: tuple[str, ...]
    variable_units: tuple[str, ...]
    pose_rad: np.ndarray
    omega_rad_s: np.ndarray
    d_omega_rad_s: np.ndarray
    tip_force_N: np.ndarray | None = None
    tip_position_m: np.ndarray | None = None
    d_tip_position_m: np.ndarray | None = None
    static_pose_rad: np.ndarray | None = None
    d_static_pose_rad: np.ndarray | None = None


def _frozen(a):
    if a is None:
        return None
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def model_gradient(beam: Beam, lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                   pose_rad: np.ndarray | None = None,
                   tip_force_N: np.ndarray | None = None) -> ModelGradient:
    """Return the frequencies and static tip of the chain cut from ``beam``, with derivatives.

    The derivatives are analytic, with respect to the joint stations and springs.

    Parameters
    ----------
    beam : Beam
        The beam the links are cut from.
    lengths_m : array_like, shape (n+1,)
        Link lengths, m (validated as for ``build_model``).
    stiffness_Nm_per_rad : array_like, shape (n,)
        Joint springs, N m/rad, held fixed when the stations move (a spring law such as the
        finite-segment one chains through ``section_gradients.finite_segment_stiffness_gradient``).
    pose_rad : array_like, shape (n,), optional
        Joint angles of the frequencies (default straight), rad.
    tip_force_N : array_like, shape (3,), optional
        Dead tip force (N, world); default the beam's ``tip_force_N``. A zero load gives no
        static part.

    Returns
    -------
    ModelGradient
        The frequencies (rad/s) at ``pose_rad``, the static tip (m) and pose (rad) under the
        load, and their derivatives per m of each station and per N m/rad of each spring.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> l, k = np.array([0.2, 0.5, 0.3]), np.array([2500.0, 1200.0])  # m, N m/rad
    >>> g = pp.model_gradient(beam, l, k)
    >>> g.variables
    ('x[1]', 'x[2]', 'k[0]', 'k[1]')
    >>> g.d_omega_rad_s[:, 2].round(5)  # rad/s per N m/rad of k[0]
    array([0.01095, 0.00456])
    >>> h = 1.0  # N m/rad: a central difference of build_model's frequencies
    >>> w_p = pp.build_model(beam, l, k + [h, 0.0]).natural_frequencies()
    >>> w_m = pp.build_model(beam, l, k - [h, 0.0]).natural_frequencies()
    >>> ((w_p - w_m) / (2 * h)).round(5)
    array([0.01095, 0.00456])
    """
    lengths = validate_lengths(beam, lengths_m)
    n = lengths.size - 1
    check_joints(n)
    k = validate_stiffness(stiffness_Nm_per_rad, n)
    check_springs(beam, k)
    q = np.zeros(n) if pose_rad is None else real_vector("pose_rad", pose_rad, "rad")
    if q.shape != (n,):
        raise BeamInputError(f"pose_rad = {np.asarray(pose_rad).tolist()}: must be {n} finite "
                             "joint angles (rad)")
    sec = planar_sections_gradient(beam, lengths)
    lam, dx, dk = frequency_gradients(lengths, sec, k, q[None])
    omega = np.sqrt(lam[0])
    d_omega = np.hstack([dx[0], dk[0]]) / (2.0 * omega[:, None])
    names = tuple(f"x[{j + 1}]" for j in range(n)) + tuple(f"k[{j}]" for j in range(n))
    units = ("m",) * n + ("N m/rad",) * n
    F = beam.tip_force_N if tip_force_N is None else tip_force_N
    F = np.asarray(F, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force = {F.tolist()}: must be 3 finite numbers (N)")
    if F[0] == 0.0 and F[2] == 0.0:
        return ModelGradient(names, units, _frozen(q), _frozen(omega), _frozen(d_omega))
    qs = static_deflection_planar(lengths, k, F)
    tip, dq, dtip = static_tip_gradient(lengths, k, F, qs)
    return ModelGradient(names, units, _frozen(q), _frozen(omega), _frozen(d_omega), _frozen(F),
                         _frozen(tip), _frozen(dtip), _frozen(qs), _frozen(dq))
