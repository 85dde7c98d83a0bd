"""One fit start's local solvers, one per parametrisation, and the polish of a ``paper`` optimum.

The polish is that of a ``paper`` eigen optimum; the solvers are chosen for accuracy per model
evaluation (see ``scripts/bench_fit.py`` and ``scripts/bench_fit_jacobian.py``). The joint
deflection and combined fits run the resumable geodesic Levenberg-Marquardt solver
(``geodesic_lm.py``) in two calls, :func:`explore_start` and :func:`refine_start`, so that a
multistart can continue only its best starts (``explore.py``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .geodesic_lm import LMState, lm_advance, lm_start
from .joint import JointResiduals
from .paper import PaperEigenResiduals, PaperScalarLoss
from .problem import unit_from_lengths
from .spec import LN_S_BOUNDS, FitSpec, StartResult

__all__ = ["solve_start", "solve_joint_start", "solve_paper_start", "explore_start",
           "refine_start", "joint_box", "polish_paper_eigen"]


def _ls(fun, x0, lb, ub, max_nfev, jac="2-point", tol=1e-10, method="dogbox", x_scale=1.0):
    from scipy.optimize import least_squares

    # measured: dogbox needs ~3x fewer evaluations than trf on the zero-residual joint eigen
    # fits; trf is faster and finds the better basins on the non-zero-residual fits (projected
    # paper eigen, combined): dogbox stalled at 0.13-0.34 % where trf reached 0.04-0.05 %
    x0 = np.clip(x0, lb, ub)
    return least_squares(fun, x0, jac=jac, bounds=(lb, ub), method=method, x_scale=x_scale,
                         ftol=tol, xtol=tol, gtol=tol, max_nfev=max_nfev)


def _slsqp(fun, x0, lb, ub, max_iter=200, jac=None):
    from scipy.optimize import Bounds, minimize

    x0 = np.clip(x0, lb, ub)
    opts = {"ftol": 1e-14, "maxiter": max_iter, "eps": 1e-8}
    return minimize(fun, x0, method="SLSQP", jac=jac, bounds=Bounds(lb, ub), options=opts)


def joint_box(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the bounds (lower, upper) of the joint fit's coordinates [u (n), ln s (n)]."""
    return (np.r_[np.zeros(n), np.full(n, LN_S_BOUNDS[0])],
            np.r_[np.ones(n), np.full(n, LN_S_BOUNDS[1])])


def explore_start(spec: FitSpec, index: int, lengths0: np.ndarray, factors0: np.ndarray,
                  max_nfev: int) -> tuple[StartResult, LMState]:
    """Run a joint deflection or combined start for at most ``max_nfev`` residual evaluations.

    Parameters
    ----------
    spec : FitSpec
        The fit problem (``joint`` parametrisation, objective not ``eigen``).
    index : int
        The start's index, recorded in the result.
    lengths0 : ndarray, shape (n+1,)
        Start link lengths, m.
    factors0 : ndarray, shape (n,)
        Start factors on the finite-segment springs (dimensionless).
    max_nfev : int
        Residual evaluations of this call.

    Returns
    -------
    StartResult
        Where the start stands: lengths (m), factors, loss (%), evaluations, solver message.
    LMState
        The solver's state, for :func:`refine_start`.
    """
    p = spec.problem
    n = p.n_joints
    J = JointResiduals(spec)
    lb, ub = joint_box(n)
    x0 = np.r_[unit_from_lengths(lengths0, p.length_m, p.min_fraction), np.log(factors0)]
    state = lm_advance(lm_start(J.residuals, J.jac, x0, lb, ub), J.residuals, J.jac, lb, ub,
                       max_nfev)
    return _joint_result(J, index, state), state


def refine_start(spec: FitSpec, explored: StartResult, state: LMState) -> StartResult:
    """Continue an explored joint start to convergence or to ``spec.max_nfev`` evaluations.

    Parameters
    ----------
    spec : FitSpec
        The fit problem the start was explored on.
    explored : StartResult
        The explored start (its index and evaluations).
    state : LMState
        The solver's state at the end of the exploration.

    Returns
    -------
    StartResult
        The local optimum; with several poses, polished on the true loss by SLSQP.
    """
    J = JointResiduals(spec)
    lb, ub = joint_box(spec.problem.n_joints)
    state = lm_advance(state, J.residuals, J.jac, lb, ub, spec.max_nfev)
    return _joint_result(J, explored.index, state, polish=True)


def _joint_result(J: JointResiduals, index: int, state: LMState,
                  polish: bool = False) -> StartResult:
    x, msg = state.x, state.message
    n0 = J.nfev
    if polish and J.p.n_poses > 1:
        lb, ub = joint_box(J.p.n_joints)
        r2 = _slsqp(J.loss, x, lb, ub)
        if r2.fun <= J.loss(x):
            x, msg = r2.x, f"{msg}; polished: {r2.message}"
    lengths, s = J.design(x)
    loss = 100.0 * J.loss(x)
    # the solve's residuals and Jacobians (exploration included), the polish and the loss
    nfev = state.nfev + state.njev + J.nfev - n0
    return StartResult(index, lengths, s, loss, nfev, state.status > 0, str(msg))


