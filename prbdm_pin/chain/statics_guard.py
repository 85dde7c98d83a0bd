"""Loads the planar statics solver can answer in double precision, and its finiteness guard.

The solver stops when ||K q - J^T F|| <= rtol max(||K q||, ||J^T F||). The terms of J^T F are
sums of L_i (F_x sin phi_i, F_z cos phi_i), each rounded to about ``eps |F| L`` (eps = 2.2e-16),
so the residual carries a rounding floor of ``eps |F| L`` whatever q is. At an equilibrium
||K q|| is at most ``k_max |q|_1 <= k_max pi`` (a chain under a dead load turns at most half a
turn towards it), so once::

    eps |F| L > rtol pi k_max,   i.e.   alpha = |F| L / k_max > pi rtol / eps  (1.4e6 at rtol 1e-10)

the test can only pass by rounding luck, and the answer is not an equilibrium of the model: the
chain lies along the load to within the rounding of the angles. ``alpha`` is the chain's load index
(P L^2 / EI of a beam with EI / L ~ k). Separately, the squared norms overflow (and ``inf <= inf``
passes) once ``|F| L`` or k_max pi exceed sqrt(max double / (n + 1)); both loads are refused.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SolveError

__all__ = ["load_index", "max_load_index", "check_load", "load_ok_rows", "require_finite",
           "off_saddle"]

_EPS = float(np.finfo(float).eps)
_MAX = float(np.finfo(float).max)


def max_load_index(rtol: float) -> float:
    """Return the largest load index ``|F| L / k_max`` the convergence test ``rtol`` resolves.

    No bound for ``rtol <= 0``, an exact test that the iteration itself passes or stalls on.
    """
    return math.pi * rtol / _EPS if rtol > 0.0 else math.inf


def _magnitude_cap(n: int) -> float:
    # the solver squares and sums n + 1 terms of this size
    return math.sqrt(_MAX / (n + 1))


def load_index(arm_m: np.ndarray, k_max: np.ndarray, force_N: float) -> np.ndarray:
    """Compute the load index ``|F| L / k_max`` (dimensionless) of chains.

    The chains have lever arms ``arm_m`` (m, the summed lengths after the first joint) and
    stiffest springs ``k_max`` (N m/rad), under ``|F| = force_N`` (N).
    """
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        return _index(np.asarray(arm_m, dtype=float), np.asarray(k_max, dtype=float), force_N)


def _index(arm_m, k_max, force_N):
    # without load_index's floating-point guard: the caller holds one
    return force_N * arm_m / k_max


def load_ok_rows(lengths_m: np.ndarray, k: np.ndarray, force: np.ndarray,
                 rtol: float) -> np.ndarray:
    """Tell, per row, whether the load ``force`` (N) is within what double precision resolves.

    Rows of ``lengths_m`` (B, n+1), m, and ``k`` (B, n), N m/rad; see the module notes.
    """
    f = math.hypot(float(force[0]), float(force[2]))
    arm = np.sum(lengths_m[:, 1:], axis=1)
    kmax = np.max(k, axis=1)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        return _resolvable(arm, kmax, f, rtol, k.shape[1])


def _resolvable(arm, kmax, f: float, rtol: float, n: int):
    """Run the test of :func:`load_ok_rows` on arrays, or on floats (with ``kmax`` > 0)."""
    cap = _magnitude_cap(n)
    return ((_index(arm, kmax, f) <= max_load_index(rtol)) & (f * arm <= cap)
            & (kmax * math.pi <= cap))


def check_load(lengths_m: np.ndarray, k: np.ndarray, force: np.ndarray, rtol: float) -> None:
    """Raise SolveError naming the load when it is beyond what double precision resolves."""
    L = np.asarray(lengths_m, dtype=float)
    k = np.asarray(k, dtype=float)
    f = math.hypot(float(force[0]), float(force[2]))
    # one chain (every static solve of a fit) in Python floats, unless k_max <= 0 or NaN
    # (where numpy's division rules decide)
    arm, kmax = float(np.add.reduce(L[1:])), float(np.maximum.reduce(k))
    if (_resolvable(arm, kmax, f, rtol, k.size) if kmax > 0.0
            else load_ok_rows(L[None, :], k[None, :], force, rtol)[0]):
        return
    alpha = float(load_index(np.sum(L[1:]), np.max(k), f))
    raise SolveError(
        f"tip_force = {np.asarray(force).tolist()} N: load index |F| L / k_max = {alpha:.3g} "
        f"is beyond {max_load_index(rtol):.3g} (pi rtol / eps) or overflows: the equilibrium "
        "cannot be resolved in double precision (the chain lies along the load)")


def require_finite(force: np.ndarray, *values: float) -> None:
    """Raise SolveError when a residual norm, scale or potential is not finite."""
    if not all(map(math.isfinite, values)):
        raise SolveError(f"static deflection under tip_force = {np.asarray(force).tolist()} N: "
                         "the residual is not finite (the load or springs overflow double "
                         "precision)")


def off_saddle(pot, q: np.ndarray, step_rad: float = 1e-2) -> np.ndarray:
    """Move ``q`` (rad) by ``step_rad`` along the Hessian's most negative curvature.

    The step goes downhill in V; where V is convex ``q`` itself is returned. It gives a start
    for a descent that crawls near a saddle (a straight column past its buckling load), with
    ``pot`` a :class:`prbdm_pin.chain.planar.ChainPotential`.
    """
    _, H, _ = pot.derivatives(q, 1.0)
    w, V = np.linalg.eigh(H)
    if w[0] > 0.0:
        return q
    a, b = q + step_rad * V[:, 0], q - step_rad * V[:, 0]
    return a if pot.value(a, 1.0) <= pot.value(b, 1.0) else b
