"""Residuals of the ``joint`` parametrisation.

It has one pose-independent factor s_j per joint on the finite-segment springs, over
x = [u (n), ln s (n)] (u the stick-breaking length coordinates). With ``gain_points`` the
tip amplitude rows of :mod:`.planar_gains` follow the frequency and tip rows.

Like every parametrisation it has ``nfev``, ``design(x) -> (lengths m, factors)`` and
``loss(x)`` (fraction); the local solvers use its residuals and analytic Jacobians
(:mod:`.joint_jacobian`).
"""

from __future__ import annotations

import math

import numpy as np

from ..chain.planar import tip_positions
from ..chain.planar_mass import chain_points, planar_mass_matrices
from ..chain.sections import planar_sections
from ..chain.statics import static_deflection_planar_unchecked
from ..chain.stiffness import finite_segment_stiffness_unchecked
from ..errors import BeamInputError, SolveError
from .evaluate import chain_frequencies
from .joint_jacobian import joint_residual_jacobian
from .objectives import eigen_residuals, eigen_weights
from .planar_gains import planar_gain_term, straight_modes
from .problem import lengths_from_unit
from .spec import BAD_LOSS, FitSpec, tip_scales_m

__all__ = ["JointResiduals"]


class JointResiduals:
    """Residuals of the ``joint`` parametrisation over x = [u (n), ln s (n)].

    Parameters
    ----------
    spec : FitSpec
        The fit problem, its objective, deflection norm and evaluation budget.
    """

    def __init__(self, spec: FitSpec):
        self.spec = spec
        p = spec.problem
        self.p = p
        self.f = p.target.omega_truth_rad_s ** (2 if p.squared else 1)
        # the eigen norm's weights (Eq. 16: 1/||f||; relative: 1/(f_k sqrt(N)))
        self.d = eigen_weights(p.target.omega_truth_rad_s, p.squared, p.eigen_norm)
        self.cases = p.target.load_cases if spec.objective.has_deflection_term else ()
        self.norms = tip_scales_m(p) if self.cases else np.zeros(0)
        # what scales each residual row: the eigen rows by their weights over sqrt(m); the
        # squared residuals of k load cases sum to the mean squared tip error
        self.eigen_row_scale = (np.tile(self.d, p.n_poses) / math.sqrt(p.n_poses))[:, None]
        wc = 1.0 / math.sqrt(max(len(self.cases), 1))
        self.tip_scale = [wc / norm for norm in self.norms]
        self.q0 = [None] * len(self.cases)  # warm starts, one per load case
        # the tip amplitudes at the straight pose (options.check_planar_gains: one pose)
        self.gains = planar_gain_term(p.target, p.options, p.n_freq)
        self.n_gains = 0 if self.gains is None else self.gains.size
        self.nfev = 0
        # (x as a tuple, what the Jacobian at the same x reuses) of the last residuals
        self._last = None

    def design(self, x):
        """Return the link lengths and the joint spring factors of x.

        Parameters
        ----------
        x : ndarray, shape (2n,)
            Fit coordinates [u, ln s] (dimensionless).

        Returns
        -------
        lengths_m : ndarray, shape (n+1,)
            Link lengths, m.
        factors : ndarray, shape (n,)
            Factors s on the finite-segment springs (dimensionless).
        """
        n = self.p.n_joints
        return lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction), np.exp(x[n:])

    def residuals(self, x):
        """Return the residual vector at x (all ``BAD_LOSS`` where the model cannot be solved).

        Parameters
        ----------
        x : ndarray, shape (2n,)
            Fit coordinates [u, ln s] (dimensionless).

        Returns
        -------
        ndarray, shape (size(),)
            The frequency residuals over the poses, scaled by ``1/sqrt(m)`` (fractions), then
            each load case's tip error over its tip scale, then with ``gain_points`` each
            mode's weighted tip amplitude error (:mod:`.planar_gains`) (dimensionless).
        """
        self.nfev += 1
        p, spec = self.p, self.spec
        lengths, s = self.design(x)
        out = np.empty(self.size())
        row = 0
        try:
            sec, K0, M, points = self._chain(lengths)
            K = s * K0
            if spec.objective.has_eigen_term:
                w = chain_frequencies(M, K)[:, : p.n_freq]
                row = w.size
                out[:row] = eigen_residuals(w, p.target.omega_truth_rad_s, p.squared,
                                            weights=self.d).ravel() / math.sqrt(p.n_poses)
            for c, case in enumerate(self.cases):
                q0 = np.zeros(p.n_joints) if self.q0[c] is None else self.q0[c]
                q = static_deflection_planar_unchecked(lengths, K, case.tip_force_N, q0)
                self.q0[c] = q
                out[row:row + 3] = (tip_positions(lengths, q) - case.tip_position_m) \
                    * self.tip_scale[c]
                row += 3
            if self.gains is not None:
                out[row:] = self.gains.residual(lengths, straight_modes(M[0], K))
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            self._last = None
            return np.full(self.size(), BAD_LOSS)
        self._last = (tuple(np.asarray(x, dtype=float).tolist()),
                      (lengths, s, sec, K0, M, points), list(self.q0))
        return out

    def _chain(self, lengths):
        """Return the sections, unit springs, mass matrices and points of valid lengths.

        As ``evaluate.chain_mass_matrices``, keeping the sections and the chain's points for
        the Jacobian.
        """
        p = self.p
        sec = planar_sections(p.beam, lengths)
        K0 = finite_segment_stiffness_unchecked(p.beam, lengths)
        points = chain_points(lengths[None], sec[1][None], p.poses_rad)
        return sec, K0, planar_mass_matrices(lengths, *sec[:3], p.poses_rad, points), points

    def size(self):
        """Return the length of the residual vector."""
        p = self.p
        return (p.n_poses * p.n_freq if self.spec.objective.has_eigen_term else 0) \
            + 3 * len(self.cases) + self.n_gains

    def jac(self, x):
        """Return the analytic Jacobian of :meth:`residuals` (:mod:`.joint_jacobian`).

        It counts as one evaluation; it is zero where the model cannot be solved (as its
        residuals are then).

        Parameters
        ----------
        x : ndarray, shape (2n,)
            Fit coordinates [u, ln s] (dimensionless).

        Returns
        -------
        ndarray, shape (size(), 2n)
            d residual / d x (per unit of each coordinate).
        """
        x = np.asarray(x, dtype=float)
        # a tuple's == on Python floats: np.array_equal's wrapper costs more than a short x
        if self._last is None or self._last[0] != tuple(x.tolist()):
            # scipy asks at the last residuals' x; elsewhere evaluate there first
            self.residuals(x)
            self.nfev -= 1
        self.nfev += 1
        if self._last is None:
            return np.zeros((self.size(), x.size))
        try:
            return joint_residual_jacobian(self, x, *self._last[1:])
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.zeros((self.size(), x.size))

    def eigen_residuals(self, x):
        """Return the residuals of the eigen objective (:meth:`residuals` with no load case)."""
        return self.residuals(x)

    def eigen_jac(self, x):
        """Return the analytic Jacobian of :meth:`eigen_residuals`."""
        return self.jac(x)

    def loss(self, x):
        """Return the true loss at x: mean of per-pose eigen norms, hypot with the tip term.

        With ``gain_points`` the norm of the amplitude rows joins the hypot.

        Parameters
        ----------
        x : ndarray, shape (2n,)
            Fit coordinates [u, ln s] (dimensionless).

        Returns
        -------
        float
            The loss (fraction).
        """
        r = self.residuals(x)
        p, o = self.p, self.spec.objective
        e = d = 0.0
        if o.has_eigen_term:
            ne = p.n_poses * p.n_freq
            e = float(np.mean(np.linalg.norm(
                r[:ne].reshape(p.n_poses, p.n_freq) * math.sqrt(p.n_poses), axis=1)))
            r = r[ne:]
        if o.has_deflection_term:
            # residuals scaled by 1/sqrt(k): the loss averages the k cases' errors (Eq. 18)
            k = len(self.cases)
            d = float(np.mean(np.linalg.norm(r[:3 * k].reshape(k, 3), axis=1))) * math.sqrt(k)
        g = float(np.linalg.norm(r[r.size - self.n_gains:])) if self.n_gains else 0.0
        return math.hypot(e, d, g)
