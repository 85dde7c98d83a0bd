"""The planar chain's equilibrium under a dead tip force, compiled first.

:func:`prbdm_pin.chain.statics.static_deflection_planar_unchecked` from a given pose (a fit's
warm start) or from the straight pose (a linearisation under a load): the load's guard
(:func:`prbdm_pin.chain.statics_guard.check_load`), then the compiled descent of
:mod:`.planar_statics_kernel`; wherever that descent does not converge at once, the numpy
path from the start (load stepping, saddle escape, its errors).
"""

from __future__ import annotations

import numpy as np

from .compiled_entry import entry_point
from .statics import static_deflection_planar_unchecked
from .statics_guard import check_load

__all__ = ["static_deflection_straight", "static_deflection_warm", "static_tip_warm"]

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
    return static_deflection_warm(lengths_m, stiffness_Nm_per_rad, tip_force_N,
                                  np.zeros(stiffness_Nm_per_rad.size), rtol, max_iter,
                                  max_step_rad)


def static_deflection_warm(lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                           tip_force_N: np.ndarray, q0: np.ndarray, rtol: float = 1e-10,
                           max_iter: int = 60, max_step_rad: float = 0.5) -> np.ndarray:
    """Return the equilibrium joint angles (rad, (n,)) from the pose ``q0``.

    As :func:`static_deflection_straight` from ``q0`` (rad, (n,), finite, not modified): a
    fit's static solve from the last design's equilibrium; where the compiled descent does
    not converge at once, the numpy path from ``q0``.

    Raises
    ------
    SolveError
        A load double precision cannot resolve, or no equilibrium.

    Examples
    --------
    >>> import numpy as np
    >>> from prbdm_pin.chain.planar_statics_fast import static_deflection_warm
    >>> L, k, F = np.array([0.0, 1.0]), np.array([100.0]), np.array([0.0, 0.0, -1.0])
    >>> q = static_deflection_warm(L, k, F, np.array([0.3]))  # from 0.3 rad
    >>> round(float(100.0 * q[0] - np.cos(q[0])), 12)  # k q = F L cos q
    0.0
    """
    return _solve(lengths_m, stiffness_Nm_per_rad, tip_force_N, q0, rtol, max_iter,
                  max_step_rad, None)


def static_tip_warm(lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                    tip_force_N: np.ndarray, q0: np.ndarray, rtol: float = 1e-10,
                    max_iter: int = 60, max_step_rad: float = 0.5
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Return the equilibrium (rad, (n,)) from ``q0`` and the tip position there (m, (3,)).

    :func:`static_deflection_warm` and the tip (x, 0, z) in the same compiled call (a fit's
    tip rows); every argument a float64 array or float of the shapes given there.

    Examples
    --------
    >>> import numpy as np
    >>> from prbdm_pin.chain.planar_statics_fast import static_tip_warm
    >>> L, k, F = np.array([0.5, 1.0]), np.array([100.0]), np.array([0.0, 0.0, -1.0])
    >>> q, tip = static_tip_warm(L, k, F, np.zeros(1))
    >>> tip.round(6), round(float(0.5 + np.cos(q[0])), 6), round(float(-np.sin(q[0])), 6)
    (array([ 1.49995 ,  0.      , -0.009999]), 1.49995, -0.009999)
    """
    tip = np.empty(3)
    return _solve(lengths_m, stiffness_Nm_per_rad, tip_force_N, q0, rtol, max_iter,
                  max_step_rad, tip), tip


_NEWTON_TIP = _TIP = None


def _load_kernels() -> None:
    """Load the compiled descent and tip (numba is imported on first use, not with the package)."""
    global _NEWTON, _NEWTON_TIP, _TIP
    if _NEWTON is None:
        from . import planar_statics_kernel as kernel

        _NEWTON = kernel.planar_newton
        _NEWTON_TIP = entry_point(kernel.planar_newton_tip)
        _TIP = entry_point(kernel.tip_into)


def _solve(lengths_m, stiffness_Nm_per_rad, tip_force_N, q0, rtol, max_iter, max_step_rad,
           tip):
    """Return the equilibrium from ``q0``, compiled first; the tip there into ``tip`` if given."""
    _load_kernels()
    F = tip_force_N
    n = stiffness_Nm_per_rad.size
    if F[0] == 0.0 and F[2] == 0.0:
        q = np.zeros(n)  # no in-plane load: the straight pose is the only minimum
    else:
        check_load(lengths_m, stiffness_Nm_per_rad, F, rtol)
        q = q0.copy()
        if tip is None:
            if _NEWTON(lengths_m, stiffness_Nm_per_rad, float(F[0]), float(F[2]), rtol,
                       max_iter, max_step_rad, q):
                return q
        elif _NEWTON_TIP(lengths_m, stiffness_Nm_per_rad, float(F[0]), float(F[2]),
                         float(rtol), int(max_iter), float(max_step_rad), q, tip):
            return q
        q = static_deflection_planar_unchecked(lengths_m, stiffness_Nm_per_rad, F, q0, rtol,
                                               max_iter, max_step_rad)
    if tip is not None:
        _TIP(lengths_m, q, tip)
    return q
