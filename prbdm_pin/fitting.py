"""Single-objective multistart fits and the NSGA-II Pareto fit.

Local solvers (chosen for accuracy per model evaluation; see ``scripts/bench_fit.py``):

- ``joint`` parametrisation: ``scipy.optimize.least_squares`` (trust-region reflective) on the
  residual vector (frequency residuals over the poses, scaled by ``1/sqrt(m)``, and/or the tip
  position residual), over x = [u, ln s] with u in the box [0, 1]^n mapped onto the bounded
  length simplex by stick-breaking (:func:`problem.lengths_from_unit`). With the straight pose
  (the default) the sum of squares is exactly the squared loss, and n frequencies are matched to
  round-off. With a sweep (m > 1) the least-squares optimum is polished on the true loss
  (mean of per-pose norms) by SLSQP.
- ``paper`` parametrisation, eigen objective: variable projection. For fixed lengths every
  pose's SCF k_i enters only as ``omega = sqrt(k_i) w_i`` (the mass matrix does not depend on
  the springs), so its best value is a 1-D linear least-squares solution in closed form
  (:func:`objectives.best_scale`) and the loss becomes a function of the n free length
  coordinates only. ``least_squares`` minimises the stacked projected residuals (sum of squared
  per-pose errors); the best few local optima are then polished by SLSQP (box-bounded u) on the
  paper's loss (mean of per-pose errors), which differs only in how poses are weighted.
- ``paper`` with a deflection term: SLSQP over [u, ln k] on the scalar loss, started from the
  projected SCFs of the start lengths times a random factor. Pose i's errors depend on its own
  k_i only, so one central difference moving every ln k_i gives all m SCF derivatives; with
  forward differences in u a gradient costs n + 3 designs, evaluated as one batch with every
  pose's static solve in one vectorised Newton (``problem.batch_losses``).

Eigen norm (``eigen_norm``): ``"relative"`` (default), the rms of the per-mode relative errors,
or ``"paper"``, Eq. 16's l2 norm, which the highest mode dominates; both are a weighted l2
norm (``objectives.eigen_weights``), so every residual, the variable projection's closed-form
SCF and the scalar and batch losses take the weights of the chosen norm.

What is exported: ``paper`` fits export the springs fitted at the sweep's first pose (every
joint at xi, the pose nearest straight), recorded with their pose in the FitResult; the whole
per-pose table stays in it (``FitResult.stiffness_schedule`` for ``simulate``). Pose 0 is a
spring set the fit chose (with the deflection term, when there is one), unlike springs re-scaled
at q = 0 (``scripts/export_pose_study.py`` compares the two). Every result carries the exported
model's own frequencies at q = 0 and its per-mode errors, and warns when one is off by more than
``EXPORT_WARN_PCT``.

Inner loop: trial designs are evaluated without building a ``pinocchio.Model``, through
:func:`problem.chain_mass_matrices` (exact link sections and the closed-form mass matrix of the
planar chain, checked against Pinocchio's CRBA in the tests) and the vectorised static solver
``dynamics.static_deflection_planar_batch``; each finite-difference stencil, and each NSGA-II
generation, is evaluated as one stacked batch (scipy's ``workers`` map, the analytic-in-ln s
Jacobian of the ``joint`` fit, ``problem.pareto_objectives_batch``). The chosen design is
evaluated again through the Pinocchio model (:func:`result_from_design`), so every reported
number comes from the product path.

Start points are uniform on the bounded simplex (``layout.sample_lengths``, Eq. 23) plus random
factors, all drawn up front from ``numpy.random.default_rng(seed)``; starts are solved in order
(in processes when ``workers > 1``) and the best is chosen by (loss, start index), so the same
seed gives the same result whatever the number of workers. ``loss_tol`` stops at the first start
(in start order) that reaches it.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, replace

import numpy as np

from .choices import DEFAULT_EIGEN_NORM, OBJECTIVES
from .eigen import modes_from_mass
from .errors import BeamInputError, SolveError
from .geometry import Beam
from .objectives import (
    best_scale,
    check_eigen_norm,
    eigen_weights,
    knee_index,
    mode_errors_pct,
    scf_deviation_pct,
    scf_mean,
    worst_mode_error_pct,
)
from .planar import planar_tip, planar_tips
from .problem import (
    FitProblem,
    FitTarget,
    LengthRepair,
    ParetoProblem,
    batch_losses,
    build,
    chain_frequencies,
    chain_mass_matrices,
    evaluate,
    fast_unit_frequencies,
    lengths_from_unit,
    make_problem,
    pareto_objectives,
    pareto_objectives_batch,
    unit_frequencies,
    unit_from_lengths,
)
from .results import FitResult, ParetoResult
from .statics import static_deflection_planar, static_deflection_planar_batch

__all__ = ["fit", "fit_pareto", "StartResult", "solve_start", "result_from_design"]

_BAD = 1e3  # loss (fraction) reported for designs whose model cannot be solved
# eigen loss (%) above which a joint fit of n frequencies at the straight pose has not matched
# them (reached fits end at 1e-11 % or below)
EXACT_MATCH_PCT = 1e-4
_LN_S_BOUNDS = (math.log(1e-3), math.log(1e3))
# worst per-mode error (%) of the exported model at the straight pose above which a fit warns
EXPORT_WARN_PCT = 1.0
# a link within this fraction of L of its lower bound is reported as sitting on it
BOUND_TOL = 1e-6


@dataclass(frozen=True)
class StartResult:
    """Local optimum of one start: lengths (m), factors, loss (%), evaluations, solver message."""

    index: int
    lengths_m: np.ndarray
    factors: np.ndarray
    loss_pct: float
    nfev: int
    success: bool
    message: str


@dataclass(frozen=True, eq=False)
class _Spec:
    problem: FitProblem
    objective: str
    deflection_norm: str
    max_nfev: int


# --- residuals and losses ----------------------------------------------------------------------
def _tip_norms(problem: FitProblem, norm: str) -> np.ndarray:
    """The normalisation of each load case's tip error (its truth position or displacement), m."""
    return np.array([np.linalg.norm(c.tip_position_m if norm == "position"
                                    else c.tip_displacement_m)
                     for c in problem.target.load_cases])


