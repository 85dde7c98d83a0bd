"""The symmetric generalised eigenproblem K phi = omega^2 M phi of a chain, and its guard.

Every frequency of the package goes through here. With a diagonal K the problem is solved
exactly through the scaling S = K^(-1/2): the eigenvalues mu of S M S are 1 / omega^2 (no inverse
of M), and the lowest frequencies come out of the largest eigenvalues, where the solver is most
accurate. The guard raises instead of answering when the spectrum is not positive, not finite,
or too ill-conditioned for the highest frequency to be accurate to ``FREQUENCY_RTOL``.
A full (not diagonal) K, as the damping forms and a MuJoCo model's mass matrix bring, goes
through :func:`generalized_eigh`, and a plain symmetric matrix through :func:`symmetric_eigh`.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
from scipy.linalg.lapack import dsyevd as _syevd

from ..errors import SolveError

__all__ = ["FREQUENCY_RTOL", "COND_LIMIT", "check_spectrum", "eig_scaled", "one_chain",
           "one_chain_unchecked", "modes_from_mass", "generalized_eigh", "symmetric_eigh"]

# Largest cond(K^-1/2 M K^-1/2) accepted. The highest omega^2 comes from the smallest eigenvalue
# mu_min of the scaled matrix, whose relative error is about eps * mu_max / mu_min (measured
# against 40-digit mpmath solves: up to 1.3 eps * cond). Beyond this limit the top frequency
# could be off by more than FREQUENCY_RTOL, so the solvers raise instead of answering.
FREQUENCY_RTOL = 1e-6
COND_LIMIT = FREQUENCY_RTOL / np.finfo(float).eps
# above these the overflow checks cannot fail and are skipped: 1 / mu < max double / 2, and
# (1 / s)^2 / mu <= 1e300
_SAFE_INVERSE = 2.0 / np.finfo(float).max
_SAFE_SCALE = 1e-100


def check_spectrum(mu: np.ndarray) -> None:
    """Raise SolveError unless every row of eigenvalues ``mu`` of S M S is well conditioned.

    Each row of ascending eigenvalues must be positive, finite and within ``COND_LIMIT``.
    """
    # the common case in one pass (NaN fails every comparison): the full checks below only
    # run to find what is wrong; one row (the fits' inner loop) in Python floats, cheaper
    # than numpy's calls on a few numbers
    if mu.ndim == 1 or mu.shape[0] == 1:
        v = mu.reshape(-1).tolist()
        if v[0] > 0.0 and v[-1] / v[0] <= COND_LIMIT and all(map(math.isfinite, v)):
            return
    lo, hi = mu[..., 0], mu[..., -1]
    if (lo > 0.0).all() and np.isfinite(mu).all() and (hi / lo).max() <= COND_LIMIT:
        return
    if not np.all(np.isfinite(mu)):
        raise SolveError("eigenvalues are not finite: the mass or stiffness values overflow "
                         "double precision")
    # an eigenvalue below zero by more than rounding: M itself is not positive definite
    if np.any(lo < -1e-12 * np.abs(hi)) or not np.all(hi > 0.0):
        raise SolveError("mass matrix is not positive definite: frequencies are undefined")
    with np.errstate(divide="ignore"):
        cond = np.where(lo > 0.0, hi / np.where(lo > 0.0, lo, 1.0), np.inf)
    worst = int(np.argmax(cond)) if cond.ndim else 0
    c = float(np.max(cond))
    if c > COND_LIMIT:
        where = f" (pose {worst})" if cond.ndim else ""
        raise SolveError(
            f"frequencies cannot be trusted{where}: cond(K^-1/2 M K^-1/2) = {c:.3g} exceeds "
            f"{COND_LIMIT:.3g}, so the highest frequency could be off by more than "
            f"{FREQUENCY_RTOL:g} relative in double precision; check the spread of the joint "
            "stiffness and of the link lengths"
        )


def _eigvalsh(A: np.ndarray, lower: int) -> np.ndarray:
    """Eigenvalues (ascending) of one small symmetric matrix from one triangle, by LAPACK directly.

    ``lower=1`` reads the triangle ``np.linalg.eigvalsh`` reads, so the two agree; this skips
    numpy's batched wrapper, which costs more than the solve for a small matrix.
    """
    mu, _, info = _syevd(A, compute_v=0, lower=lower)
    if info != 0:
        raise SolveError(f"symmetric eigensolver failed (LAPACK info {info})")
    return mu


def one_chain(M: np.ndarray, s: np.ndarray, squared: bool = False, lower: bool = False,
              q: np.ndarray | None = None) -> np.ndarray | None:
    """Frequencies of one chain by one compiled call (:mod:`.small_eigen`), or None.

    ``M`` (n, n), kg m^2, float64 (only the triangle ``lower`` is read) and s = K^(-1/2)
    (n,), (N m/rad)^(-1/2), finite and > 0 (no input checks); ``q`` (float64, rad) the pose
    M was computed at, None if none: a non-finite one is refused. Returns omega (rad/s) or, with
    ``squared``, omega^2, ascending, as :func:`eig_scaled`; None when the spectrum does not pass
    the guard's common case at once (then :func:`eig_scaled`'s LAPACK path decides, and raises).
    """
    # the compiled entry point does not check types: float64 arrays of the right dimensions
    # only (dtype singletons: ``is`` is the cheap test, a false negative only costs time)
    if q is None:
        q = _NO_POSE
    if M.dtype is not _F8 or s.dtype is not _F8 or M.ndim != 2 or s.ndim != 1 \
            or q.dtype is not _F8 or q.ndim != 1:
        return None
    return one_chain_unchecked(M, s, q, squared, lower)


def one_chain_unchecked(M: np.ndarray, s: np.ndarray, q: np.ndarray, squared: bool = False,
                        lower: bool = False) -> np.ndarray | None:
    """:func:`one_chain` for float64 arrays M (n, n), s (n,) and q (any size, 1-D) only.

    The compiled entry point unboxes them without checks: a caller that cannot promise these
    types and dimensions calls :func:`one_chain`.
    """
    global _SCALED_OMEGA
    if _SCALED_OMEGA is None:  # numba is imported on first use, not with the package
        from .small_eigen import scaled_omega_entry

        _SCALED_OMEGA = scaled_omega_entry()
    out = np.empty(s.shape[0])
    if _SCALED_OMEGA(M, s, q, out, squared, lower, COND_LIMIT, _SAFE_SCALE):
        return out
    return None


_SCALED_OMEGA = None
# In a process that has not loaded numba, the first compiled call costs about
# 0.25 s of CPU (import numba ~0.10 s; its typing and target registries, set up at the first
# cached function, ~0.14 s; each further cached function a few ms), measured by
# scripts/bench_oneshot_load.py; the compiled one-chain solve saves ~9 us a call (5R: 11 ->
# 2 us), so it pays from some 30,000 solves in a process, not for one.
_F8 = np.dtype(np.float64)
_NO_POSE = np.empty(0)


def _check_finite(w2: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(w2)):
        raise SolveError("omega^2 overflows double precision: the stiffness is too large for "
                         "the mass (check the units)")
    return w2


def eig_scaled(M: np.ndarray, s: np.ndarray, squared: bool = False,
               compiled: bool = True) -> np.ndarray:
    """Compute frequencies from mass matrices and scaled springs.

    Frequencies are in rad/s, ascending (omega^2 in rad^2/s^2 when ``squared``), from mass
    matrices M (n, n) or (m, n, n), kg m^2, and s = K^(-1/2) (n,) or (m, n), (N m/rad)^(-1/2).
    ``compiled=False`` skips the compiled one-chain solve and its numba load: a caller that
    solves once per command (an export's record, the default integrator's rule) would pay
    ~0.25 s of CPU loading numba in a fresh process to save ~9 us (the note at the module's
    end).

    No input checks: the callers validate once. Raises SolveError when the guard
    (:func:`check_spectrum`) refuses the spectrum or omega^2 overflows.
    """
    if compiled and M.ndim == 2 and s.ndim == 1:
        w = one_chain(M, s, squared)
        if w is not None:
            return w
    elif compiled and M.shape[0] == 1 and s.ndim == 2:
        # the fits' stack of one: the triangle eigvalsh reads
        w = one_chain(M[0], s[0], squared, lower=True)
        if w is not None:
            return w[None]
    # S normalised to max 1 keeps S M S as large as M: no underflow for stiff springs
    smax = np.maximum.reduce(s, axis=-1, keepdims=True)
    sn = s / smax
    A = M * sn[..., :, None] * sn[..., None, :]
    if A.ndim == 2:
        mu = _eigvalsh(A, lower=0)
    elif A.shape[0] == 1:  # a stack of one (the fits' inner loop): the same as eigvalsh's
        mu = _eigvalsh(A[0], lower=1)[None]
    else:
        mu = np.linalg.eigvalsh(A)  # ascending, batched over the stack
    check_spectrum(mu)
    if np.minimum.reduce(smax, axis=None) >= _SAFE_SCALE and np.minimum.reduce(
            mu[..., 0], axis=None) >= _SAFE_SCALE:
        w2 = (1.0 / smax) ** 2 / mu[..., ::-1]  # at most 1e300: finite, no check needed
    else:
        with np.errstate(over="ignore"):
            w2 = _check_finite((1.0 / smax) ** 2 / mu[..., ::-1])
    return w2 if squared else np.sqrt(w2)


def modes_from_mass(
    M: np.ndarray, stiffness_Nm_per_rad: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (rad/s, ascending) and mass-normalised mode shapes of stacked problems.

    ``M`` is (m, n, n), kg m^2, and ``stiffness_Nm_per_rad`` (n,) or (m, n) (no input checks);
    returns omega (m, n) and Phi (m, n, n) with Phi[i]^T M[i] Phi[i] = I and
    Phi[i]^T K Phi[i] = diag(omega[i]^2), under the guard of :func:`eig_scaled`.
    """
    s = np.empty(M.shape[:2])  # broadcast_to costs more than this copy for small n
    s[...] = 1.0 / np.sqrt(stiffness_Nm_per_rad)
    A = M * s[:, :, None] * s[:, None, :]
    if A.shape[0] == 1:  # one small matrix (the fits' Jacobians): LAPACK directly
        mu, V, info = _syevd(A[0], compute_v=1, lower=0)
        if info != 0:
            raise SolveError(f"symmetric eigensolver failed (LAPACK info {info})")
        mu, V = mu[None], V[None]
    else:
        mu, V = np.linalg.eigh(A)
    check_spectrum(mu)
    if not np.minimum.reduce(mu[:, 0]) >= _SAFE_INVERSE:  # 1 / mu may overflow: check it
        with np.errstate(over="ignore", divide="ignore"):
            _check_finite(1.0 / mu)
    mu, V = mu[:, ::-1], V[:, :, ::-1]
    # K^(1/2) phi = V/sqrt(mu) makes phi^T M phi = v^T (S M S) v / mu = 1
    Phi = s[:, :, None] * V / np.sqrt(mu)[:, None, :]
    return np.sqrt(1.0 / mu), Phi


def generalized_eigh(
    K: np.ndarray, M: np.ndarray, what: str, vectors: bool = True, lowest_only: bool = False
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Solve K phi = omega^2 M phi for omega^2 (rad^2/s^2, ascending).

    K (N m/rad) and M (kg m^2) are full symmetric, shape (n, n); with ``vectors`` also the
    modes Phi, Phi^T M Phi = I.

    ``lowest_only`` returns omega_1^2 alone, shape (1,) (no vectors). A failed solve (M not
    positive definite, non-finite entries) raises SolveError naming ``what``; the callers
    decide what a non-positive omega^2 means.
    """
    try:
        if vectors:
            return sla.eigh(K, M)
        return sla.eigh(K, M, eigvals_only=True,
                        subset_by_index=[0, 0] if lowest_only else None)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolveError(f"{what}: generalized eigenproblem failed ({exc})") from None


def symmetric_eigh(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Compute eigenvalues (ascending) and orthonormal eigenvectors of a symmetric A (n, n).

    Eigenvalues are in A's units; this is the standard problem a Cholesky factor of M turns
    the generalised one into.
    """
    return np.linalg.eigh(A)
