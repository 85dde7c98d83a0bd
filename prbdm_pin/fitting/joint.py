"""Residuals of the ``joint`` parametrisation: one pose-independent factor s_j per joint on the
finite-segment springs, over x = [u (n), ln s (n)] (u the stick-breaking length coordinates).

Like every parametrisation it has ``nfev``, ``design(x) -> (lengths m, factors)`` and
``loss(x)`` (fraction); the local solvers use its residuals and Jacobians.
"""

from __future__ import annotations

import math

import numpy as np

from ..eigen import modes_from_mass
from ..errors import BeamInputError, SolveError
from ..evaluate import chain_frequencies, chain_mass_matrices
from ..objectives import eigen_residuals, eigen_weights
from ..planar import planar_tip, planar_tips
from ..problem import lengths_from_unit
from ..statics import static_deflection_planar, static_deflection_planar_batch
from .spec import BAD_LOSS, FitSpec, tip_scales_m

__all__ = ["JointResiduals"]


class JointResiduals:
    """Residuals of the ``joint`` parametrisation over x = [u (n), ln s (n)]."""

    def __init__(self, spec: FitSpec):
        self.spec = spec
        p = spec.problem
        self.p = p
        self.f = p.target.omega_truth_rad_s ** (2 if p.squared else 1)
        # the eigen norm's weights (Eq. 16: 1/||f||; relative: 1/(f_k sqrt(N)))
        self.d = eigen_weights(p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
        self.cases = p.target.load_cases if spec.objective != "eigen" else ()
        self.norms = tip_scales_m(p, spec.deflection_norm) if self.cases else np.zeros(0)
        self.q0 = [None] * len(self.cases)  # warm starts, one per load case
        self.nfev = 0
        self._cache = None

    def design(self, x):
        """Lengths (m) and joint factors of x."""
        n = self.p.n_joints
        return lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction), np.exp(x[n:])

    def residuals(self, x):
        self.nfev += 1
        p, spec = self.p, self.spec
        lengths, s = self.design(x)
        parts = []
        try:
            M, K0 = chain_mass_matrices(p, lengths)
            K = s * K0
            if spec.objective != "deflection":
                w = chain_frequencies(M, K)[:, : p.n_freq]
                parts.append(eigen_residuals(w, p.target.omega_truth_rad_s, p.squared,
                                             p.eigen_norm).ravel() / math.sqrt(p.n_poses))
            # the squared residuals of k load cases sum to the mean squared tip error
            wc = 1.0 / math.sqrt(max(len(self.cases), 1))
            for c, case in enumerate(self.cases):
                q = static_deflection_planar(lengths, K, case.tip_force_N, q0=self.q0[c])
                tip = planar_tip(lengths, q)[0]
                self.q0[c] = q
                parts.append((tip - case.tip_position_m) * (wc / self.norms[c]))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.full(self.size(), BAD_LOSS)
        return np.concatenate(parts)

    def size(self):
        p, o = self.p, self.spec.objective
        return (p.n_poses * p.n_freq if o != "deflection" else 0) + 3 * len(self.cases)

    def _eigen_parts(self, x):
        """Scaled eigen residuals (m*N,) and their analytic derivative in ln s, (m*N, n)."""
        p = self.p
        lengths, s = self.design(x)
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
        # objectives.eigen_residuals with the weights and 1/sqrt(m) in one factor, which the
        # analytic ln s derivative shares
        c = np.tile(self.d, p.n_poses) / math.sqrt(p.n_poses)
        res = (w ** (2 if p.squared else 1)).ravel()
        return (res - np.tile(self.f, p.n_poses)) * c, np.vstack(dlns) * c[:, None]

    def _stencil_residuals(self, X, chain=None):
        """Scaled eigen residuals of the designs in the rows of X, (B, m*N), in one batch
        (``chain``: their lengths, mass matrices and unit springs, when already computed)."""
        p, n = self.p, self.p.n_joints
        if chain is None:
            lengths = np.array([self.design(x)[0] for x in X])
            chain = (lengths, *chain_mass_matrices(p, lengths))
        _, M, K0 = chain
        w = chain_frequencies(M, np.exp(X[:, n:]) * K0)[..., : p.n_freq]
        r = eigen_residuals(w, p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
        return r.reshape(X.shape[0], -1) / math.sqrt(p.n_poses)

    def _batch_residuals(self, X):
        """:meth:`residuals` of the designs in the rows of X, (B, size), in one batch: one
        stacked eigensolve and, per load case, every design's static solve in one vectorised
        Newton. A design that cannot be solved gets NaN residuals."""
        p, n = self.p, self.p.n_joints
        lengths = np.array([self.design(x)[0] for x in X])
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
            r, d = np.full(self.size(), BAD_LOSS), np.zeros((self.size(), self.p.n_joints))
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
