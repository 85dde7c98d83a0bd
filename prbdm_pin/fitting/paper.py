"""Losses of the ``paper`` parametrisation (equation 14: one SCF k_i per pose on ``sqrt(E I / m)``).

They are the variable-projected eigen residuals over u (n) and the scalar loss with a
deflection term over x = [u, ln k].

Like every parametrisation each has ``nfev``, ``design(x) -> (lengths m, factors)`` and
``loss(x)`` (fraction).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import BeamInputError, SolveError
from .evaluate import batch_losses, fast_unit_frequencies
from .objectives import best_scale, projected_eigen_residuals
from .paper_jacobian import projected_residual_jacobian, scalar_loss_gradient, unit_chain_gradient
from .problem import lengths_from_unit
from .spec import BAD_LOSS, FitSpec, tip_scales_m

__all__ = ["PaperEigenResiduals", "PaperScalarLoss"]


class PaperEigenResiduals:
    """Variable-projected eigen residuals of the ``paper`` parametrisation over u (n).

    Parameters
    ----------
    spec : FitSpec
        The fit problem; its objective is ``eigen``.
    """

    def __init__(self, spec: FitSpec):
        self.p = spec.problem
        self.nfev = 0

    def lengths(self, u):
        """Return the link lengths of u, m, shape (n+1,)."""
        return lengths_from_unit(u, self.p.length_m, self.p.min_fraction)

    def design(self, u):
        """Return the link lengths (m) and each pose's projected SCF of u.

        Parameters
        ----------
        u : ndarray, shape (n,)
            Stick-breaking length coordinates in [0, 1] (dimensionless).

        Returns
        -------
        lengths_m : ndarray, shape (n+1,)
            Link lengths, m.
        factors : ndarray, shape (m,)
            Each pose's best SCF in closed form (the factor on ``sqrt(E I / m)``).
        """
        return self.lengths(u), self.factors(u)

    def pose_residuals(self, u):
        """Return the projected residuals (m, N) of u (fractions); one evaluation."""
        self.nfev += 1
        return self.batch(np.asarray(u, dtype=float)[None])[0]

    def batch(self, U):
        """Return the projected per-pose residuals (B, m, N) of the designs in the rows of U.

        Parameters
        ----------
        U : ndarray, shape (B, n)
            Stick-breaking length coordinates in [0, 1] (dimensionless), one design a row.

        Returns
        -------
        ndarray, shape (B, m, N)
            The weighted frequency residuals at each pose's best SCF (fractions); ``BAD_LOSS``
            for a design whose model cannot be solved.
        """
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

    def residuals(self, u):
        """Return the stacked projected residuals (m N,) of u, scaled by ``1/sqrt(m)``."""
        return self.pose_residuals(u).ravel() / math.sqrt(self.p.n_poses)

    def _pose_jacobian(self, u):
        """Return the projected residuals (m, N) and their analytic Jacobian (m, N, n) at u.

        The Jacobian is zero where the model cannot be solved (as its residuals are then); one
        evaluation.
        """
        self.nfev += 1
        p = self.p
        try:
            g = unit_chain_gradient(p, np.asarray(u, dtype=float))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return (np.full((p.n_poses, p.n_freq), BAD_LOSS),
                    np.zeros((p.n_poses, p.n_freq, p.n_joints)))
        r = projected_eigen_residuals(g.omega_rad_s, p.target.omega_truth_rad_s, p.squared,
                                      p.eigen_norm)
        return r, projected_residual_jacobian(p, g)

    def jac(self, u):
        """Return the analytic Jacobian of :meth:`residuals` (:mod:`.paper_jacobian`), (m N, n)."""
        return self._pose_jacobian(u)[1].reshape(-1, self.p.n_joints) / math.sqrt(
            self.p.n_poses)

    def loss(self, u):
        """Return the paper's loss of u (fraction): the mean of the per-pose eigen norms.

        Parameters
        ----------
        u : ndarray, shape (n,)
            Stick-breaking length coordinates in [0, 1] (dimensionless).

        Returns
        -------
        float
            The loss (fraction).
        """
        return float(np.mean(np.linalg.norm(self.pose_residuals(u), axis=1)))

    def loss_grad(self, u):
        """Return the analytic gradient of :meth:`loss`, shape (n,), per unit of u."""
        r, dr = self._pose_jacobian(u)
        e = np.maximum(np.linalg.norm(r, axis=1), 1e-300)
        return np.einsum("ik,ikl->l", r / e[:, None], dr) / self.p.n_poses

    def factors(self, u):
        """Return each pose's best SCF of u in closed form (``objectives.best_scale``), (m,)."""
        _, W = fast_unit_frequencies(self.p, self.lengths(u))
        return best_scale(W, self.p.target.omega_truth_rad_s, self.p.squared,
                          self.p.eigen_norm)


