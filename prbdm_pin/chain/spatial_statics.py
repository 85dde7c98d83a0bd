"""Large-deflection statics of a spatial chain under a dead tip force and moment.

Solves K q = J(q)^T w (w the tip force and moment, fixed in the world, at the tip point) for a
serial chain of revolute joints about x, y or z, with the exact tangent stiffness of
:mod:`.spatial_tangent`:

- under a force alone the load has a potential V = 1/2 q^T K q - f . p_tip, and each solve is a
  damped Newton descent on V (the planar solver's method, :mod:`.statics`): Armijo backtracking,
  the Hessian's negative curvature left along its eigenvectors, converged only at a minimum;
- a dead moment has no potential in three dimensions, so each solve is Newton on the residual
  with backtracking on ||r||.

The full load is tried first; if it fails (or, under a moment, always), the load is applied in
adaptive steps lambda w, lambda from 0 to 1 (continuation): a tangent predictor
dq/dlambda = T^-1 J^T w, a corrector at the new load, a step accepted when the corrector
converges within ``max_step_rad`` of the prediction on a tangent that has not lost its
stability (positive definite under a force alone, det T > 0 under a moment: the branch that
starts at the unloaded chain). Loads double precision cannot resolve are refused as the planar
solver refuses them (:mod:`.statics_guard`).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError, SolveError
from .pin_dynamics import checked_stiffness
from .spatial_tangent import ChainLoad, check_chain, checked_wrench
from .statics_guard import load_index, max_load_index

__all__ = ["spatial_static_deflection"]


def _pd(T: np.ndarray) -> bool:
    try:
        np.linalg.cholesky(T)
    except np.linalg.LinAlgError:
        return False
    return True


def _stable(T: np.ndarray, descend: bool) -> bool:
    # a minimum of V under a force alone; under a moment no real eigenvalue crossed zero
    return _pd(T) if descend else np.linalg.slogdet(T)[0] > 0.0


def _direction(T: np.ndarray, r: np.ndarray, descend: bool, converged: bool, max_step: float
               ) -> np.ndarray | None:
    """Newton step (rad), eigen-modified where V is not convex; None if T is singular."""
    if descend and not _pd(T):
        w, V = np.linalg.eigh(T)
        if converged:  # a stationary point that is not a minimum: leave it downhill
            return V[:, 0] * min(max_step, 1e-2)
        floor = 1e-8 * max(float(np.max(np.abs(w))), 1e-300)
        return -V @ ((V.T @ r) / np.maximum(np.abs(w), floor))
    try:
        return -np.linalg.solve(T, r)
    except np.linalg.LinAlgError:
        return None


def _newton(ch: ChainLoad, q: np.ndarray, lam: float, rtol: float, max_iter: int,
            max_step: float, descend: bool) -> tuple[np.ndarray, bool]:
    """Damped Newton at load ``lam`` from ``q``: a descent on V if ``descend``, else on ||r||."""
    for _ in range(max_iter + 1):
        r, rn, scale, T, _ = ch.eval(q, lam)
        converged = rn <= rtol * scale
        if converged and (not descend or _pd(T)):
            return q, True
        d = _direction(T, r, descend, converged, max_step)
        step = math.nan if d is None else float(np.max(np.abs(d)))
        if not math.isfinite(step):
            return q, False
        if step > max_step:
            d *= max_step / step
        v0, slope = (ch.potential(q, lam), min(float(r @ d), 0.0)) if descend else (0.0, 0.0)
        alpha = 1.0
        for _ in range(40):
            qn = q + alpha * d
            rn_new = ch.eval(qn, lam, tangent=False)[1]
            if descend:
                # Armijo on V; near the solution V stops resolving the decrease, so a step that
                # halves the gradient is accepted as well (the planar solver's rule)
                if ch.potential(qn, lam) <= v0 + 1e-4 * alpha * slope or rn_new < 0.5 * rn:
                    break
            elif rn_new <= (1.0 - 1e-4 * alpha) * rn:
                break
            alpha *= 0.5
        else:
            return q, False
        q = qn
    return q, False


def _follow(ch: ChainLoad, q: np.ndarray, rtol: float, max_iter: int, max_step: float,
            max_steps: int, descend: bool) -> tuple[np.ndarray, float, str]:
    """Continuation in the load factor from ``q`` (load 0).

    Returns q, the load factor reached and why it stopped short of 1 ("" if it did not).
    """
    lam, dlam = 0.0, 1.0
    for _ in range(max_steps):
        target = min(1.0, lam + dlam)
        _, _, _, T, J = ch.eval(q, lam)
        try:
            rate = np.linalg.solve(T, J.T @ ch.w)  # dq/dlambda on the path
        except np.linalg.LinAlgError:
            rate = np.zeros(q.size)  # a singular tangent: predict no change
        big = float(np.max(np.abs(rate))) * (target - lam)
        if not math.isfinite(big):
            rate, big = np.zeros(q.size), 0.0
        if big > max_step:  # the predictor turns no joint by more than max_step
            target = lam + (target - lam) * max_step / big
        qp = q + (target - lam) * rate
        qn, ok = _newton(ch, qp, target, rtol, max_iter, max_step, descend)
        if (ok and float(np.max(np.abs(qn - qp))) <= max_step
                and _stable(ch.eval(qn, target)[3], descend)):
            q, dlam, lam = qn, 2.0 * (target - lam), target
            if lam >= 1.0:
                return q, lam, ""
        else:
            dlam = 0.5 * (target - lam)
            if dlam < 1e-7:
                return q, lam, "load stepping stalled"
    return q, lam, f"{max_steps} load steps"


def spatial_static_deflection(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    tip_frame_id: int,
    tip_force_N: np.ndarray,
    tip_moment_Nm: np.ndarray | None = None,
    q0: np.ndarray | None = None,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
    max_load_steps: int = 2000,
) -> np.ndarray:
    """Equilibrium joint angles (rad) of a chain of revolute joints under a dead tip wrench.

    Damped Newton with the exact tangent stiffness, with load stepping when the full load
    fails (module notes). Converged means ||K q - J^T w|| <= rtol max(||K q||, ||J^T w||),
    at a minimum of V under a force alone.

    Parameters
    ----------
    pin_model, data : pinocchio.Model, pinocchio.Data
        A serial chain of revolute joints about x, y or z (``nq == nv``) and its workspace.
    stiffness_Nm_per_rad : array_like, shape (nv,)
        Joint springs, N m/rad.
    tip_frame_id : int
        The frame the load acts at, on the last joint.
    tip_force_N : array_like, shape (3,)
        Dead tip force, N, world axes.
    tip_moment_Nm : array_like, shape (3,), optional
        Dead tip moment, N m, world axes (default none).
    q0 : array_like, shape (nv,), optional
        Start pose, rad (default straight).
    rtol : float
        Relative residual of convergence.
    max_iter, max_step_rad, max_load_steps : int, float, int
        Newton iterations per solve, the largest change of one joint angle (rad) in one Newton
        or predictor step, and the cap on load steps.

    Returns
    -------
    ndarray, shape (nv,)
        Joint angles, rad.

    Raises
    ------
    BeamInputError
        A load or start pose of the wrong shape or not finite (the message names
        ``tip_force``, ``tip_moment`` or ``q0``), a model that is not a serial chain of
        revolute joints.
    SolveError
        A force beyond what double precision resolves, or no equilibrium found.
    """
    arm = check_chain(pin_model, tip_frame_id)
    n = pin_model.nv
    k = checked_stiffness(stiffness_Nm_per_rad, n)
    w = checked_wrench(tip_force_N, tip_moment_Nm)
    q = np.zeros(n) if q0 is None else np.array(q0, dtype=float)
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise BeamInputError(f"q0 = {q.tolist()}: must be {n} finite joint angles (rad)")
    alpha = float(load_index(arm, float(np.max(k)), float(np.linalg.norm(w[:3]))))
    if not alpha <= max_load_index(rtol):  # the planar guard's bound (statics_guard notes)
        raise SolveError(f"tip_force = {w[:3].tolist()} N: load index |F| L / k_max = "
                         f"{alpha:.3g} is beyond {max_load_index(rtol):.3g} (pi rtol / eps): "
                         "the equilibrium cannot be resolved in double precision")
    if not np.any(w):
        return np.zeros(n)  # V = 1/2 q^T K q: the straight pose
    ch = ChainLoad(pin_model, data, k, tip_frame_id, w)
    descend = not np.any(w[3:])
    args = (rtol, max_iter, max_step_rad)
    if descend:
        q1, ok = _newton(ch, q, 1.0, *args, True)
        if ok:
            return q1
    qf, lam, why = _follow(ch, q, *args, max_load_steps, descend)
    if lam >= 1.0:
        return qf
    if descend:
        # the path stalls at a bifurcation of the straight pose (a column past buckling):
        # leave the full load's stationary point along its negative curvature
        d = np.linalg.eigh(ch.eval(q1, 1.0)[3])[1][:, 0] * 1e-2
        a, b = q1 + d, q1 - d
        qs, ok = _newton(ch, a if ch.potential(a, 1.0) <= ch.potential(b, 1.0) else b, 1.0,
                         rtol, 4 * max_iter, max_step_rad, True)
        if ok:
            return qs
    raise SolveError(f"static deflection: no equilibrium beyond {lam:.4g} of the load "
                     f"tip_force = {w[:3].tolist()} N, tip_moment = {w[3:].tolist()} N m "
                     f"({why}; the angles of a y, z, x node whose z joint nears +-90 deg, gimbal "
                     "lock, change fast along the path)")