class _Joint:
    """Residuals of the ``joint`` parametrisation over x = [u (n), ln s (n)]."""

    def __init__(self, spec: _Spec):
        self.spec = spec
        p = spec.problem
        self.p = p
        self.f = p.target.omega_truth_rad_s ** (2 if p.squared else 1)
        # the eigen norm's weights (Eq. 16: 1/||f||; relative: 1/(f_k sqrt(N)))
        self.d = eigen_weights(p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
        self.cases = p.target.load_cases if spec.objective != "eigen" else ()
        self.norms = _tip_norms(p, spec.deflection_norm) if self.cases else np.zeros(0)
        self.q0 = [None] * len(self.cases)  # warm starts, one per load case
        self.nfev = 0
        self._cache = None

    def split(self, x):
        n = self.p.n_joints
        return lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction), np.exp(x[n:])

    def residuals(self, x):
        self.nfev += 1
        p, spec = self.p, self.spec
        lengths, s = self.split(x)
        parts = []
        try:
            M, K0 = chain_mass_matrices(p, lengths)
            K = s * K0
            if spec.objective != "deflection":
                w = chain_frequencies(M, K)[:, : p.n_freq] ** (2 if p.squared else 1)
                parts.append(((w - self.f) * self.d).ravel() / math.sqrt(p.n_poses))
            # the squared residuals of k load cases sum to the mean squared tip error
            wc = 1.0 / math.sqrt(max(len(self.cases), 1))
            for c, case in enumerate(self.cases):
                q = static_deflection_planar(lengths, K, case.tip_force_N, q0=self.q0[c])
                tip = planar_tip(lengths, q)[0]
                self.q0[c] = q
                parts.append((tip - case.tip_position_m) * (wc / self.norms[c]))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.full(self.size(), _BAD)
        return np.concatenate(parts)

    def size(self):
        p, o = self.p, self.spec.objective
        return (p.n_poses * p.n_freq if o != "deflection" else 0) + 3 * len(self.cases)

    def _eigen_parts(self, x):
        """Scaled eigen residuals (m*N,) and their analytic derivative in ln s, (m*N, n)."""
        p = self.p
        lengths, s = self.split(x)
        M, K0 = chain_mass_matrices(p, lengths)
        K = s * K0
        # the residuals through the same eigensolver as the finite-difference stencil below
        w = chain_frequencies(M, K)[:, : p.n_freq]
        _, PHI = modes_from_mass(M, K)
        dlns = []
        for wi, Phi in zip(w, PHI, strict=True):
            Phi = Phi[:, : p.n_freq]
            # d(omega_k^2)/d ln s_j = phi_jk^2 K_j for mass-normalised phi (M is independent of K)
            dw2 = (Phi**2 * K[:, None]).T
            dlns.append(dw2 if p.squared else dw2 / (2.0 * wi[:, None]))
        c = np.tile(self.d, p.n_poses) / math.sqrt(p.n_poses)
        res = (w ** (2 if p.squared else 1)).ravel()
        return (res - np.tile(self.f, p.n_poses)) * c, np.vstack(dlns) * c[:, None]

    def _stencil_residuals(self, X, chain=None):
        """Scaled eigen residuals of the designs in the rows of X, (B, m*N), in one batch
        (``chain``: their lengths, mass matrices and unit springs, when already computed)."""
        p, n = self.p, self.p.n_joints
        if chain is None:
            lengths = np.array([self.split(x)[0] for x in X])
            chain = (lengths, *chain_mass_matrices(p, lengths))
        _, M, K0 = chain
        w = chain_frequencies(M, np.exp(X[:, n:]) * K0)[..., : p.n_freq]
        r = ((w ** (2 if p.squared else 1)) - self.f) * self.d
        return r.reshape(X.shape[0], -1) / math.sqrt(p.n_poses)

    def _batch_residuals(self, X):
        """:meth:`residuals` of the designs in the rows of X, (B, size), in one batch: one
        stacked eigensolve and, per load case, every design's static solve in one vectorised
        Newton. A design that cannot be solved gets NaN residuals."""
        p, n = self.p, self.p.n_joints
        lengths = np.array([self.split(x)[0] for x in X])
        M, K0 = chain_mass_matrices(p, lengths)
        K = np.exp(X[:, n:]) * K0
        parts = []
        if self.spec.objective != "deflection":
            parts.append(self._stencil_residuals(X, (lengths, M, K0)))
        wc = 1.0 / math.sqrt(max(len(self.cases), 1))
        for c, case in enumerate(self.cases):
            q, ok = static_deflection_planar_batch(lengths, K, case.tip_force_N)
            tips = planar_tips(lengths, np.where(ok[:, None], q, 0.0))
            r = (tips - case.tip_position_m) * (wc / self.norms[c])
            r[~ok] = np.nan
            parts.append(r)
        return np.concatenate(parts, axis=1)

    def jac(self, x):
        """Forward-difference Jacobian of :meth:`residuals`, the 2n shifted designs in one
        batch (a design that cannot be solved contributes a zero column)."""
        x = np.asarray(x, dtype=float)
        n2 = x.size
        h = np.full(n2, 1e-7)
        h[: self.p.n_joints] = np.where(x[: self.p.n_joints] + 1e-7 <= 1.0, 1e-7, -1e-7)
        X = np.vstack([x, x + np.diag(h)])
        self.nfev += n2 + 1
        try:
            R = self._batch_residuals(X)
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.zeros((self.size(), n2))
        D = (R[1:] - R[0]) / h[:, None]
        D[~np.all(np.isfinite(D), axis=1)] = 0.0
        return D.T

    def eigen_residuals(self, x):
        """Residuals of the eigen objective (caches the ln s derivative for :meth:`eigen_jac`)."""
        self.nfev += 1
        try:
            r, d = self._eigen_parts(x)
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            r, d = np.full(self.size(), _BAD), np.zeros((self.size(), self.p.n_joints))
        self._cache = (np.array(x, copy=True), r, d)
        return r

    def eigen_jac(self, x):
        """Jacobian: forward differences in u (all n designs in one batch), analytic in ln s."""
        n = self.p.n_joints
        if self._cache is None or not np.array_equal(self._cache[0], x):
            self.eigen_residuals(x)
        _, r0, dlns = self._cache
        Jm = np.empty((r0.size, 2 * n))
        Jm[:, n:] = dlns
        h = np.where(x[:n] + 1e-7 <= 1.0, 1e-7, -1e-7)
        X = np.tile(x, (n, 1))
        X[np.arange(n), np.arange(n)] += h
        self.nfev += n
        try:
            RH = self._stencil_residuals(X)
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            RH = np.empty((n, r0.size))
            for j in range(n):  # find the failing designs one by one
                try:
                    RH[j] = self._stencil_residuals(X[j : j + 1])[0]
                except (SolveError, BeamInputError, np.linalg.LinAlgError):
                    RH[j] = r0
        Jm[:, :n] = ((RH - r0) / h[:, None]).T
        return Jm

    def loss(self, x):
        """The true loss (fraction): mean of per-pose eigen norms, hypot with the tip term."""
        r = self.residuals(x)
        p, o = self.p, self.spec.objective
        e = d = 0.0
        if o != "deflection":
            ne = p.n_poses * p.n_freq
            e = float(np.mean(np.linalg.norm(
                r[:ne].reshape(p.n_poses, p.n_freq) * math.sqrt(p.n_poses), axis=1)))
            r = r[ne:]
        if o != "eigen":
            # residuals scaled by 1/sqrt(k): the loss averages the k cases' errors (Eq. 18)
            k = len(self.cases)
            d = float(np.mean(np.linalg.norm(r.reshape(k, 3), axis=1))) * math.sqrt(k)
        return math.hypot(e, d)


