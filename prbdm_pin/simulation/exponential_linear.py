"""The linear part of the exponential integrator (``exponential``).

The eigen-decomposition of the Jacobian, the weak springs that keep it diagonalisable on a
coordinate without a spring (a hub), and the continuous extension: a step's formula at any
offset into the step (exact for the linear part).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import scipy.linalg

from ..errors import SolveError
from .phi import phi123, phi1234
from .system import symmetrised

# a coordinate without a spring gets one in the Jacobian at this fraction of the lowest
# flexible frequency (see soft_springs)
SOFT_RATIO = 1e-3


def eig_with_inverse(J: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues lam, eigenvectors V and V^-1 of a real matrix; SolveError when defective.

    ``t`` (s) is the time the Jacobian was built at, for the message.
    """
    try:
        lam, V = np.linalg.eig(J)
        return lam, V, np.linalg.inv(V)
    except np.linalg.LinAlgError:
        raise SolveError(f"exponential integrator: defective or non-finite Jacobian at "
                         f"t = {t:.6g} s") from None


def soft_springs(pm, data, q0: np.ndarray, k_const: np.ndarray) -> np.ndarray | None:
    """Return soft springs (N m/rad) for the coordinates without a spring, for the Jacobian.

    They put each coordinate without a spring (a hub) at ``SOFT_RATIO`` times the lowest
    flexible frequency; None when every coordinate has a spring.

    A free coordinate with no damping makes the Jacobian defective (a Jordan block at 0: the
    rigid rotation's angle grows with its rate), and an eigen-decomposition of it is
    meaningless. With the soft spring the rigid mode becomes a slow oscillation with distinct
    eigenvalues; the dynamics themselves keep no spring: the difference, -k_soft q, is part
    of the remainder the method evaluates at every step, and its effect shrinks with
    (omega_soft h)^2.
    """
    free = k_const == 0.0
    if not np.any(free):
        return None
    M = symmetrised(pin.crba(pm, data, q0))
    sprung = ~free
    w2 = scipy.linalg.eigh(np.diag(k_const[sprung]), _schur(M, free), eigvals_only=True)
    soft = np.zeros_like(k_const)
    soft[free] = (SOFT_RATIO ** 2 * float(w2[0])) * np.diag(M)[free]
    return soft


def _schur(M: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Return the sprung coordinates' mass with the free ones left to move, kg m^2."""
    a, b = M[np.ix_(~free, ~free)], M[np.ix_(~free, free)]
    return a - b @ np.linalg.solve(M[np.ix_(free, free)], b.T)


def continuous_extension(y_start: np.ndarray, record: tuple, t_s: np.ndarray) -> np.ndarray:
    """Return the states (q, v) at the times ``t_s`` (s) of one step, shape (len(t_s), 2n).

    The step's formula with h replaced by the offset s from its start (at most h), from its
    start state ``y_start`` and its record: exact for the linear part. exprb32's record holds
    the start time (s), the step (s), the eigenvalues, the eigenvectors and the modal
    coefficients of the rate, the correction and the forcing; exprb43's the remainder's s^2
    and s^3 terms in place of the correction (``exponential_rb43``).
    """
    if len(record) == 8:
        return _cubic_extension(y_start, record, t_s)
    # the same array shapes (one row per sample) as when every step was sampled at once, so
    # the samples keep their bits
    m = len(t_s)
    start, h, lam, V, c1, cd, cb = record
    hs = np.full((m, 1), h)
    s_col = np.minimum(t_s - start, hs[:, 0])[:, None]
    p1, p2, p3 = phi123(s_col * np.repeat(lam[None], m, axis=0))
    coef = (s_col * p1 * c1 + (2.0 * s_col**3 / hs**2) * p3 * cd + s_col**2 * p2 * cb)
    Vs = np.repeat(V[None], m, axis=0)
    return np.repeat(y_start[None], m, axis=0) + np.einsum("sij,sj->si", Vs, coef).real


def _cubic_extension(y_start: np.ndarray, record: tuple, t_s: np.ndarray) -> np.ndarray:
    """exprb43's continuous extension: the remainder a s^2 + c s^3 propagated exactly."""
    start, h, lam, V, c1, cq, cc, cb = record
    s_col = np.minimum(t_s - start, h)[:, None]
    p1, p2, p3, p4 = phi1234(s_col * lam[None])
    coef = (s_col * p1 * c1 + s_col**2 * p2 * cb + 2.0 * s_col**3 * p3 * cq
            + 6.0 * s_col**4 * p4 * cc)
    return y_start[None] + (coef @ V.T).real