def solve_start(spec: FitSpec, index: int, lengths0: np.ndarray, factors0: np.ndarray):
    """Run the local solver of the problem's parametrisation from one start.

    Parameters
    ----------
    spec : FitSpec
        The fit problem, objective and evaluation cap.
    index : int
        The start's index, recorded in the result.
    lengths0 : ndarray, shape (n+1,)
        Start link lengths, m.
    factors0 : ndarray
        Start spring factors: the ``joint`` factors on the finite-segment springs, shape (n,),
        or the ``paper`` SCFs, one per pose (both dimensionless multipliers; the eigen
        ``paper`` fit projects the SCFs out and ignores them).

    Returns
    -------
    StartResult
        The local optimum: link lengths (m), factors, loss (%), evaluations and solver message.
    """
    # the parametrisation picks its solver (solve_joint_start or solve_paper_start)
    return spec.problem.parametrisation.solve_start(spec, index, lengths0, factors0)


def solve_joint_start(spec: FitSpec, index: int, lengths0: np.ndarray,
                      factors0: np.ndarray) -> StartResult:
    """Run the ``joint`` local solver from one start (:func:`solve_start`'s arguments).

    Eigen: least squares over [u, ln s] (polished on the true loss by SLSQP over a sweep);
    with a deflection term: :func:`explore_start` then :func:`refine_start` to the cap.
    """
    p = spec.problem
    n = p.n_joints
    if spec.objective.has_deflection_term:
        explored, state = explore_start(spec, index, lengths0, factors0, spec.max_nfev)
        return refine_start(spec, explored, state)
    J = JointResiduals(spec)
    lb, ub = joint_box(n)
    x0 = np.r_[unit_from_lengths(lengths0, p.length_m, p.min_fraction), np.log(factors0)]
    r = _ls(J.eigen_residuals, x0, lb, ub, spec.max_nfev, jac=J.eigen_jac,
            method="dogbox" if p.n_poses == 1 else "trf")
    x, msg, ok = r.x, r.message, bool(r.success)
    if p.n_poses > 1:
        r2 = _slsqp(J.loss, x, lb, ub)
        if r2.fun <= J.loss(x):
            x, msg = r2.x, f"{msg}; polished: {r2.message}"
    lengths, s = J.design(x)
    return StartResult(index, lengths, s, 100.0 * J.loss(x), J.nfev, ok, str(msg))


def solve_paper_start(spec: FitSpec, index: int, lengths0: np.ndarray,
                      factors0: np.ndarray) -> StartResult:
    """Run the ``paper`` local solver from one start (:func:`solve_start`'s arguments).

    Eigen: least squares on the variable-projected residuals over u (the SCFs in closed
    form); with a deflection term: SLSQP on the scalar loss over [u, ln k].
    """
    p = spec.problem
    n = p.n_joints
    u0 = unit_from_lengths(lengths0, p.length_m, p.min_fraction)
    if not spec.objective.has_deflection_term:
        P = PaperEigenResiduals(spec)
        # a loose stage-1 tolerance: the best few starts are polished on the true loss
        r = _ls(P.residuals, u0, np.zeros(n), np.ones(n), spec.max_nfev, jac=P.jac,
                method="trf", tol=1e-8)
        return StartResult(index, P.lengths(r.x), P.factors(r.x), 100.0 * P.loss(r.x),
                           P.nfev, bool(r.success), str(r.message))
    S = PaperScalarLoss(spec)
    lb = np.r_[np.zeros(n), np.full(p.n_poses, LN_S_BOUNDS[0] + math.log(1e-2))]
    ub = np.r_[np.ones(n), np.full(p.n_poses, LN_S_BOUNDS[1] + math.log(1e3))]
    r = _slsqp(S.loss, np.r_[u0, np.log(factors0)], lb, ub, jac=S.jac)
    lengths, k = S.design(r.x)
    return StartResult(index, lengths, k, 100.0 * float(r.fun), S.nfev,
                       bool(r.success), str(r.message))


def polish_paper_eigen(spec: FitSpec, start: StartResult) -> StartResult:
    """Polish a variable-projected ``paper`` eigen optimum on the paper's loss with SLSQP.

    Parameters
    ----------
    spec : FitSpec
        The fit problem of a ``paper`` eigen fit.
    start : StartResult
        The optimum of the projected least-squares stage.

    Returns
    -------
    StartResult
        The polished optimum when its loss (%) is lower, otherwise ``start``; its evaluation
        count includes the polish's.
    """
    P = PaperEigenResiduals(spec)
    p = spec.problem
    u0 = unit_from_lengths(start.lengths_m, p.length_m, p.min_fraction)
    r = _slsqp(P.loss, u0, np.zeros(p.n_joints), np.ones(p.n_joints), jac=P.loss_grad)
    loss = 100.0 * P.loss(r.x)
    if not loss < start.loss_pct:
        return replace(start, nfev=start.nfev + P.nfev)
    return StartResult(start.index, P.lengths(r.x), P.factors(r.x), loss, start.nfev + P.nfev,
                       start.success, f"{start.message}; polished: {r.message}")

