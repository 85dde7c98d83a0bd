"""Levenberg-Marquardt with geodesic acceleration, in a box: the combined joint fits' solver.

The combined (and deflection) joint fits have fewer independent residuals than unknowns and
their optimum sits on a fold: the frequencies hold only along a narrow curved valley in
(lengths, springs), and a Gauss-Newton trust region (scipy's ``trf``) follows it in hundreds of
short steps. The geodesic acceleration of Transtrum & Sethna (2012, arXiv:1201.5885) adds to
each Levenberg-Marquardt step v the second-order correction a = -(J^T J + mu D^2)^-1 J^T r_vv,
r_vv the residuals' second derivative along v (one extra residual evaluation, by a difference),
so the step v + a/2 bends with the valley; a step whose correction is large beside it
(|D a| > ``accel_max`` |D v|) is refused and mu raised. D is More's scaling (the largest
column norms of J met so far), mu is updated as in Nielsen's rule.

Bounds are kept by an active set: a variable at a bound whose gradient points out of the box
is held there for the step; the others move and the step is then clipped into the box.

The solver is resumable (:class:`LMState` carries where it stands), so a multistart can run
every start a little and continue only the best (``fitting/explore.py``). It counts residual
evaluations against its cap, as scipy's ``least_squares`` does (Jacobians, analytic, apart).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["LMState", "lm_start", "lm_advance"]

_H_FVV = 0.1  # the difference step of r_vv, as a fraction of the step v
_MU0 = 1e-3  # the first damping, relative to D^2


@dataclass(frozen=True)
class LMState:
    """Where one geodesic Levenberg-Marquardt solve stands.

    Attributes
    ----------
    x : ndarray
        The current point (the best so far).
    r : ndarray
        The residuals at ``x``.
    J : ndarray
        Their Jacobian at ``x``.
    scale : ndarray
        More's scaling D: the largest column norms of J met so far.
    mu, nu : float
        The damping and its growth factor after a refused step.
    nfev, njev : int
        Residual and Jacobian evaluations so far.
    status : int
        0 running; 1 converged (relative reduction or step below the tolerance); 2 gradient
        below the tolerance; 3 the damping overflowed (no step reduces the loss); -1 the
        residuals cannot be evaluated at the start.
    """

    x: np.ndarray
    r: np.ndarray
    J: np.ndarray
    scale: np.ndarray
    mu: float
    nu: float
    nfev: int
    njev: int
    status: int = 0

    @property
    def message(self) -> str:
        """The status in words."""
        return {0: "evaluation cap reached", 1: "converged (reduction or step below tol)",
                2: "converged (gradient below tol)", 3: "no step reduces the loss",
                -1: "the start cannot be evaluated"}[self.status]


def lm_start(fun: Callable, jac: Callable, x0: np.ndarray, lb: np.ndarray,
             ub: np.ndarray) -> LMState:
    """Return the state at ``x0`` (clipped into [lb, ub]): its residuals and Jacobian.

    Parameters
    ----------
    fun, jac : callable
        The residuals r(x) and their Jacobian dr/dx (arrays).
    x0, lb, ub : ndarray
        Start point and bounds, in the solver's coordinates.

    Returns
    -------
    LMState
        The state before the first step.
    """
    x = np.clip(np.asarray(x0, dtype=float), lb, ub)
    r = np.asarray(fun(x), dtype=float)
    J = np.asarray(jac(x), dtype=float)
    scale = np.maximum(np.linalg.norm(J, axis=0), 1e-12)
    return LMState(x, r, J, scale, _MU0, 2.0, 1, 1, 0 if np.any(J) else -1)


def _damped_solver(A: np.ndarray, mu: float, scale: np.ndarray, free: np.ndarray):
    """Return b -> (A + mu D^2)^-1 b on the free variables (zero on the held ones)."""
    c = np.linalg.cholesky((A + np.diag(mu * scale * scale))[np.ix_(free, free)])

    def solve(b: np.ndarray) -> np.ndarray:
        out = np.zeros_like(b)
        out[free] = np.linalg.solve(c.T, np.linalg.solve(c, b[free]))
        return out

    return solve


def lm_advance(state: LMState, fun: Callable, jac: Callable, lb: np.ndarray, ub: np.ndarray,
               max_nfev: int, tol: float = 1e-10, accel_max: float = 0.75) -> LMState:
    """Continue a solve until it converges or has made ``max_nfev`` residual evaluations.

    Parameters
    ----------
    state : LMState
        Where the solve stands (from :func:`lm_start` or an earlier call).
    fun, jac : callable
        The residuals and their Jacobian, as given to :func:`lm_start`.
    lb, ub : ndarray
        Bounds of x.
    max_nfev : int
        Cap on the residual evaluations of the whole solve (``state.nfev`` included).
    tol : float
        Relative tolerance on the loss reduction, the step and the scaled gradient.
    accel_max : float
        The largest accepted ratio |D a| / |D v| of the acceleration to the step.

    Returns
    -------
    LMState
        The new state (``status`` says why it stopped).
    """
    if state.status != 0:
        return state
    x, r, J, scale, mu, nu = state.x, state.r, state.J, state.scale, state.mu, state.nu
    nfev, njev = state.nfev, state.njev
    F = 0.5 * float(r @ r)
    span = ub - lb
    status = 0
    while nfev + 2 <= max_nfev:  # an iteration evaluates the residuals twice
        scale = np.maximum(scale, np.linalg.norm(J, axis=0))
        g = J.T @ r
        free = ~(((x <= lb + 1e-12 * span) & (g > 0)) | ((x >= ub - 1e-12 * span) & (g < 0)))
        # the largest cosine between a free scaled column of J and r (MINPACK's gtol test; a
        # variable held on its bound by the gradient is at its optimum)
        if np.max(np.abs(g * free) / scale) <= tol * np.linalg.norm(r):
            status = 2
            break
        try:
            solve = _damped_solver(J.T @ J, mu, scale, free)
        except np.linalg.LinAlgError:
            mu, nu = mu * nu, nu * 2.0
            continue
        v = -solve(g)
        # geodesic acceleration: r_vv by a second difference along v
        rh = np.asarray(fun(x + _H_FVV * v), dtype=float)
        nfev += 1
        rvv = (2.0 / _H_FVV) * ((rh - r) / _H_FVV - J @ v)
        a = -solve(J.T @ rvv)
        if not np.linalg.norm(scale * a) <= accel_max * np.linalg.norm(scale * v):
            mu, nu = mu * nu, nu * 2.0
            if mu > 1e30:
                status = 3
                break
            continue
        xn = np.clip(x + v + 0.5 * a, lb, ub)
        rn = np.asarray(fun(xn), dtype=float)
        nfev += 1
        Fn = 0.5 * float(rn @ rn)
        Jv = J @ v
        predicted = -(g @ v + 0.5 * Jv @ Jv)
        rho = (F - Fn) / predicted if predicted > 0 else -1.0
        if rho > 0:
            step = np.linalg.norm(scale * (xn - x))
            reduction = F - Fn
            x, r, F = xn, rn, Fn
            J = np.asarray(jac(x), dtype=float)
            njev += 1
            mu, nu = mu * max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), 2.0
            if reduction <= tol * F or step <= tol * (np.linalg.norm(scale * x) + tol):
                status = 1
                break
        else:
            mu, nu = mu * nu, nu * 2.0
            if mu > 1e30:
                status = 3
                break
    return replace(state, x=x, r=r, J=J, scale=scale, mu=mu, nu=nu, nfev=nfev, njev=njev,
                   status=status)
