"""The planar chain's equilibrium under a dead tip force from the straight pose, compiled first.

:func:`prbdm_pin.chain.statics.static_deflection_planar` from the straight pose, with its
defaults, as a linearisation under a load asks for it: the load's guard
(:func:`prbdm_pin.chain.statics_guard.check_load`), then the compiled descent of
:mod:`.planar_statics_kernel`; wherever that descent does not converge at once, the numpy
path from the start (load stepping, saddle escape, its errors).
"""

from __future__ import annotations

import numpy as np

from .statics import static_deflection_planar_unchecked
from .statics_guard import check_load

__all__ = ["static_deflection_straight"]

_NEWTON = None


def static_deflection_straight(lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                               tip_force_N: np.ndarray, rtol: float = 1e-10,
                               max_iter: int = 60, max_step_rad: float = 0.5) -> np.ndarray:
    """Return the equilibrium joint angles (rad, (n,)) from the straight pose.

    Parameters
    ----------
    lengths_m : ndarray (n+1,)
        Link lengths, m, finite floats.
    stiffness_Nm_per_rad : ndarray (n,)
        Joint springs, N m/rad, finite and > 0.
    tip_force_N : ndarray (3,)
        Dead world tip force, N, finite (its y component does not act on the planar chain).
    rtol, max_iter, max_step_rad : float, int, float
        As :func:`prbdm_pin.chain.statics.static_deflection_planar`.

    Raises
    ------
    SolveError
        A load double precision cannot resolve, or no equilibrium.

    Examples
    --------
    >>> import numpy as np
    >>> from prbdm_pin.chain.planar_statics_fast import static_deflection_straight
    >>> q = static_deflection_straight(np.array([0.0, 1.0]), np.array([100.0]),
    ...                                np.array([0.0, 0.0, -1.0]))
    >>> round(float(100.0 * q[0] - np.cos(q[0])), 12)  # k q = F L cos q
    0.0
    """
    global _NEWTON
    F = tip_force_N
    n = stiffness_Nm_per_rad.size
    if F[0] == 0.0 and F[2] == 0.0:
        return np.zeros(n)  # no in-plane load: the straight pose is the only minimum
    check_load(lengths_m, stiffness_Nm_per_rad, F, rtol)
    if _NEWTON is None:  # numba is imported on first use, not with the package
        from .planar_statics_kernel import planar_newton

        _NEWTON = planar_newton
    q = np.zeros(n)
    if _NEWTON(lengths_m, stiffness_Nm_per_rad, float(F[0]), float(F[2]), rtol, max_iter,
               max_step_rad, q):
        return q
    return static_deflection_planar_unchecked(lengths_m, stiffness_Nm_per_rad, F, np.zeros(n),
                                              rtol, max_iter, max_step_rad)