class _PaperEigen:
    """Variable-projected eigen residuals of the ``paper`` parametrisation over u (n)."""

    def __init__(self, spec: _Spec):
        self.p = spec.problem
        self.f = self.p.target.omega_truth_rad_s ** (2 if self.p.squared else 1)
        self.d = eigen_weights(self.p.target.omega_truth_rad_s, self.p.squared,
                               self.p.eigen_norm)
        self.nfev = 0

    def lengths(self, u):
        return lengths_from_unit(u, self.p.length_m, self.p.min_fraction)

    def pose_residuals(self, u):
        self.nfev += 1
        return self._batch(np.asarray(u, dtype=float)[None])[0]

    def _batch(self, U):
        """Projected per-pose residuals (B, m, N) of the designs in the rows of U."""
        p = self.p
        try:
            _, W = fast_unit_frequencies(p, np.array([self.lengths(u) for u in U]))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            if U.shape[0] == 1:
                return np.full((1, p.n_poses, p.n_freq), _BAD)
            return np.concatenate([self._batch(U[i : i + 1]) for i in range(U.shape[0])])
        w = W ** (2 if p.squared else 1)
        # each pose's best SCF in closed form (objectives.best_scale, weighted by the norm)
        wd = w * self.d**2
        c = (wd @ self.f) / np.einsum("bij,bij->bi", wd, w)
        return (w * c[..., None] - self.f) * self.d

    def map(self, fun, xs):
        """A ``workers`` map for scipy's finite differences: the stencil in one batch
        (``fun`` is :meth:`residuals` wrapped by scipy, whose rows these are)."""
        U = np.array(list(xs), dtype=float)
        self.nfev += U.shape[0]
        return list(self._batch(U).reshape(U.shape[0], -1) / math.sqrt(self.p.n_poses))

    def residuals(self, u):
        return self.pose_residuals(u).ravel() / math.sqrt(self.p.n_poses)

    def loss(self, u):
        return float(np.mean(np.linalg.norm(self.pose_residuals(u), axis=1)))

    def loss_map(self, fun, xs):
        """A ``workers`` map for scipy's finite differences of :meth:`loss`, in one batch."""
        U = np.array(list(xs), dtype=float)
        self.nfev += U.shape[0]
        return list(np.linalg.norm(self._batch(U), axis=2).mean(axis=1))

    def factors(self, u):
        _, W = fast_unit_frequencies(self.p, self.lengths(u))
        return best_scale(W, self.p.target.omega_truth_rad_s, self.p.squared,
                          self.p.eigen_norm)


