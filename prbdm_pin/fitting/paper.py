"""Losses of the ``paper`` parametrisation (Eq. 14: one SCF k_i per pose on
``sqrt(E I / m)``): the variable-projected eigen residuals over u (n) and the scalar loss with a
deflection term over x = [u, ln k].

Like every parametrisation each has ``nfev``, ``design(x) -> (lengths m, factors)`` and
``loss(x)`` (fraction).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import BeamInputError, SolveError
from ..evaluate import batch_losses, fast_unit_frequencies
from ..objectives import best_scale, projected_eigen_residuals
from ..problem import lengths_from_unit
from .spec import BAD_LOSS, FitSpec

__all__ = ["PaperEigenResiduals", "PaperScalarLoss"]


class PaperEigenResiduals:
    """Variable-projected eigen residuals of the ``paper`` parametrisation over u (n)."""

    def __init__(self, spec: FitSpec):
        self.p = spec.problem
        self.nfev = 0

    def lengths(self, u):
        """Link lengths of u, m."""
        return lengths_from_unit(u, self.p.length_m, self.p.min_fraction)

    def design(self, u):
        """Lengths (m) and each pose's projected SCF of u."""
        return self.lengths(u), self.factors(u)

    def pose_residuals(self, u):
        self.nfev += 1
        return self.batch(np.asarray(u, dtype=float)[None])[0]

    def batch(self, U):
        """Projected per-pose residuals (B, m, N) of the designs in the rows of U."""
        p = self.p
        try:
            _, W = fast_unit_frequencies(p, np.array([self.lengths(u) for u in U]))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            if U.shape[0] == 1:
                return np.full((1, p.n_poses, p.n_freq), BAD_LOSS)
            return np.concatenate([self.batch(U[i : i + 1]) for i in range(U.shape[0])])
        # each pose's best SCF in closed form (objectives.best_scale, weighted by the norm)
        return projected_eigen_residuals(W, p.target.omega_truth_rad_s, p.squared,
                                         p.eigen_norm)

    def map(self, fun, xs):
        """A ``workers`` map for scipy's finite differences: the stencil in one batch
        (``fun`` is :meth:`residuals` wrapped by scipy, whose rows these are)."""
        U = np.array(list(xs), dtype=float)
        self.nfev += U.shape[0]
        return list(self.batch(U).reshape(U.shape[0], -1) / math.sqrt(self.p.n_poses))

    def residuals(self, u):
        return self.pose_residuals(u).ravel() / math.sqrt(self.p.n_poses)

    def loss(self, u):
        return float(np.mean(np.linalg.norm(self.pose_residuals(u), axis=1)))

    def loss_map(self, fun, xs):
        """A ``workers`` map for scipy's finite differences of :meth:`loss`, in one batch."""
        U = np.array(list(xs), dtype=float)
        self.nfev += U.shape[0]
        return list(np.linalg.norm(self.batch(U), axis=2).mean(axis=1))

    def factors(self, u):
        _, W = fast_unit_frequencies(self.p, self.lengths(u))
        return best_scale(W, self.p.target.omega_truth_rad_s, self.p.squared,
                          self.p.eigen_norm)


class PaperScalarLoss:
    """Scalar loss of the ``paper`` parametrisation with a deflection term, x = [u, ln k].

    Evaluated through ``evaluate.batch_losses`` (closed-form kinematics, every pose's static
    solve in one vectorised Newton). The gradient uses the problem's structure: pose i's eigen
    and tip errors depend on its own SCF k_i only, so one central difference that moves every
    ln k_i at once gives all m partial derivatives in ln k; the n length coordinates take
    forward differences. The whole stencil (n + 3 designs) is one batch.
    """

    _H_U, _H_K = 1e-7, 1e-6

    def __init__(self, spec: FitSpec):
        self.spec = spec
        self.p = spec.problem
        self.nfev = 0

    def design(self, x):
        """Lengths (m) and SCFs of x."""
        n = self.p.n_joints
        return lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction), np.exp(x[n:])

    def _parts(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per-pose eigen and tip errors (fractions), each (B, m), of the rows of X."""
        p, n = self.p, self.p.n_joints
        lengths = np.array([lengths_from_unit(x[:n], p.length_m, p.min_fraction) for x in X])
        r = batch_losses(p, lengths, np.exp(X[:, n:]))
        return r.eigen_errors, r.tip_errors(self.spec.deflection_norm)

    def _loss(self, e: np.ndarray, d: np.ndarray) -> np.ndarray:
        loss = d.mean(axis=-1) if self.spec.objective == "deflection" \
            else np.hypot(e.mean(axis=-1), d.mean(axis=-1))
        return np.where(np.isfinite(loss), loss, BAD_LOSS)

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
        if not (np.all(np.isfinite(de)) and np.all(np.isfinite(dd)) and f[0] < BAD_LOSS):
            g[n:] = 0.0  # an unsolvable neighbour: no information on the SCFs here
        elif self.spec.objective == "deflection":
            g[n:] = dd / m
        else:
            g[n:] = (E * de + D * dd) / (m * max(f[0], 1e-300))
        return g