class PaperScalarLoss:
    """Scalar loss of the ``paper`` parametrisation with a deflection term, x = [u, ln k].

    Evaluated through ``evaluate.batch_losses`` (closed-form kinematics, every pose's static
    solve in one vectorised Newton); its gradient is analytic (:mod:`.paper_jacobian`).

    Parameters
    ----------
    spec : FitSpec
        The fit problem, its objective (with a deflection term) and tip-error normalisation.
    """

    def __init__(self, spec: FitSpec):
        self.spec = spec
        self.p = spec.problem
        self.scales = tip_scales_m(self.p)
        self.nfev = 0

    def design(self, x):
        """Return the link lengths and the SCFs of x.

        Parameters
        ----------
        x : ndarray, shape (n + m,)
            [u, ln k]: stick-breaking length coordinates and log SCFs (dimensionless).

        Returns
        -------
        lengths_m : ndarray, shape (n+1,)
            Link lengths, m.
        factors : ndarray, shape (m,)
            Each pose's SCF (the factor on ``sqrt(E I / m)``).
        """
        n = self.p.n_joints
        return lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction), np.exp(x[n:])

    def _parts(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return the per-pose eigen and tip errors (fractions), each (B, m), of the rows of X."""
        p, n = self.p, self.p.n_joints
        lengths = np.array([lengths_from_unit(x[:n], p.length_m, p.min_fraction) for x in X])
        r = batch_losses(p, lengths, np.exp(X[:, n:]))
        return r.eigen_errors, r.tip_errors(p.deflection_norm)

    def _loss(self, e: np.ndarray, d: np.ndarray) -> np.ndarray:
        if self.spec.objective.has_eigen_term:
            loss = np.hypot(e.mean(axis=-1), d.mean(axis=-1))
        else:
            loss = d.mean(axis=-1)
        return np.where(np.isfinite(loss), loss, BAD_LOSS)

    def loss(self, x):
        """Return the scalar loss of x (fraction); ``BAD_LOSS`` where it cannot be solved.

        Parameters
        ----------
        x : ndarray, shape (n + m,)
            [u, ln k]: stick-breaking length coordinates and log SCFs (dimensionless).

        Returns
        -------
        float
            The mean tip error, or its hypot with the mean eigen error (fraction).
        """
        self.nfev += 1
        return float(self._loss(*self._parts(np.asarray(x, dtype=float)[None]))[0])

    def jac(self, x):
        """Return the analytic gradient of :meth:`loss` over x = [u, ln k], shape (n + m,).

        It is zero where the model cannot be solved, and counts as one evaluation.
        """
        self.nfev += 1
        x = np.asarray(x, dtype=float)
        p, n = self.p, self.p.n_joints
        try:
            g = unit_chain_gradient(p, x[:n])
            return scalar_loss_gradient(p, self.spec.objective, self.scales, g,
                                        np.exp(x[n:]))[1]
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.zeros(x.size)
