"""Joint-space damping matrices C for the PRBDM: M(q) a + h(q, v) + K q + C v = tau.

The paper adds damping only to make simulations tractable (its Eq. 5). Three forms are offered:

- ``modal_damping(M, K, xi)`` (default): C = M Phi diag(2 xi_k omega_k) Phi^T M with the
  mass-normalised modes Phi (Phi^T M Phi = I) of K phi = omega^2 M phi. It is symmetric and
  gives mode k of the linearised system exactly the damping ratio xi_k
  (Phi^T C Phi = diag(2 xi_k omega_k)).
  With one ratio for all modes it equals Caughey's 2 xi M (M^-1 K)^(1/2).
- ``eq5c_damping(M, K, xi)``: the paper's Eq. 5c, C = 2 diag(xi_j) (M K)^(1/2) with per-joint
  factors xi_j. (M K)^(1/2) is the principal square root (real: M K is similar to the positive
  definite L^T K L for M = L L^T). It is **not symmetric** in general and does not give the modes
  the ratios xi; it is kept for comparison with the paper only.
- ``stiffness_damping(M, K, xi_1)``: stiffness-proportional C = beta K with beta = 2 xi_1 / omega_1,
  so mode 1 gets the ratio xi_1 and mode k gets xi_1 omega_k / omega_1 (the modes of K, M
  diagonalise C). With the diagonal joint springs of the PRBDM, C is diagonal: it is the form a
  diagonal joint damping (MJCF ``damping``, URDF ``<dynamics damping>``) carries exactly, and
  it does not depend on the pose once beta is set. High modes are damped heavily (beyond
  critical when omega_k / omega_1 > 1 / xi_1).
- ``"modal_fit"``: a diagonal C = diag(c), c >= 0 fitted by least squares to per-mode ratios
  (:mod:`.modal_fit`): the per-mode ratios as closely as a joint damping can carry them, what
  URDF and MJCF exports of a calibrated model carry.

All take matrices evaluated at one pose; see ``prbdm_pin.simulation`` for how the pose is chosen.
``modal_ratios(M, K, C)`` gives the ratio of each mode for a damping matrix that the modes
diagonalise (modal and stiffness forms).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..chain.eigen import generalized_eigh, modes_from_mass, symmetric_eigh
from ..errors import BeamInputError, SolveError
from ..options.choices import DAMPING_FORMS
from ..options.validate import check_damping_ratio, real_vector

__all__ = [
    "DAMPING_FORMS",
    "damping_ratios",
    "modal_damping",
    "spring_modal_damping",
    "eq5c_damping",
    "stiffness_damping",
    "stiffness_damping_coefficient",
    "modal_ratios",
    "damping_matrix",
]



def damping_ratios(
    damping_ratio: float | np.ndarray, n: int, name: str = "damping_ratio"
) -> np.ndarray:
    """Validate a damping ratio (scalar or one per mode/joint) and broadcast it to shape (n,).

    Raises :class:`BeamInputError` naming ``name`` for a wrong shape, or a value that is not
    finite or not in [0, 1) (``validate.MAX_DAMPING_RATIO``: an over-damped ratio is refused, as
    ``prbdm simulate --damping`` refuses it).
    """
    v = damping_ratio.item() if isinstance(damping_ratio, np.ndarray) and \
        damping_ratio.ndim == 0 else damping_ratio
    if np.ndim(v) == 0 and not isinstance(v, (list, tuple)):
        return np.full(n, check_damping_ratio(name, v))
    xi = real_vector(name, v, "dimensionless")
    if xi.shape != (n,):
        raise BeamInputError(f"{name} has shape {xi.shape}: must be a scalar or have {n} entries")
    for i, r in enumerate(xi):
        check_damping_ratio(f"{name}[{i}]", float(r))
    return xi.copy()


def _check_pair(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    M = np.asarray(M, dtype=float)
    K = np.asarray(K, dtype=float)
    if M.ndim != 2 or M.shape[0] != M.shape[1] or K.shape != M.shape:
        raise BeamInputError(f"M {M.shape} and K {K.shape}: must be square and of equal shape")
    return M, K


def modal_damping(M: np.ndarray, K: np.ndarray, damping_ratio: float | np.ndarray) -> np.ndarray:
    """Modal damping matrix C = M Phi diag(2 xi_k omega_k) Phi^T M.

    Parameters
    ----------
    M : ndarray, shape (n, n)
        Joint-space mass matrix at the pose, kg m^2 (symmetric positive definite).
    K : ndarray, shape (n, n)
        Joint stiffness, N m/rad (symmetric positive definite).
    damping_ratio : float or ndarray, shape (n,)
        Ratio xi_k of critical damping for each mode (ascending frequency), dimensionless.

    Returns
    -------
    ndarray, shape (n, n)
        Symmetric damping matrix, N m s/rad.
    """
    M, K = _check_pair(M, K)
    xi = damping_ratios(damping_ratio, M.shape[0])
    k = np.diagonal(K)
    if np.count_nonzero(K) == k.size and np.all(k > 0.0):
        return spring_modal_damping(M, k, xi)
    w2, phi = generalized_eigh(K, M, "modal damping")  # Phi^T M Phi = I
    omega = np.sqrt(np.clip(w2, 0.0, None))
    MPhi = M @ phi
    C = (MPhi * (2.0 * xi * omega)) @ MPhi.T
    return 0.5 * (C + C.T)


def spring_modal_damping(M: np.ndarray, springs_Nm_per_rad: np.ndarray, xi: np.ndarray
                         ) -> np.ndarray:
    """Compute :func:`modal_damping` for joint springs alone, N m s/rad.

    K = diag(springs) (N m/rad, all > 0), with validated ratios ``xi`` (n,), through the scaled
    standard eigenproblem (:func:`prbdm_pin.chain.eigen.modes_from_mass`, under its guard): a
    linearisation builds this every call, and the generalized problem's set-up costs more than
    the solve. ``M`` (m, n, n) and springs (m, n): a stack of designs (``linearize_batch``),
    one stacked eigensolve, (m, n, n) back.
    """
    stack = M.ndim == 3
    omega, phi = modes_from_mass(M if stack else M[None], springs_Nm_per_rad)
    if not stack:
        omega, phi = omega[0], phi[0]
    MPhi = M @ phi
    C = (MPhi * (2.0 * xi * omega)[..., None, :]) @ MPhi.swapaxes(-1, -2)
    return 0.5 * (C + C.swapaxes(-1, -2))


def eq5c_damping(M: np.ndarray, K: np.ndarray, damping_ratio: float | np.ndarray) -> np.ndarray:
    """Compute the paper's equation 5c damping, C = 2 diag(xi_j) (M K)^(1/2), per-joint xi_j.

    Not symmetric in general and does not give mode k the ratio xi_k (use :func:`modal_damping`
    for that). The principal square root is computed as L (L^T K L)^(1/2) L^-1 with M = L L^T.

    Returns
    -------
    ndarray, shape (n, n)
        Damping matrix, N m s/rad.
    """
    M, K = _check_pair(M, K)
    xi = damping_ratios(damping_ratio, M.shape[0])
    try:
        L = np.linalg.cholesky(M)
        s, U = symmetric_eigh(L.T @ K @ L)
    except np.linalg.LinAlgError as exc:
        raise SolveError(f"Eq. 5c damping: mass matrix not positive definite ({exc})") from None
    sqrt_s = (U * np.sqrt(np.clip(s, 0.0, None))) @ U.T
    # (M K)^(1/2) = L S^(1/2) L^-1, with L^-1 applied from the right by a triangular solve
    root = sla.solve_triangular(L, (L @ sqrt_s).T, lower=True, trans="T").T
    return 2.0 * xi[:, None] * root


def _first_mode_ratio(damping_ratio: float | np.ndarray, n: int) -> float:
    xi = damping_ratios(damping_ratio, n)
    if np.any(xi != xi[0]):
        raise BeamInputError(
            f"damping_ratio = {xi.tolist()}: the stiffness form takes one ratio (mode 1's); "
            "the other modes' ratios follow from the frequencies"
        )
    return float(xi[0])


def stiffness_damping_coefficient(
    M: np.ndarray, K: np.ndarray, damping_ratio: float | np.ndarray
) -> float:
    """Compute beta = 2 xi_1 / omega_1 of the stiffness form C = beta K, s.

    Parameters
    ----------
    M, K : ndarray, shape (n, n)
        Mass matrix (kg m^2) and stiffness (N m/rad) at the pose.
    damping_ratio : float or ndarray, shape (n,)
        Ratio xi_1 of mode 1 (an array must hold one value for every mode), dimensionless.
    """
    M, K = _check_pair(M, K)
    xi1 = _first_mode_ratio(damping_ratio, M.shape[0])
    w2 = generalized_eigh(K, M, "stiffness damping", vectors=False, lowest_only=True)
    if not w2[0] > 0.0:
        raise SolveError(f"stiffness damping: omega_1^2 = {w2[0]}: must be > 0")
    return 2.0 * xi1 / float(np.sqrt(w2[0]))


def stiffness_damping(M: np.ndarray, K: np.ndarray, damping_ratio: float | np.ndarray
                      ) -> np.ndarray:
    """Stiffness-proportional damping C = beta K, beta = 2 xi_1 / omega_1.

    Mode k of the linearised system gets the ratio xi_1 omega_k / omega_1.

    Parameters
    ----------
    M : ndarray, shape (n, n)
        Joint-space mass matrix at the pose, kg m^2.
    K : ndarray, shape (n, n)
        Joint stiffness, N m/rad (diagonal for the PRBDM, so C is diagonal).
    damping_ratio : float or ndarray, shape (n,)
        Ratio xi_1 of mode 1, dimensionless (an array must hold one value).

    Returns
    -------
    ndarray, shape (n, n)
        Damping matrix, N m s/rad.
    """
    return stiffness_damping_coefficient(M, K, damping_ratio) * np.asarray(K, dtype=float)


def modal_ratios(M: np.ndarray, K: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Damping ratio of each mode, diag(Phi^T C Phi) / (2 omega), ascending frequency.

    Exact for a damping matrix that the mass-normalised modes Phi of K phi = omega^2 M phi
    diagonalise (modal, stiffness-proportional); for another C it is the ratio each mode would
    have if the coupling Phi^T C Phi off the diagonal were dropped.

    Returns
    -------
    ndarray, shape (n,)
        Ratios, dimensionless (above 1: the mode is overdamped).
    """
    M, K = _check_pair(M, K)
    C = np.asarray(C, dtype=float)
    if C.shape != M.shape:
        raise BeamInputError(f"C {C.shape}: must have the shape of M {M.shape}")
    w2, phi = generalized_eigh(K, M, "modal ratios")
    omega = np.sqrt(np.clip(w2, 0.0, None))
    return np.einsum("ik,ij,jk->k", phi, C, phi) / (2.0 * omega)


def damping_matrix(
    M: np.ndarray, K: np.ndarray, damping_ratio: float | np.ndarray, kind: str = "modal"
) -> np.ndarray:
    """Compute the damping matrix of ``kind``, N m s/rad.

    ``kind`` is ``"modal"`` (default), ``"eq5c"``, ``"stiffness"`` or ``"modal_fit"`` (K
    diagonal and positive: the joint springs).
    """
    if kind == "modal":
        return modal_damping(M, K, damping_ratio)
    if kind == "eq5c":
        return eq5c_damping(M, K, damping_ratio)
    if kind == "stiffness":
        return stiffness_damping(M, K, damping_ratio)
    if kind == "modal_fit":
        from .modal_fit import modal_fit_damping

        M, K = _check_pair(M, K)
        fit = modal_fit_damping(M, np.diagonal(K), damping_ratio)
        return np.diag(fit.joint_damping_Nms_per_rad)
    raise BeamInputError(f"damping = {kind!r}: must be one of {', '.join(DAMPING_FORMS)}")