class _PaperScalar:
    """Scalar loss of the ``paper`` parametrisation with a deflection term, x = [u, ln k].

    Evaluated through ``problem.batch_losses`` (closed-form kinematics, every pose's static
    solve in one vectorised Newton). The gradient uses the problem's structure: pose i's eigen
    and tip errors depend on its own SCF k_i only, so one central difference that moves every
    ln k_i at once gives all m partial derivatives in ln k; the n length coordinates take
    forward differences. The whole stencil (n + 3 designs) is one batch.
    """

    _H_U, _H_K = 1e-7, 1e-6

    def __init__(self, spec: _Spec):
        self.spec = spec
        self.p = spec.problem
        self.nfev = 0

    def _parts(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per-pose eigen and tip errors (fractions), each (B, m), of the rows of X."""
        p, n = self.p, self.p.n_joints
        lengths = np.array([lengths_from_unit(x[:n], p.length_m, p.min_fraction) for x in X])
        r = batch_losses(p, lengths, np.exp(X[:, n:]))
        d = r.position_errors if self.spec.deflection_norm == "position" \
            else r.displacement_errors
        return r.eigen_errors, d

    def _loss(self, e: np.ndarray, d: np.ndarray) -> np.ndarray:
        loss = d.mean(axis=-1) if self.spec.objective == "deflection" \
            else np.hypot(e.mean(axis=-1), d.mean(axis=-1))
        return np.where(np.isfinite(loss), loss, _BAD)

    def loss(self, x):
        self.nfev += 1
        return float(self._loss(*self._parts(np.asarray(x, dtype=float)[None]))[0])

    def jac(self, x):
        x = np.asarray(x, dtype=float)
        n, m = self.p.n_joints, self.p.n_poses
        hu = np.where(x[:n] + self._H_U <= 1.0, self._H_U, -self._H_U)
        X = np.tile(x, (n + 3, 1))
        X[np.arange(1, n + 1), np.arange(n)] += hu
        X[n + 1, n:] += self._H_K
        X[n + 2, n:] -= self._H_K
        self.nfev += n + 3
        e, d = self._parts(X)
        f = self._loss(e, d)
        g = np.empty(n + m)
        g[:n] = (f[1:n + 1] - f[0]) / hu
        de = (e[n + 1] - e[n + 2]) / (2 * self._H_K)
        dd = (d[n + 1] - d[n + 2]) / (2 * self._H_K)
        E, D = e[0].mean(), d[0].mean()
        if not (np.all(np.isfinite(de)) and np.all(np.isfinite(dd)) and f[0] < _BAD):
            g[n:] = 0.0  # an unsolvable neighbour: no information on the SCFs here
        elif self.spec.objective == "deflection":
            g[n:] = dd / m
        else:
            g[n:] = (E * de + D * dd) / (m * max(f[0], 1e-300))
        return g


# --- one start ----------------------------------------------------------------------------------
def _ls(fun, x0, lb, ub, max_nfev, jac="2-point", tol=1e-10, method="dogbox", x_scale=1.0,
        workers=None):
    from scipy.optimize import least_squares

    # measured: dogbox needs ~3x fewer evaluations than trf on the zero-residual joint eigen
    # fits; trf is faster and finds the better basins on the non-zero-residual fits (projected
    # paper eigen, combined): dogbox stalled at 0.13-0.34 % where trf reached 0.04-0.05 %
    x0 = np.clip(x0, lb, ub)
    return least_squares(fun, x0, jac=jac, bounds=(lb, ub), method=method, x_scale=x_scale,
                         ftol=tol, xtol=tol, gtol=tol, max_nfev=max_nfev, workers=workers)


def _slsqp(fun, x0, lb, ub, max_iter=200, workers=None, jac=None):
    from scipy.optimize import Bounds, minimize

    x0 = np.clip(x0, lb, ub)
    opts = {"ftol": 1e-14, "maxiter": max_iter, "eps": 1e-8}
    if workers is not None:
        opts["workers"] = workers
    return minimize(fun, x0, method="SLSQP", jac=jac, bounds=Bounds(lb, ub), options=opts)


def solve_start(spec: _Spec, index: int, lengths0: np.ndarray, factors0: np.ndarray):
    """Run the local solver from one start; returns a :class:`StartResult`."""
    p = spec.problem
    n = p.n_joints
    u0 = unit_from_lengths(lengths0, p.length_m, p.min_fraction)
    if p.stiffness == "joint":
        J = _Joint(spec)
        lb = np.r_[np.zeros(n), np.full(n, _LN_S_BOUNDS[0])]
        ub = np.r_[np.ones(n), np.full(n, _LN_S_BOUNDS[1])]
        x0 = np.r_[u0, np.log(factors0)]
        if spec.objective == "eigen":
            r = _ls(J.eigen_residuals, x0, lb, ub, spec.max_nfev, jac=J.eigen_jac,
                    method="dogbox" if p.n_poses == 1 else "trf")
        else:
            r = _ls(J.residuals, x0, lb, ub, spec.max_nfev, jac=J.jac, method="trf",
                    x_scale="jac")
        x, msg, ok = r.x, r.message, bool(r.success)
        if p.n_poses > 1:
            r2 = _slsqp(J.loss, x, lb, ub)
            if r2.fun <= J.loss(x):
                x, msg = r2.x, f"{msg}; polished: {r2.message}"
        lengths, s = J.split(x)
        return StartResult(index, lengths, s, 100.0 * J.loss(x), J.nfev, ok, str(msg))
    if spec.objective == "eigen":
        P = _PaperEigen(spec)
        # a loose stage-1 tolerance: the best few starts are polished on the true loss
        r = _ls(P.residuals, u0, np.zeros(n), np.ones(n), spec.max_nfev, method="trf", tol=1e-8,
                workers=P.map)
        return StartResult(index, P.lengths(r.x), P.factors(r.x), 100.0 * P.loss(r.x),
                           P.nfev, bool(r.success), str(r.message))
    S = _PaperScalar(spec)
    lb = np.r_[np.zeros(n), np.full(p.n_poses, _LN_S_BOUNDS[0] + math.log(1e-2))]
    ub = np.r_[np.ones(n), np.full(p.n_poses, _LN_S_BOUNDS[1] + math.log(1e3))]
    r = _slsqp(S.loss, np.r_[u0, np.log(factors0)], lb, ub, jac=S.jac)
    lengths = lengths_from_unit(r.x[:n], p.length_m, p.min_fraction)
    return StartResult(index, lengths, np.exp(r.x[n:]), 100.0 * float(r.fun), S.nfev,
                       bool(r.success), str(r.message))


def polish_paper_eigen(spec: _Spec, start: StartResult) -> StartResult:
    """Polish a variable-projected ``paper`` eigen optimum on the paper's loss with SLSQP."""
    P = _PaperEigen(spec)
    p = spec.problem
    u0 = unit_from_lengths(start.lengths_m, p.length_m, p.min_fraction)
    r = _slsqp(P.loss, u0, np.zeros(p.n_joints), np.ones(p.n_joints), workers=P.loss_map)
    loss = 100.0 * P.loss(r.x)
    if not loss < start.loss_pct:
        return replace(start, nfev=start.nfev + P.nfev)
    return StartResult(start.index, P.lengths(r.x), P.factors(r.x), loss, start.nfev + P.nfev,
                       start.success, f"{start.message}; polished: {r.message}")


# --- multistart driver ------------------------------------------------------------------------
_WORKER_SPEC: _Spec | None = None


def _init_worker(spec: _Spec) -> None:
    global _WORKER_SPEC
    _WORKER_SPEC = spec


def _run_one(args) -> StartResult:
    i, lengths0, factors0 = args
    return solve_start(_WORKER_SPEC, i, lengths0, factors0)


def _pool_context():
    import multiprocessing as mp

    pinned = all(os.environ.get(v) == "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"))
    if pinned and "fork" in mp.get_all_start_methods():
        return mp.get_context("fork")
    # BLAS reads its thread count at import: pin it for children started fresh
    for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[v] = "1"
    return mp.get_context("spawn")


def run_starts(spec: _Spec, tasks: list, workers: int = 1, progress: bool = True,
               loss_tol: float | None = None) -> list[StartResult]:
    """Solve the starts in order, in ``workers`` processes; stop after the first (in start
    order) whose loss is <= ``loss_tol`` (%). Returns the results of the starts run, in order."""
    from tqdm.auto import tqdm

    out: list[StartResult] = []
    bar = tqdm(total=len(tasks), disable=not progress, desc="fit starts", unit="start")
    try:
        if workers <= 1:
            for t in tasks:
                res = solve_start(spec, *t)
                out.append(res)
                bar.update()
                if loss_tol is not None and res.loss_pct <= loss_tol:
                    break
            return out
        from .workers import pool_scope, process_pool

        with pool_scope(process_pool(workers, _pool_context(), _init_worker, (spec,))) as ex:
            futures = [ex.submit(_run_one, t) for t in tasks]
            for fut in futures:
                res = fut.result()
                out.append(res)
                bar.update()
                if loss_tol is not None and res.loss_pct <= loss_tol:
                    for f in futures:
                        f.cancel()
                    break
        return out
    finally:
        bar.close()


