"""Analytic derivatives of the ``paper`` parametrisation's losses over u and ln k.

The springs are Eq. 14's ``K_j(i) = k_i sqrt(E I_(j+1) / m_(j+1))``; the variables are the
stick-breaking length coordinates u and the SCFs' logarithms ln k.

The unit springs K0 move with the joint stations through the links' area moments and masses
(``section_gradients.planar_sections_gradient``), the frequencies through the mass matrix and K0
(``chain_gradient.frequency_gradients``), the equilibrium tips through the springs and the
lengths (``chain_gradient.static_tip_gradient``); every station derivative is chained to u by
``joint_jacobian.unit_lengths_jacobian``. Scaling all springs of a pose by k_i scales its omega^2
by k_i, so d omega / d ln k_i = omega / 2 (omega^2: omega^2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..chain.chain_derivatives import frequency_gradients, static_tip_gradient
from ..chain.planar import planar_mass_matrices, planar_tips
from ..chain.sections_derivatives import planar_sections_gradient
from ..chain.statics import static_deflection_planar_batch
from ..chain.stiffness import paper_unit_stiffness
from ..errors import SolveError
from ..options.choices import Objective
from .evaluate import chain_frequencies
from .joint_jacobian import unit_lengths_jacobian
from .objectives import eigen_weights
from .problem import FitProblem, lengths_from_unit

__all__ = ["UnitChainGradient", "unit_chain_gradient", "projected_residual_jacobian",
           "scalar_loss_gradient"]


@dataclass(frozen=True, eq=False)
class UnitChainGradient:
    """A ``paper`` design at unit SCF and its derivatives with respect to u.

    Attributes
    ----------
    lengths_m : ndarray, shape (n+1,)
        Link lengths of u, m.
    unit_springs_Nm_per_rad : ndarray, shape (n,)
        sqrt(E I / m) of links 1..n, N m/rad.
    d_unit_springs : ndarray, shape (n, n)
        d K0_j / d u_l, N m/rad.
    d_station_du : ndarray, shape (n, n)
        d x_j / d u_l of the joint stations, m.
    omega_rad_s : ndarray, shape (m, N)
        Unit-SCF natural frequencies, rad/s.
    w : ndarray, shape (m, N)
        Unit-SCF frequencies compared (omega in rad/s, or omega^2 when ``squared``).
    d_w : ndarray, shape (m, N, n)
        d w / d u at unit SCF (rad/s, or rad^2/s^2 when ``squared``, per unit of u).
    """

    lengths_m: np.ndarray
    unit_springs_Nm_per_rad: np.ndarray
    d_unit_springs: np.ndarray
    d_station_du: np.ndarray
    omega_rad_s: np.ndarray
    w: np.ndarray
    d_w: np.ndarray


def unit_chain_gradient(problem: FitProblem, u: np.ndarray) -> UnitChainGradient:
    """Return the unit-SCF frequencies of the design u and their analytic derivatives.

    Raises SolveError or LinAlgError where the model cannot be solved (the caller decides).

    Parameters
    ----------
    problem : FitProblem
        The fit problem (beam, poses, target and frequency form).
    u : ndarray, shape (n,)
        Stick-breaking length coordinates in [0, 1] (dimensionless).

    Returns
    -------
    UnitChainGradient
        The lengths (m), unit springs (N m/rad), frequencies (rad/s) and their derivatives in u.
    """
    p = problem
    lengths = lengths_from_unit(u, p.length_m, p.min_fraction)
    sec = planar_sections_gradient(p.beam, lengths)
    K0 = paper_unit_stiffness(p.beam.material.E_Pa, sec.area_moment_m4, sec.mass_kg)
    # K0_j = sqrt(E I_(j+1) / m_(j+1)): d ln K0 = (d ln I - d ln m) / 2
    dK0_dx = 0.5 * K0[:, None] * (sec.d_area_moment_m3[1:] / sec.area_moment_m4[1:, None]
                                  - sec.d_mass_kg_per_m[1:] / sec.mass_kg[1:, None])
    dx_du = unit_lengths_jacobian(u, p.length_m, p.min_fraction).cumsum(axis=0)[:-1]
    M = planar_mass_matrices(lengths, sec.mass_kg, sec.com_offset_m, sec.inertia_yy_kg_m2,
                             p.poses_rad)
    lam, d_x, d_k = frequency_gradients(lengths, sec, K0, p.poses_rad, M)
    N = p.n_freq
    lam, d_x, d_k = lam[:, :N], d_x[:, :N], d_k[:, :N]
    d_lam = (d_x + d_k @ dK0_dx) @ dx_du
    omega = chain_frequencies(M, K0)[:, :N]  # the residuals' own eigensolve, bit for bit
    if p.squared:
        w, d_w = omega**2, d_lam
    else:
        w, d_w = omega, d_lam / (2.0 * omega[..., None])
    return UnitChainGradient(lengths, K0, dK0_dx @ dx_du, dx_du, omega, w, d_w)


def projected_residual_jacobian(problem: FitProblem, g: UnitChainGradient) -> np.ndarray:
    """Return d/du of the variable-projected eigen residuals, shape (m, N, n), dimensionless.

    The residuals are ``d (c_i w_i - f)``, with pose i's optimal amplitude c_i
    (``objectives.best_amplitude``).

    c_i = sum d^2 f w_i / sum d^2 w_i^2 moves with u too: dc_i = (sum d^2 f dw_i
    - 2 c_i sum d^2 w_i dw_i) / sum d^2 w_i^2.
    """
    p = problem
    f = p.target.omega_truth_rad_s ** (2 if p.squared else 1)
    d = eigen_weights(p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
    d2 = d * d
    w, dw = g.w, g.d_w
    den = (d2 * w * w).sum(axis=1)
    c = (d2 * w) @ f / den
    dc = (np.einsum("k,ikl->il", d2 * f, dw)
          - 2.0 * c[:, None] * np.einsum("ik,ikl->il", d2 * w, dw)) / den[:, None]
    return d[None, :, None] * (c[:, None, None] * dw + w[..., None] * dc[:, None, :])


def scalar_loss_gradient(problem: FitProblem, objective: Objective, tip_scales: np.ndarray,
                         g: UnitChainGradient, scf: np.ndarray) -> tuple[float, np.ndarray]:
    """Return the ``paper`` loss with a deflection term and its gradient over [u (n), ln k (m)].

    loss = D (``deflection``) or hypot(E, D) (``combined``), E = mean_i e_i the per-pose eigen
    errors ``||d (sqrt(k_i) w_i - f)||`` (omega^2: ``k_i w_i``), D = mean_i of the per-pose tip
    errors averaged over the load cases, each divided by ``tip_scales`` (m).

    Raises SolveError where a static solve does not converge.

    Parameters
    ----------
    problem : FitProblem
        The fit problem (beam, poses, target with its load cases).
    objective : Objective
        ``DEFLECTION`` or ``COMBINED`` (an objective with a tip term).
    tip_scales : ndarray, shape (cases,)
        What each load case's tip error is divided by, m.
    g : UnitChainGradient
        ``unit_chain_gradient`` of the lengths' coordinates u.
    scf : ndarray, shape (m,)
        Each pose's SCF (the factor on ``sqrt(E I / m)``).

    Returns
    -------
    loss : float
        The loss (fraction).
    gradient : ndarray, shape (n + m,)
        d loss / d [u, ln k] (fraction per unit of each coordinate).
    """
    p = problem
    m, n = p.n_poses, p.n_joints
    L = g.lengths_m
    # eigen: w_i(k) = k_i^a w_i, a = 1/2 (omega) or 1 (omega^2)
    a = 1.0 if p.squared else 0.5
    f = p.target.omega_truth_rad_s ** (2 if p.squared else 1)
    d = eigen_weights(p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
    ka = scf**a
    r = d * (ka[:, None] * g.w - f)  # (m, N)
    e = np.linalg.norm(r, axis=1)
    safe = np.maximum(e, 1e-300)[:, None]
    de_du = np.einsum("ik,ikl->il", r * d * ka[:, None], g.d_w) / safe
    de_dlnk = (r * d * a * ka[:, None] * g.w).sum(axis=1) / e.clip(1e-300)
    # statics: pose i's springs k_i K0, one vectorised solve per load case
    K = scf[:, None] * g.unit_springs_Nm_per_rad[None, :]
    Lr = np.broadcast_to(L, (m, L.size))
    t = np.zeros(m)
    dt_du = np.zeros((m, n))
    dt_dlnk = np.zeros(m)
    cases = p.target.load_cases
    for case, scale in zip(cases, tip_scales, strict=True):
        q, ok = static_deflection_planar_batch(Lr, K, case.tip_force_N)
        if not np.all(ok):
            raise SolveError("a pose's static solve did not converge")
        tips = planar_tips(Lr, q)
        for i in range(m):
            diff = tips[i] - case.tip_position_m
            err = np.linalg.norm(diff)
            _, _, dtip = static_tip_gradient(L, K[i], case.tip_force_N, q[i])
            # stations at fixed springs, springs k_i K0(u), and ln k_i
            dtip_du = dtip[:, :n] @ g.d_station_du + dtip[:, n:] @ (scf[i] * g.d_unit_springs)
            dtip_dlnk = dtip[:, n:] @ K[i]
            t[i] += err / scale
            dt_du[i] += diff @ dtip_du / (max(err, 1e-300) * scale)
            dt_dlnk[i] += diff @ dtip_dlnk / (max(err, 1e-300) * scale)
    nc = len(cases)
    t, dt_du, dt_dlnk = t / nc, dt_du / nc, dt_dlnk / nc
    D = t.mean()
    grad = np.empty(n + m)
    if not objective.has_eigen_term:
        grad[:n] = dt_du.mean(axis=0)
        grad[n:] = dt_dlnk / m
        return float(D), grad
    E = e.mean()
    loss = float(np.hypot(E, D))
    s = max(loss, 1e-300)
    grad[:n] = (E * de_du.mean(axis=0) + D * dt_du.mean(axis=0)) / s
    grad[n:] = (E * de_dlnk + D * dt_dlnk) / (m * s)
    return loss, grad
