"""The ``unique="nearest"`` fit: a ``joint`` model matching n frequencies exactly, by a rule.

The rule makes it one model per design, smooth in the design.

n frequencies do not determine the 2n lengths and springs of an nR ``joint`` model, and with
the lengths fixed the n springs that match them are not unique either (several exact
solutions), so a multistart picks one at random and its parameters jump along a design sweep.
The rule, in the fit coordinates x = [u (stick-breaking lengths), ln s (joint factors)]:

1. Reference: x_ref, the links [h/2, h, ..., h, h/2] (h = L/n) with the finite-segment springs
   as they are (s = 1).
2. Branch: the minimum-norm homotopy flow dx/dtau = J(x)^+ (ln w_truth - ln w_ref), tau 0 -> 1,
   which moves the model's log frequencies on a straight line from the reference model's to
   the truth's. J is n x 2n: it loses rank only on a set of codimension n + 1, which a
   one-parameter path generically misses, so the flow is defined, unique and smooth in the
   design (a square n x n Jacobian, springs only, turns singular on a fold on some panels).
3. Model: from the flow's end, the exact match nearest x_ref: ``min |x - x_ref|^2`` subject to
   ln w(x) = ln w_truth, whose KKT conditions are the optimality conditions that
   ``fitting.derivative`` differentiates.

The rule fails (SolveError naming the step) when J loses rank on the path, a link reaches its
length bound, or the nearest-point iteration does not converge.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, SolveError
from ..options.choices import Objective
from ..options.objects import UNIQUE_RULES
from .evaluate import chain_frequencies, chain_mass_matrices
from .problem import FitProblem, lengths_from_unit, unit_from_lengths
from .spec import StartResult

__all__ = ["UNIQUE_RULES", "rule_lengths", "reference_x", "log_frequencies",
           "log_frequency_jacobian", "check_unique_problem", "solve_unique"]
FLOW_STEPS = 20  # RK4 steps of the homotopy flow (each followed by a min-norm correction)
# central-difference step in x: the nearest-point iteration stalls at the forward stencil's
# O(h) error, the central one's O(h^2) is below its tolerance
JAC_STEP = 1e-6
NEAREST_TOL = 1e-9  # max |dx| of the nearest-point iteration at convergence
NEAREST_ITERS = 300


def rule_lengths(length_m: float, joints: int) -> np.ndarray:
    """Return the reference links [h/2, h, ..., h, h/2], h = L/n.

    Parameters
    ----------
    length_m : float
        The beam length L, m.
    joints : int
        n, the number of revolute joints.

    Returns
    -------
    ndarray, shape (n+1,)
        The link lengths, m.
    """
    h = length_m / joints
    return np.r_[h / 2, np.full(joints - 1, h), h / 2]


def reference_x(problem: FitProblem) -> np.ndarray:
    """Return x_ref = [u of :func:`rule_lengths`, ln s = 0]."""
    u = unit_from_lengths(rule_lengths(problem.length_m, problem.n_joints), problem.length_m,
                          problem.min_fraction)
    return np.r_[u, np.zeros(problem.n_joints)]


def log_frequencies(problem: FitProblem, X: np.ndarray) -> np.ndarray:
    """Return ln omega (rad/s) at the straight pose of the designs in the rows of X, (B, n)."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    n = problem.n_joints
    lengths = np.array([lengths_from_unit(x[:n], problem.length_m, problem.min_fraction)
                        for x in X])
    M, K0 = chain_mass_matrices(problem, lengths)
    return np.log(chain_frequencies(M, np.exp(X[:, n:]) * K0)[:, 0, : problem.n_freq])


def log_frequency_jacobian(problem: FitProblem, x: np.ndarray, h: float = JAC_STEP):
    """Return ln omega at x, (n,), and its Jacobian in x, (n, 2n), by central differences.

    The whole stencil is evaluated in one batch; analytic model derivatives can replace it.
    """
    x = np.asarray(x, dtype=float)
    E = h * np.eye(x.size)
    W = log_frequencies(problem, np.vstack([x, x + E, x - E]))
    return W[0], ((W[1 : x.size + 1] - W[x.size + 1 :]) / (2.0 * h)).T


def check_unique_problem(problem: FitProblem, objective: Objective) -> None:
    """Check that the problem is a ``joint`` eigen fit of n frequencies at the straight pose.

    The rule needs one; anything else is a BeamInputError naming the field.
    """
    if not problem.parametrisation.pose_independent:
        raise BeamInputError(f"unique = 'nearest': stiffness = "
                             f"{problem.parametrisation.name!r}: needs 'joint'")
    if objective.has_deflection_term:  # the rule matches frequencies only
        raise BeamInputError(f"unique = 'nearest': objective = {objective.value!r}: needs "
                             "'eigen'")
    if problem.n_poses != 1:
        raise BeamInputError("unique = 'nearest': joint_sweep = True: needs the straight pose")
    if problem.n_freq != problem.n_joints:
        raise BeamInputError(f"unique = 'nearest': frequencies = {problem.n_freq}: needs "
                             f"{problem.n_joints} (one per joint)")