def _check_fit_args(objective, starts, workers, target):
    if objective not in OBJECTIVES:
        raise BeamInputError(f"objective = {objective!r}: must be one of {OBJECTIVES}")
    if isinstance(starts, bool) or not isinstance(starts, (int, np.integer)) or starts < 1:
        raise BeamInputError(f"starts = {starts!r}: must be an integer >= 1")
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise BeamInputError(f"workers = {workers!r}: must be an integer >= 1")
    if objective != "eigen" and not target.has_static:
        raise BeamInputError(
            f"objective = {objective!r}: the target has no truth tip position/displacement"
        )
    if objective != "eigen" and not np.any(target.tip_force_N):
        raise BeamInputError(f"tip_force = [0, 0, 0] N: a {objective} fit needs a tip load "
                             "(the beam's tip_force)")


def _draw_starts(problem: FitProblem, starts: int, seed: int) -> list:
    from .layout import sample_lengths

    rng = np.random.default_rng(seed)
    L0 = sample_lengths(rng, problem.length_m, problem.n_joints + 1, starts,
                        min_fraction=problem.min_fraction)
    # random factors: log-uniform within a factor 2 either side of the start's reference
    F0 = np.exp(rng.uniform(-math.log(2.0), math.log(2.0), (starts, problem.n_factors)))
    return [(i, L0[i], F0[i]) for i in range(starts)]


def fit(
    beam: Beam,
    target: FitTarget,
    joints: int,
    frequencies: int | None = None,
    objective: str = "eigen",
    stiffness: str = "paper",
    starts: int = 64,
    seed: int = 0,
    xi: float = 0.05,
    eps: float = 0.1,
    squared: bool = False,
    workers: int = 1,
    progress: bool = True,
    loss_tol: float | None = None,
    joint_sweep: bool = False,
    deflection_norm: str = "position",
    polish: int = 4,
    max_nfev: int = 400,
    eigen_norm: str = DEFAULT_EIGEN_NORM,
    min_fraction: float = 0.02,
) -> FitResult:
    """Fit an nR PRBDM to a target by a multistart of a local solver.

    Parameters
    ----------
    beam : Beam
    target : FitTarget
        Truth frequencies (rad/s) and, for deflection terms, the truth tip under the load.
    joints : int
        n, the number of revolute joints.
    frequencies : int, optional
        N <= n truth frequencies to match (default min(n, available)).
    objective : {"eigen", "deflection", "combined"}
        Eq. 17, Eq. 19 or Eq. 27 (eigen and tip-position, or tip-displacement with
        ``deflection_norm="displacement"``).
    stiffness : {"paper", "joint"}
        One SCF per pose on Eq. 14, or one factor per joint on the finite-segment stiffness.
    starts, seed : int
        Number of start points and the seed of their generator.
    xi, eps : float
        Pose sweep offset and step, rad (Eqs. 10-11).
    squared : bool
        Compare omega^2 instead of omega.
    workers : int
        Processes to spread the starts over (BLAS pinned to one thread in each).
    progress : bool
        Show a tqdm progress bar.
    loss_tol : float, optional
        Stop at the first start (in start order) whose loss (%) is at or below this.
    joint_sweep : bool
        ``joint`` only: compare frequencies over the pose sweep instead of the straight pose.
    polish : int
        ``paper`` eigen: polish the best starts, up to this many, on the paper's loss (a start
        whose lengths are within 1e-3 L of a better one's is not polished again).
    max_nfev : int
        Evaluation cap of each least-squares start.
    eigen_norm : {"relative", "paper"}
        The per-pose eigen error: the rms of the per-mode relative errors, each mode weighed
        equally (default), or Eq. 16's l2 norm (the paper's; dominated by the highest mode).
    min_fraction : float
        Lower bound of every link length as a fraction of L (Eq. 15c).

    Returns
    -------
    FitResult
        For ``paper`` its exported springs (``stiffness_Nm_per_rad``) are those of the sweep's
        first pose, the one nearest straight (``export_pose_rad``); the whole per-pose table is
        ``stiffness_per_pose_Nm_per_rad`` (``FitResult.stiffness_schedule``).
    """
    t0 = time.perf_counter()
    if deflection_norm not in ("position", "displacement"):
        raise BeamInputError(
            f"deflection_norm = {deflection_norm!r}: must be 'position' or 'displacement'")
    problem = make_problem(beam, target, joints, frequencies, stiffness, xi, eps, squared,
                           joint_sweep, min_fraction, check_eigen_norm(eigen_norm))
    _check_fit_args(objective, starts, workers, target)
    spec = _Spec(problem, objective, deflection_norm, int(max_nfev))
    tasks = _draw_starts(problem, int(starts), int(seed))
    if stiffness == "paper" and objective != "eigen":
        # random SCFs around each start's projected eigen optimum (the SCF scale is beam-specific)
        P = _PaperEigen(_Spec(problem, "eigen", deflection_norm, int(max_nfev)))
        tasks = [(i, L, F * P.factors(unit_from_lengths(L, problem.length_m,
                                                        problem.min_fraction)))
                 for i, L, F in tasks]
    runs = run_starts(spec, tasks, workers, progress, loss_tol)
    order = sorted(range(len(runs)), key=lambda i: (runs[i].loss_pct, i))
    best = runs[order[0]]
    if stiffness == "paper" and objective == "eigen" and polish > 0:
        # starts that ended in the same local optimum polish to the same design: polish
        # only distinct ones among the best ``polish``
        chosen: list[int] = []
        for i in order[:polish]:
            if all(np.max(np.abs(runs[i].lengths_m - runs[j].lengths_m)) > 1e-3 * beam.length_m
                   for j in chosen):
                chosen.append(i)
        polished = [polish_paper_eigen(spec, runs[i]) for i in chosen]
        best = min(polished, key=lambda r: (r.loss_pct, r.index))
        runs = [*runs]
        for q, i in zip(polished, chosen, strict=True):
            runs[i] = replace(runs[i], nfev=q.nfev)  # count the polishing evaluations too
    nfev = sum(r.nfev for r in runs)
    return result_from_design(
        problem, best.lengths_m, best.factors, objective=objective, seed=int(seed),
        starts=int(starts), starts_run=len(runs), nfev=nfev,
        start_losses_pct=np.array([r.loss_pct for r in runs]),
        wall_time_s=time.perf_counter() - t0, success=bool(best.success),
        message=f"best of {len(runs)} starts (start {best.index}): {best.message}",
        deflection_norm=deflection_norm,
    )


