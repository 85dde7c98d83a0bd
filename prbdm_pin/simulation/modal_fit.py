"""A diagonal joint damping fitted to per-mode damping ratios (the ``"modal_fit"`` form).

A URDF ``<dynamics damping>`` or an MJCF hinge ``damping`` is one coefficient c_j per joint:
C = diag(c). Mode k of the undamped chain (mass-normalised, Phi^T M Phi = I, frequency
omega_k) then gets, in the proportional-damping approximation that drops the coupling
Phi^T C Phi off its diagonal, the ratio

    xi_k(c) = phi_k^T diag(c) phi_k / (2 omega_k) = sum_j c_j phi_jk^2 / (2 omega_k),

linear in c. :func:`modal_fit_damping` solves min ||xi(c) - xi_requested|| over c >= 0
(``scipy.optimize.nnls``, on c = k * s so that the columns have comparable size: the scaling
changes neither the feasible set nor the optimum). With as many joints as modes the fit is
usually exact in the approximation; a requested set that needs a negative c is met as
closely as c >= 0 allows. The ratios each mode then really has (:func:`damped_ratios`) come
from the complex eigenvalues lambda of the damped chain, zeta = -Re(lambda) / |lambda|, and
differ from the approximation by the dropped coupling (second order in C).

The alternatives a diagonal C can carry: the stiffness form C = beta K (:mod:`.damping`) is
c = beta k, a point of the fit's feasible set, so the fit's residual is never larger than the
best beta's (``stiffness_residual``); Rayleigh damping alpha M + beta K with two anchor modes
is not diagonal unless alpha = 0 (the chain's M is full), so its mass part cannot be written
as joint damping and is not offered.

With a hub (``n_free=1``) or a free bus (``n_free=6``) the leading coordinates have no spring:
their damping stays 0, the ratios go to the flexible modes only, and the rigid modes (2
n_free eigenvalues at zero) are left out of the damped ratios.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.optimize as so

from ..chain.eigen import modes_from_mass
from ..errors import BeamInputError, SolveError
from .damping import damping_ratios

__all__ = ["ModalFitDamping", "fit_joint_damping", "modal_fit_damping", "damped_ratios",
           "flexible_modes"]

# An eigenvalue with |Im| below this fraction of |lambda| is real (an overdamped mode's root)
_REAL_EIG = 1e-9


@dataclass(frozen=True, eq=False)
class ModalFitDamping:
    """A diagonal joint damping fitted to per-mode ratios, and the ratios it achieves.

    n is the number of flexible modes (the springs), nv the coordinates (n plus a hub's or a
    bus's spring-less ones).

    Attributes
    ----------
    joint_damping_Nms_per_rad : ndarray, shape (nv,)
        c_j, N m s/rad, all >= 0 (0 on a hub's or bus's coordinates).
    requested_ratios : ndarray, shape (n,)
        The ratios asked of modes 1..n (ascending frequency), dimensionless.
    projected_ratios : ndarray, shape (n,)
        diag(Phi^T C Phi) / (2 omega): the ratios in the approximation the fit solves.
    achieved_ratios : ndarray, shape (n,)
        The ratios from the damped chain's complex eigenvalues, ``-Re(lambda) / |lambda|``.
    ratio_errors : ndarray, shape (n,)
        ``achieved_ratios - requested_ratios`` (absolute, dimensionless).
    frequencies_rad_s : ndarray, shape (n,)
        The undamped flexible frequencies the fit used, rad/s.
    residual : float
        ||projected_ratios - requested_ratios||_2 (the fit's optimum).
    stiffness_residual : float
        The same for the best stiffness form c = beta k, beta >= 0 (never below ``residual``).
    """

    joint_damping_Nms_per_rad: np.ndarray
    requested_ratios: np.ndarray
    projected_ratios: np.ndarray
    achieved_ratios: np.ndarray
    ratio_errors: np.ndarray
    frequencies_rad_s: np.ndarray
    residual: float
    stiffness_residual: float

    def __post_init__(self) -> None:
        """Freeze the arrays."""
        for name in ("joint_damping_Nms_per_rad", "requested_ratios", "projected_ratios",
                     "achieved_ratios", "ratio_errors", "frequencies_rad_s"):
            a = np.array(getattr(self, name), dtype=float)
            a.setflags(write=False)
            object.__setattr__(self, name, a)


def flexible_modes(M: np.ndarray, springs_Nm_per_rad: np.ndarray, n_free: int = 0
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Return the flexible frequencies (rad/s, (n,)) and mass-normalised modes ((nv, n)).

    ``n_free`` leading coordinates without a spring: 0 (clamped), 1 (a hub), 6 (a free bus).
    """
    k = np.asarray(springs_Nm_per_rad, dtype=float)
    if n_free == 0:
        omega, Phi = modes_from_mass(np.asarray(M, dtype=float)[None], k)
        return omega[0], Phi[0]
    if n_free == 1:
        from ..model.hub import hub_modes

        omega, Phi = hub_modes(M, k)
    else:
        from ..model.supports import free_modes

        omega, Phi = free_modes(M, k, n_free)
    return omega[n_free:], Phi[:, n_free:]


def damped_ratios(M: np.ndarray, K: np.ndarray, C: np.ndarray, n_free: int = 0
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Return each mode's frequency and ratio from the damped chain's complex eigenvalues.

    The eigenvalues lambda of [[0, I], [-M^-1 K, -M^-1 C]]: an underdamped mode is a conjugate
    pair with omega_n = |lambda| and zeta = -Re(lambda) / |lambda|; an overdamped one two real
    roots r1, r2 with omega_n = sqrt(r1 r2) and zeta = -(r1 + r2) / (2 omega_n) (the real roots
    are paired in sorted order, exact for one overdamped mode). The 2 ``n_free`` eigenvalues
    nearest zero (the rigid modes of a hub or bus) are left out.

    Parameters
    ----------
    M, K, C : ndarray, shape (nv, nv)
        Mass (kg m^2), stiffness (N m/rad) and damping (N m s/rad) at one pose.
    n_free : int
        Rigid modes to leave out.

    Returns
    -------
    omega_n : ndarray, shape (nv - n_free,)
        The modes' natural frequencies, rad/s, ascending.
    zeta : ndarray, shape (nv - n_free,)
        Their damping ratios, dimensionless, in that order.
    """
    M = np.asarray(M, dtype=float)
    nv = M.shape[0]
    A = np.zeros((2 * nv, 2 * nv))
    A[:nv, nv:] = np.eye(nv)
    A[nv:, :nv] = -np.linalg.solve(M, np.asarray(K, dtype=float))
    A[nv:, nv:] = -np.linalg.solve(M, np.asarray(C, dtype=float))
    lam = np.linalg.eigvals(A)
    lam = lam[np.argsort(np.abs(lam), kind="stable")][2 * n_free:]
    cplx = np.abs(lam.imag) > _REAL_EIG * np.abs(lam)
    up = lam[cplx & (lam.imag > 0.0)]
    real = np.sort(lam[~cplx].real)
    if up.size * 2 != np.count_nonzero(cplx) or real.size % 2:
        raise SolveError(f"damped modes: eigenvalues {lam.tolist()} do not pair into modes")
    w = np.concatenate([np.abs(up), np.sqrt(real[0::2] * real[1::2])])
    z = np.concatenate([-up.real / np.abs(up), -(real[0::2] + real[1::2]) / (2.0 * w[up.size:])])
    order = np.argsort(w, kind="stable")
    return w[order], z[order]


def modal_fit_damping(M: np.ndarray, springs_Nm_per_rad: np.ndarray,
                      damping_ratio: float | np.ndarray, n_free: int = 0,
                      name: str = "damping_ratio") -> ModalFitDamping:
    """Fit a diagonal joint damping c >= 0 to per-mode damping ratios.

    Parameters
    ----------
    M : ndarray, shape (nv, nv)
        Mass matrix at the pose (the straight pose for an export), kg m^2.
    springs_Nm_per_rad : ndarray, shape (n,)
        The joint springs, N m/rad, all > 0 (K = diag of them, after ``n_free`` zeros).
    damping_ratio : float or ndarray, shape (n,)
        The ratio asked of each flexible mode, ascending frequency (a scalar: every mode),
        each in [0, 1).
    n_free : int
        Leading coordinates without a spring (0; a hub's 1; a free bus's 6): undamped.
    name : str
        The argument named in a refusal.

    Returns
    -------
    ModalFitDamping
        c, the requested, projected and achieved ratios and the residuals.

    Raises
    ------
    BeamInputError
        A ratio outside [0, 1) or not finite, or not one per mode (naming ``name``).
    """
    k = np.asarray(springs_Nm_per_rad, dtype=float).reshape(-1)
    n = k.size
    xi = damping_ratios(damping_ratio, n, name)
    omega, Phi = flexible_modes(M, k, n_free)
    G = (Phi[n_free:, :] ** 2).T / (2.0 * omega[:, None])  # xi(c) = G c
    Gk = G * k[None, :]  # unknowns s = c / k (s): columns of comparable size
    s, residual = so.nnls(Gk, xi)
    c = np.concatenate([np.zeros(n_free), s * k])
    g = Gk.sum(axis=1)  # the stiffness form: s = beta for every joint
    beta = max(float(g @ xi) / float(g @ g), 0.0)
    K = np.diag(np.concatenate([np.zeros(n_free), k]))
    _, achieved = damped_ratios(M, K, np.diag(c), n_free)
    if achieved.size != n:
        raise BeamInputError(f"{name}: {n} ratios for {achieved.size} modes")
    return ModalFitDamping(c, xi, Gk @ s, achieved, achieved - xi, omega, float(residual),
                           float(np.linalg.norm(beta * g - xi)))


def fit_joint_damping(model, damping_ratio: float | np.ndarray) -> ModalFitDamping:
    """Fit the diagonal joint damping of ``model`` to per-mode ratios, at the straight pose.

    What a URDF or MJCF export with ``damping_form="modal_fit"`` writes, and what
    ``simulate``/``linearize(..., damping="modal_fit")`` run (module notes).

    Parameters
    ----------
    model : PrbdmModel
        Clamped, on a hub or on a free bus (their coordinates stay undamped).
    damping_ratio : float or ndarray, shape (n,)
        The ratio asked of each flexible mode (ascending frequency), in [0, 1); n is
        ``model.n_springs``.

    Returns
    -------
    ModalFitDamping
        c (N m s/rad, one per coordinate), the asked, projected and achieved ratios.

    Raises
    ------
    InputTypeError
        ``model`` not a PrbdmModel.
    BeamInputError
        A ratio out of range, or not one per mode (naming ``damping_ratio``).
    """
    from ..model.checks import check_model

    check_model(model)
    return modal_fit_damping(model.mass_matrix(), model.stiffness_Nm_per_rad, damping_ratio,
                             int(model.n_free))