def _min_norm(J: np.ndarray, r: np.ndarray, what: str, rcond: float = 1e-10) -> np.ndarray:
    s = np.linalg.svd(J, compute_uv=False)
    if s[-1] <= rcond * s[0]:
        raise SolveError(f"unique = 'nearest': the frequency Jacobian lost rank {what} "
                         f"(singular values {s[-1]:.3g} / {s[0]:.3g})")
    return np.linalg.lstsq(J, r, rcond=None)[0]


def _check_box(problem: FitProblem, x: np.ndarray, what: str) -> None:
    u = x[: problem.n_joints]
    if u.min() < 0.0 or u.max() > 1.0:
        raise SolveError(f"unique = 'nearest': a link reached its length bound (min_fraction "
                         f"{problem.min_fraction:g}) {what}")


def homotopy_flow(problem: FitProblem, x_ref: np.ndarray, steps: int = FLOW_STEPS):
    """Return the end of the minimum-norm flow (rule step 2) and the evaluations it took."""
    n = problem.n_joints
    lw_ref = log_frequencies(problem, x_ref)[0]
    D = np.log(problem.target.omega_truth_rad_s) - lw_ref
    nfev = 1

    def rate(x, tau):
        nonlocal nfev
        nfev += 4 * n + 1
        return _min_norm(log_frequency_jacobian(problem, x)[1], D, f"at tau = {tau:.3f}")

    x = np.array(x_ref, dtype=float)
    dt = 1.0 / steps
    for k in range(steps):
        tau = k * dt
        k1 = rate(x, tau)
        k2 = rate(x + 0.5 * dt * k1, tau)
        k3 = rate(x + 0.5 * dt * k2, tau)
        k4 = rate(x + dt * k3, tau)
        x = x + dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0
        # back onto the path at tau + dt: min-norm Gauss-Newton corrections
        goal = lw_ref + (k + 1) * dt * D
        for _ in range(4):
            w, J = log_frequency_jacobian(problem, x)
            nfev += 4 * n + 1
            r = w - goal
            if np.max(np.abs(r)) < 1e-12:
                break
            x = x - _min_norm(J, r, f"at tau = {tau + dt:.3f}")
        _check_box(problem, x, f"at tau = {tau + dt:.3f}")
    return x, nfev


def nearest_exact(problem: FitProblem, x_ref: np.ndarray, x0: np.ndarray):
    """Return the exact match nearest x_ref from x0 (rule step 3), its multipliers, evaluations.

    The iteration is x <- x_ref + J^T (J J^T)^-1 (J (x - x_ref) - F(x)), whose fixed points are
    the KKT points of ``min |x - x_ref|^2`` s.t. F = 0.
    """
    lwt = np.log(problem.target.omega_truth_rad_s)
    x, nfev = np.array(x0, dtype=float), 0
    for _ in range(NEAREST_ITERS):
        w, J = log_frequency_jacobian(problem, x)
        nfev += 4 * problem.n_joints + 1
        # v = (J J^T)^-1 (J (x - x_ref) - F), by the rank-checked min-norm solve
        v = _min_norm(J @ J.T, J @ (x - x_ref) - (w - lwt), "at the nearest exact match")
        x_new = x_ref + J.T @ v
        if np.max(np.abs(x_new - x)) < NEAREST_TOL:
            _check_box(problem, x_new, "at the nearest exact match")
            return x_new, -v, nfev  # x - x_ref + J^T lambda = 0
        x = x_new
    raise SolveError(f"unique = 'nearest': the nearest-point iteration did not converge in "
                     f"{NEAREST_ITERS} iterations")


def solve_unique(problem: FitProblem) -> tuple[StartResult, np.ndarray]:
    """Return the rule's model as a :class:`StartResult` (index 0) and its KKT multipliers.

    Parameters
    ----------
    problem : FitProblem
        A ``joint`` eigen fit problem of n frequencies at the straight pose.

    Returns
    -------
    result : StartResult
        The model: link lengths (m), joint factors (dimensionless), loss (%, the rms of the
        per-mode relative errors), evaluations.
    multipliers : ndarray, shape (n,)
        The KKT multipliers of the nearest-point problem (dimensionless).

    Raises
    ------
    SolveError
        When the frequency Jacobian loses rank on the path, a link reaches its length bound,
        or the nearest-point iteration does not converge.
    """
    x_ref = reference_x(problem)
    xf, n1 = homotopy_flow(problem, x_ref)
    x, lam, n2 = nearest_exact(problem, x_ref, xf)
    n = problem.n_joints
    lengths = lengths_from_unit(x[:n], problem.length_m, problem.min_fraction)
    w = np.exp(log_frequencies(problem, x)[0])
    err = (w - problem.target.omega_truth_rad_s) / problem.target.omega_truth_rad_s
    loss = 100.0 * float(np.sqrt(np.mean(err**2)))
    res = StartResult(0, lengths, np.exp(x[n:]), loss, n1 + n2 + 1, True,
                      "unique = 'nearest': minimum-norm homotopy from the reference, then the "
                      "exact match nearest it")
    return res, lam