def result_from_design(problem: FitProblem, lengths_m, factors, *, objective: str, seed: int,
                       starts: int, starts_run: int, nfev: int, start_losses_pct,
                       wall_time_s: float, success: bool, message: str,
                       deflection_norm: str = "position") -> FitResult:
    """Evaluate a design in full (frequencies, tip under load) and package it as a FitResult."""
    t = problem.target
    try:
        ev = evaluate(problem, lengths_m, factors, deflection=t.has_static)
    except SolveError as exc:
        ev = evaluate(problem, lengths_m, factors, deflection=False)
        message = f"{message}; static deflection failed: {exc}"
    model, K0 = build(problem, lengths_m)
    extra = bool(t.extra_loads) and ev.extra_tip_position_m is not None
    notes = t.shape_notes()
    if (problem.stiffness == "joint" and objective == "eigen" and problem.n_poses == 1
            and problem.n_freq == problem.n_joints and ev.eigen_loss_pct > EXACT_MATCH_PCT):
        notes.insert(0, f"the {problem.n_freq} truth frequencies were not matched (eigen loss "
                        f"{ev.eigen_loss_pct:.3g} % after {starts_run} starts): a joint model "
                        "matches n frequencies exactly when they are within a chain's reach")
    n = problem.n_joints
    if problem.stiffness == "paper":
        k_mean = scf_mean(ev.factors)  # a diagnostic (Eq. 25): no pose was fitted with it
        dev = scf_deviation_pct(ev.factors)
        # the springs of one fitted pose: the sweep's first, the one nearest straight (the
        # frequencies move by O(q^2) from there to q = 0; the straight pose is where users
        # linearise and simulate)
        K = ev.stiffness_Nm_per_rad[0]
        pose = problem.poses_rad[0]
        described = (f"paper: the springs fitted at sweep pose 0 (every joint at "
                     f"{pose[0]:.6g} rad, the pose nearest straight; SCF {ev.factors[0]:.6g})")
    else:
        k_mean = float(np.mean(ev.factors))
        K = ev.factors * K0
        dev = np.zeros(problem.n_poses)
        pose = np.zeros(n)
        described = ("joint: pose-independent springs, fitted "
                     + ("over the pose sweep" if problem.n_poses > 1 else "at the straight pose"))
    omega_errors = mode_errors_pct(ev.omega_model_rad_s, t.omega_truth_rad_s)
    # the exported model on its own: its frequencies at the straight pose
    w_export = model.with_stiffness(K).natural_frequencies(np.zeros(n))[: problem.n_freq]
    export_errors = mode_errors_pct(w_export, t.omega_truth_rad_s)[0]
    worst_export = worst_mode_error_pct(export_errors)
    if worst_export > EXPORT_WARN_PCT:
        k = int(np.argmax(np.abs(export_errors)))
        notes.append(f"the exported model ({described}) misses "
                     f"truth mode {k + 1} by {export_errors[k]:+.3g} % at the straight pose "
                     f"(every mode: {_pct_list(export_errors)}); the {problem.eigen_norm}-norm "
                     f"eigen loss of {ev.eigen_loss_pct:.3g} % does not show it"
                     + ("; Eq. 14's springs, one SCF times sqrt(E I_j / m_j), cannot follow "
                        "every planform: joint springs (stiffness='joint') fit each joint"
                        if problem.stiffness == "paper" else ""))
    notes.extend(_bound_notes(ev.lengths_m, problem.length_m, problem.min_fraction))
    return FitResult(
        beam_name=problem.beam.name, beam_fingerprint=problem.beam.fingerprint(),
        joints=problem.n_joints, frequencies=problem.n_freq, objective=objective,
        stiffness=problem.stiffness, lengths_m=ev.lengths_m, stiffness_Nm_per_rad=K,
        stiffness_per_pose_Nm_per_rad=ev.stiffness_Nm_per_rad, factors=ev.factors,
        scf_mean=k_mean, scf_deviation_pct=dev, poses_rad=problem.poses_rad,
        omega_truth_rad_s=t.omega_truth_rad_s, omega_model_rad_s=ev.omega_model_rad_s,
        eigen_errors_pct=100.0 * ev.eigen_errors, eigen_loss_pct=ev.eigen_loss_pct,
        deflection_loss_pct=ev.deflection_loss_pct,
        displacement_loss_pct=ev.displacement_loss_pct,
        combined_loss_pct=ev.combined_loss_pct if deflection_norm == "position"
        else float(math.hypot(ev.eigen_loss_pct, ev.displacement_loss_pct)),
        tip_position_model_m=ev.tip_position_m, tip_position_truth_m=t.tip_position_m,
        tip_displacement_truth_m=t.tip_displacement_m, tip_force_N=t.tip_force_N, mac=t.mac,
        truth_source=t.source, truth_request=t.truth_request,
        static_theory_gap_pct=math.nan if t.static_theory_gap_pct is None
        else float(t.static_theory_gap_pct),
        squared=problem.squared,
        xi=problem.xi, eps=problem.eps,
        seed=seed, starts=starts, starts_run=starts_run, nfev=nfev,
        start_losses_pct=start_losses_pct, wall_time_s=wall_time_s, success=success,
        message=message,
        extra_tip_force_N=np.array([c.tip_force_N for c in t.extra_loads]) if extra else None,
        extra_tip_position_truth_m=np.array([c.tip_position_m for c in t.extra_loads])
        if extra else None,
        extra_tip_position_model_m=ev.extra_tip_position_m if extra else None,
        warnings=tuple(notes),
        eigen_norm=problem.eigen_norm, min_fraction=problem.min_fraction,
        omega_errors_pct=omega_errors,
        worst_mode_error_pct=worst_mode_error_pct(omega_errors), export_pose_rad=pose,
        stiffness_pose=described, omega_export_rad_s=w_export,
        omega_export_errors_pct=export_errors, worst_export_error_pct=worst_export,
    )


def _pct_list(errors_pct) -> str:
    return ", ".join(f"{v:+.3g}" for v in np.ravel(errors_pct)) + " %"


def _bound_notes(lengths_m: np.ndarray, length_m: float, min_fraction: float) -> list[str]:
    """One note per link at its lower bound: ``L_j <= min_fraction L + 1e-6 L``."""
    a = min_fraction * length_m
    return [f"link {j} ({v:.6g} m) sits on its length bound min_fraction L = {a:.6g} m "
            f"(min_fraction {min_fraction:g}): the fit wanted it shorter, so the optimum is "
            "constrained; fewer joints or a lower min_fraction (--min-link) may fit better"
            for j, v in enumerate(np.asarray(lengths_m, dtype=float))
            if v <= a + BOUND_TOL * length_m]


# --- Pareto ----------------------------------------------------------------------------------
def fit_pareto(
    beam: Beam,
    target: FitTarget,
    joints: int,
    frequencies: int | None = None,
    stiffness: str = "paper",
    pop: int = 100,
    generations: int = 200,
    seed: int = 0,
    xi: float = 0.05,
    eps: float = 0.01,
    squared: bool = False,
    deflection_norm: str = "position",
    log10_bounds: tuple[float, float] | None = None,
    progress: bool = True,
    workers: int = 1,
    seed_with_fits: bool = True,
    seed_starts: int = 4,
    polish_knee: bool = True,
    eigen_norm: str = DEFAULT_EIGEN_NORM,
    min_fraction: float = 0.02,
) -> ParetoResult:
    """NSGA-II Pareto fit over (eigen loss, deflection loss), with the knee of Eq. 27.

    Design vector [gamma (n+1), log10 factors]; a Repair projects gamma onto the bounded
    simplex; termination after ``generations`` generations. ``log10_bounds`` bounds the log10
    factors (default: joint factors in [-1, 1]; SCFs within 1.5 decades of the projected eigen
    optimum at equal link lengths). ``eps`` defaults to the paper's Pareto step 0.01 rad.
    ``workers > 1`` evaluates each generation's designs in that many processes (results do not
    depend on it).

    ``seed_with_fits`` puts the single-objective optima (eigen-only, deflection-only and the
    Eq. 27 combined optimum, each the best of a ``seed_starts`` multistart :func:`fit` with the
    same seed) and designs on the segments between them into the initial population, the rest
    drawn uniformly (lengths on the bounded simplex, log10 factors in their bounds), so the front
    spans its anchors and the knee region.
    ``polish_knee`` (default on) runs the single-objective local solver on Eq. 27 from the
    NSGA-II knee and adds the result to the front if no front design dominates it; the knee is
    then taken on that front, and ``message`` records the raw NSGA-II knee beside it. Each
    generation is evaluated as one batch (``problem.pareto_objectives_batch``: every design's and
    pose's static solve in one vectorised Newton), so a ``paper`` front with a static solve per
    pose costs seconds, not minutes. ``eigen_norm`` (``"paper"``, Eq. 16, or ``"relative"``)
    is the norm of the front's eigen objective; ``min_fraction`` bounds the link lengths.
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize
    from pymoo.termination import get_termination

    t0 = time.perf_counter()
    if deflection_norm not in ("position", "displacement"):
        raise BeamInputError(
            f"deflection_norm = {deflection_norm!r}: must be 'position' or 'displacement'")
    for name, v in (("pop", pop), ("generations", generations)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise BeamInputError(f"{name} = {v!r}: must be an integer >= 1")
    problem = make_problem(beam, target, joints, frequencies, stiffness, xi, eps, squared,
                           min_fraction=min_fraction, eigen_norm=check_eigen_norm(eigen_norm))
    if not target.has_static:
        raise BeamInputError("target has no truth tip position: a Pareto fit needs one")
    if not np.any(target.tip_force_N):
        raise BeamInputError("tip_force = [0, 0, 0] N: a Pareto fit needs a tip load "
                             "(the beam's tip_force)")
    n1 = problem.n_joints + 1
    if log10_bounds is None:
        if stiffness == "joint":
            log10_bounds = (-1.0, 1.0)
        else:
            eq = np.full(n1, problem.length_m / n1)
            _, _, W = unit_frequencies(problem, eq)
            k_ref = float(np.mean(best_scale(W, problem.target.omega_truth_rad_s, squared,
                                             problem.eigen_norm)))
            log10_bounds = (math.log10(k_ref) - 1.5, math.log10(k_ref) + 1.5)
    if isinstance(seed_starts, bool) or not isinstance(seed_starts, (int, np.integer)) \
            or seed_starts < 1:
        raise BeamInputError(f"seed_starts = {seed_starts!r}: must be an integer >= 1")
    pp = ParetoProblem(problem, log10_bounds, deflection_norm=deflection_norm)
    X0, n_seed_evals = _initial_population(
        beam, target, problem, int(pop), int(seed), log10_bounds, deflection_norm,
        seed_with_fits, int(seed_starts), workers)
    algo = NSGA2(pop_size=int(pop), sampling=X0, repair=LengthRepair(n1, problem.min_fraction),
                 eliminate_duplicates=True)
    kw = {}
    if progress:
        kw["callback"] = _PymooBar(int(generations))
    pool = None
    if workers > 1:
        from .workers import process_pool

        pool = process_pool(workers, _pool_context(), _init_pareto_worker,
                            (problem, deflection_norm))
        pp.map_rows = lambda X: np.vstack(list(pool.map(_pareto_rows,
                                                        np.array_split(X, int(workers)))))
    try:
        res = minimize(pp, algo, get_termination("n_gen", int(generations)), seed=int(seed),
                       verbose=False, **kw)
    except BaseException:
        if pool is not None:
            from .workers import stop_pool

            stop_pool(pool)
            pool = None
        raise
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        if progress:
            kw["callback"].close()
    F = np.atleast_2d(res.F)
    X = np.atleast_2d(res.X)
    n_evals = int(res.algorithm.evaluator.n_eval) + n_seed_evals
    ki = knee_index(F)
    raw = F[ki].copy()
    note = (f"raw NSGA-II knee: eigen {raw[0]:.6g} %, deflection {raw[1]:.6g} %, "
            f"combined {math.hypot(raw[0], raw[1]):.6g} %")
    if polish_knee:
        x_p, f_p, nfev_p = _polish_knee(problem, X[ki], deflection_norm, log10_bounds)
        n_evals += nfev_p
        dominated = np.any(np.all(F <= f_p, axis=1) & np.any(F < f_p, axis=1))
        if np.all(np.isfinite(f_p)) and not dominated:
            keep = ~(np.all(f_p <= F, axis=1) & np.any(f_p < F, axis=1))
            F, X = np.vstack([F[keep], f_p]), np.vstack([X[keep], x_p])
            note += (f"; polished knee (Eq. 27 local solver): combined "
                     f"{math.hypot(f_p[0], f_p[1]):.6g} %")
        else:
            note += "; the knee polish did not improve on the front"
    order = np.lexsort((F[:, 1], F[:, 0]))
    F, X = F[order], X[order]
    ki = knee_index(F)
    lengths = X[:, :n1] * problem.length_m
    factors = 10.0 ** X[:, n1:]
    wall = time.perf_counter() - t0
    knee = result_from_design(
        problem, lengths[ki], factors[ki], objective="combined", seed=int(seed), starts=int(pop),
        starts_run=int(pop), nfev=n_evals,
        start_losses_pct=np.hypot(F[:, 0], F[:, 1]), wall_time_s=wall, success=True,
        message=f"knee (Eq. 27) of an NSGA-II front of {F.shape[0]} designs; {note}",
        deflection_norm=deflection_norm)
    return ParetoResult(
        beam_name=beam.name, joints=problem.n_joints, frequencies=problem.n_freq,
        stiffness=stiffness, deflection_norm=deflection_norm, F_pct=F, X=X,
        front_lengths_m=lengths, front_factors=factors, knee_index=ki, pop=int(pop),
        generations=int(generations), n_evals=n_evals,
        seed=int(seed), xi=problem.xi, eps=problem.eps, wall_time_s=wall, success=True,
        eigen_norm=problem.eigen_norm,
        message=f"NSGA-II, {generations} generations of {pop}"
                f"{', seeded with single-objective fits' if seed_with_fits else ''}; {note}",
        knee=knee)


def _design_row(problem: FitProblem, lengths_m, factors, log10_bounds) -> np.ndarray:
    """[gamma, log10 factors] of a design, the factors clipped to the Pareto bounds."""
    lf = np.clip(np.log10(np.asarray(factors, dtype=float)), *log10_bounds)
    return np.r_[np.asarray(lengths_m, dtype=float) / problem.length_m, lf]


def _initial_population(beam, target, problem: FitProblem, pop: int, seed: int, log10_bounds,
                        deflection_norm: str, seed_with_fits: bool, seed_starts: int,
                        workers: int) -> tuple[np.ndarray, int]:
    """NSGA-II's initial population: single-objective optima (optional) then uniform draws."""
    from .layout import sample_lengths

    rng = np.random.default_rng(seed)
    n1 = problem.n_joints + 1
    X = np.empty((pop, n1 + problem.n_factors))
    X[:, :n1] = sample_lengths(rng, problem.length_m, n1, pop,
                               min_fraction=problem.min_fraction) / problem.length_m
    X[:, n1:] = rng.uniform(log10_bounds[0], log10_bounds[1], (pop, problem.n_factors))
    nfev = 0
    if seed_with_fits:
        rows = []
        for objective in ("combined", "eigen", "deflection")[:pop]:
            r = fit(beam, target, problem.n_joints, problem.n_freq, objective=objective,
                    stiffness=problem.stiffness, starts=seed_starts, seed=seed, xi=problem.xi,
                    eps=problem.eps, squared=problem.squared, workers=workers, progress=False,
                    deflection_norm=deflection_norm, eigen_norm=problem.eigen_norm,
                    min_fraction=problem.min_fraction)
            nfev += r.nfev
            rows.append(_design_row(problem, r.lengths_m, r.factors, log10_bounds))
        # designs on the segments eigen -> combined -> deflection anchor (the bounded length
        # simplex is convex): a start for the middle of the front, which NSGA-II alone fills
        # slowly when the SCFs add tens of variables
        combined, eigen, deflection = rows[0], rows[1 % len(rows)], rows[-1]
        for a, b in ((eigen, combined), (combined, deflection)):
            for t in np.linspace(0.0, 1.0, INTERPOLATED_SEEDS + 2)[1:-1]:
                rows.append((1.0 - t) * a + t * b)
        rows = rows[:pop]
        X[:len(rows)] = rows
    return X, nfev


INTERPOLATED_SEEDS = 5  # per segment between two anchors of the initial population


def _polish_knee(problem: FitProblem, x: np.ndarray, deflection_norm: str, log10_bounds):
    """The Eq. 27 local solver from a front design: (design row, (eigen %, deflection %), nfev)."""
    n1 = problem.n_joints + 1
    spec = _Spec(problem, "combined", deflection_norm, 400)
    r = solve_start(spec, 0, x[:n1] * problem.length_m, 10.0 ** x[n1:])
    x_p = _design_row(problem, r.lengths_m, r.factors, log10_bounds)
    f_p = pareto_objectives(problem, x_p[:n1] * problem.length_m, 10.0 ** x_p[n1:],
                            deflection_norm=deflection_norm)
    return x_p, f_p, int(r.nfev) + 1


_WORKER_PARETO: tuple | None = None


def _init_pareto_worker(problem: FitProblem, deflection_norm: str) -> None:
    global _WORKER_PARETO
    _WORKER_PARETO = (problem, deflection_norm)


def _pareto_rows(X: np.ndarray) -> np.ndarray:
    problem, norm = _WORKER_PARETO
    return pareto_objectives_batch(problem, X, deflection_norm=norm)


class _PymooBar:
    """A pymoo callback driving a tqdm bar, one tick per generation."""

    def __init__(self, total: int):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=total, desc="NSGA-II", unit="gen")

    def __call__(self, algorithm) -> None:
        self.bar.update()

    def close(self) -> None:
        self.bar.close()


__all__ += ["pareto_objectives"]
