"""A design evaluated against its target.

Through the Pinocchio model (:func:`evaluate`, what every reported number comes from) and, for
the fit's inner loop, through the closed-form planar chain for many designs at once
(:func:`batch_losses`), which the tests check against it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..chain.eigen import eig_scaled
from ..chain.planar import planar_mass_matrices, planar_tips
from ..chain.sections import planar_sections
from ..chain.statics import static_deflection_planar_batch
from ..errors import BeamInputError, SolveError
from ..options.choices import DeflectionNorm
from .objectives import (
    check_deflection_norm,
    eigen_errors,
    tip_displacement_errors,
    tip_position_errors,
)
from .problem import FitProblem, static_tips

__all__ = [
    "Evaluation",
    "chain_mass_matrices",
    "chain_frequencies",
    "fast_unit_frequencies",
    "evaluate",
    "BatchLosses",
    "batch_losses",
]


@dataclass(frozen=True, eq=False)
class Evaluation:
    """A design evaluated against the target.

    Attributes
    ----------
    lengths_m : ndarray, shape (n+1,)
    factors : ndarray
        The SCFs k_i, shape (m,) (paper), or the joint factors s_j, shape (n,) (joint).
    stiffness_Nm_per_rad : ndarray, shape (m, n)
        The springs of every pose (rows identical for ``joint``), N m/rad.
    omega_model_rad_s : ndarray, shape (m, N)
    eigen_errors : ndarray, shape (m,)
        Per-pose relative eigen error in the problem's norm (fraction).
    tip_position_m : ndarray, shape (m', 3), or None
        Model tip under the load for each distinct stiffness (m' = m for paper, 1 for joint).
    position_errors, displacement_errors : ndarray, shape (m',), or None
        Relative tip errors (fractions), normalised by the truth tip position / displacement,
        averaged over the target's load cases.
    extra_tip_position_m : ndarray, shape (k, m', 3), or None
        Model tips under the target's ``extra_loads``.
    """

    lengths_m: np.ndarray
    factors: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    omega_model_rad_s: np.ndarray
    eigen_errors: np.ndarray
    tip_position_m: np.ndarray | None = None
    position_errors: np.ndarray | None = None
    displacement_errors: np.ndarray | None = None
    extra_tip_position_m: np.ndarray | None = None

    @property
    def eigen_loss_pct(self) -> float:
        """Eigen loss: the per-pose relative eigen errors averaged over poses (equation 17), %."""
        return float(100.0 * np.mean(self.eigen_errors))

    @property
    def deflection_loss_pct(self) -> float:
        """Tip error normalised by the truth tip position (equation 19), %; NaN without statics."""
        return math.nan if self.position_errors is None else float(
            100.0 * np.mean(self.position_errors))

    @property
    def displacement_loss_pct(self) -> float:
        """Tip error normalised by the truth tip displacement, %; NaN without statics."""
        return math.nan if self.displacement_errors is None else float(
            100.0 * np.mean(self.displacement_errors))

    @property
    def combined_loss_pct(self) -> float:
        """Combined loss sqrt(eigen^2 + deflection^2) (equation 27), %."""
        return float(math.hypot(self.eigen_loss_pct, self.deflection_loss_pct))

    def tip_loss_pct(self, norm: DeflectionNorm | str = DeflectionNorm.POSITION) -> float:
        """Return the tip loss in the normalisation ``norm``, %.

        ``norm`` is one of ``objectives.DEFLECTION_NORMS``.
        """
        if check_deflection_norm(norm) is DeflectionNorm.POSITION:
            return self.deflection_loss_pct
        return self.displacement_loss_pct



def chain_mass_matrices(problem: FitProblem, lengths_m: np.ndarray):
    """Mass matrices over the problem's poses and the unit-factor springs, without Pinocchio.

    The fit's inner loop calls this instead of ``problem.build``: the closed-form planar mass
    matrix (``planar.planar_mass_matrices``, checked against Pinocchio's CRBA in the tests)
    saves building a ``pinocchio.Model`` for each trial design. ``lengths_m`` must already be
    valid (as ``lengths_from_unit`` makes them); every reported result is re-evaluated with
    the Pinocchio model by :func:`evaluate`.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (n+1,) or (B, n+1)
        One design, or a stack of designs (e.g. a finite-difference stencil), m.

    Returns
    -------
    M : ndarray, shape (m, n, n) or (B, m, n, n)
        Mass matrices at the poses, kg m^2.
    K0 : ndarray, shape (n,) or (B, n)
        Unit-factor springs, N m/rad (as ``problem.parametrisation.build``'s).
    """
    lengths = np.asarray(lengths_m, dtype=float)
    mass, offset, Iyy, area_moment = planar_sections(problem.beam, lengths)
    K0 = problem.parametrisation.chain_unit_springs(problem.beam, lengths, area_moment, mass)
    M = planar_mass_matrices(lengths, mass, offset, Iyy, problem.poses_rad)
    return M, K0


def chain_frequencies(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Compute frequencies from :func:`chain_mass_matrices`' mass matrices and springs.

    Parameters
    ----------
    M : ndarray, shape (..., m, n, n)
        Mass matrices at the poses, kg m^2.
    K : ndarray, shape (..., n)
        Joint springs, N m/rad.

    Returns
    -------
    ndarray, shape (..., m, n)
        Natural frequencies at each pose, ascending, rad/s.
    """
    n = M.shape[-1]
    s = np.empty(M.shape[:-1])  # broadcast_to costs more than this copy for small n
    s[...] = (1.0 / np.sqrt(K))[..., None, :]
    return eig_scaled(M.reshape(-1, n, n), s.reshape(-1, n)).reshape(M.shape[:-1])


def fast_unit_frequencies(problem: FitProblem, lengths_m: np.ndarray):
    """Return unit-factor springs ``K0`` (N m/rad) and frequencies over the poses (rad/s).

    As ``problem.unit_frequencies`` but through :func:`chain_mass_matrices` (the fit's inner loop);
    shapes (n,), (m, N) for one design, (B, n), (B, m, N) for a stack.
    """
    M, K0 = chain_mass_matrices(problem, lengths_m)
    return K0, chain_frequencies(M, K0)[..., : problem.n_freq]


def evaluate(
    problem: FitProblem,
    lengths_m: np.ndarray,
    factors: np.ndarray,
    deflection: bool = True,
) -> Evaluation:
    """Evaluate a design: frequencies over the poses and (when asked) the tip under the load.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (n+1,)
    factors : ndarray
        SCFs k_i (m,) for ``paper``, joint factors s_j (n,) for ``joint``.
    deflection : bool
        Also solve the static deflection (needs a target with a tip position). For ``paper``
        one static solve per pose's stiffness (Eq. 18 averages over them).

    Raises
    ------
    SolveError
        When a static solve does not converge.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    factors = np.asarray(factors, dtype=float).reshape(-1)
    if factors.size != problem.n_factors:
        raise BeamInputError(f"factors has {factors.size} entries: {problem.n_factors} needed")
    P = problem.parametrisation
    model, K0 = P.build(problem, lengths)
    omega = P.frequencies(problem, model, K0, factors)
    err = eigen_errors(omega, problem.target.omega_truth_rad_s, problem.squared,
                       problem.eigen_norm)
    K = P.pose_springs(K0, factors, problem.n_poses)
    tips = pos = disp = extra = None
    if deflection and problem.target.has_static:
        rows = P.static_rows(K)
        cases = problem.target.load_cases
        all_tips = np.array([static_tips(model, c.tip_force_N, rows) for c in cases])
        pos = np.mean([tip_position_errors(t, c.tip_position_m)
                       for t, c in zip(all_tips, cases, strict=True)], axis=0)
        disp = np.mean([tip_displacement_errors(t, c.tip_position_m, c.tip_displacement_m)
                        for t, c in zip(all_tips, cases, strict=True)], axis=0)
        tips = all_tips[0]
        extra = all_tips[1:] if len(cases) > 1 else None
    return Evaluation(lengths, factors, K, omega, err, tips, pos, disp, extra)


@dataclass(frozen=True, eq=False)
class BatchLosses:
    """Per-pose errors of a stack of designs (rows), as fractions.

    NaN where a design cannot be solved.

    Attributes
    ----------
    eigen_errors : ndarray, shape (B, m)
        Relative eigen error of each pose (Eq. 16, or the relative norm: the problem's).
    position_errors, displacement_errors : ndarray, shape (B, m'), or None
        Tip error under the load case for each distinct stiffness (m' = m for ``paper``, 1 for
        ``joint``), normalised by the truth tip position (Eq. 19) and by the truth tip
        displacement; None when the statics were not solved.
    """

    eigen_errors: np.ndarray
    position_errors: np.ndarray | None = None
    displacement_errors: np.ndarray | None = None

    @property
    def eigen_pct(self) -> np.ndarray:
        """Eigen loss of each design (equation 17), %."""
        return 100.0 * self.eigen_errors.mean(axis=1)

    @property
    def position_pct(self) -> np.ndarray:
        """Deflection loss of each design (equations 18-19), %."""
        return 100.0 * self.position_errors.mean(axis=1)

    @property
    def displacement_pct(self) -> np.ndarray:
        """Tip-displacement loss of each design, %."""
        return 100.0 * self.displacement_errors.mean(axis=1)

    def tip_errors(self, norm: DeflectionNorm | str = DeflectionNorm.POSITION
                   ) -> np.ndarray | None:
        """Return the tip errors in the normalisation ``norm``, as fractions.

        ``norm`` is one of ``objectives.DEFLECTION_NORMS``.
        """
        if check_deflection_norm(norm) is DeflectionNorm.POSITION:
            return self.position_errors
        return self.displacement_errors

def batch_losses(problem: FitProblem, lengths_m: np.ndarray, factors: np.ndarray,
                 deflection: bool = True) -> BatchLosses:
    """Compute the losses of :func:`evaluate` for many designs at once, without Pinocchio.

    The population of a Pareto generation or a finite-difference stencil is evaluated in one
    pass: closed-form mass matrices (:func:`chain_mass_matrices`), one stacked eigensolve, and
    every static solve (one per design and pose for ``paper``, one per design for ``joint``) in
    one vectorised Newton (``statics.static_deflection_planar_batch``). Tests check it against
    :func:`evaluate`, which uses the Pinocchio model.

    Parameters
    ----------
    problem : FitProblem
    lengths_m : ndarray, shape (B, n+1)
        Valid link lengths (on the bounded simplex), m.
    factors : ndarray, shape (B, m) (paper) or (B, n) (joint)
        Stiffness factors.
    deflection : bool
        Also solve the statics (needs a target with a tip position).
    """
    L = np.atleast_2d(np.asarray(lengths_m, dtype=float))
    f = np.atleast_2d(np.asarray(factors, dtype=float))
    B, m, n = L.shape[0], problem.n_poses, problem.n_joints
    static = deflection and problem.target.has_static
    P = problem.parametrisation
    reps = P.n_static_rows(m)  # static solves per design
    try:
        M, K0 = chain_mass_matrices(problem, L)
        K = P.pose_springs(K0, f, m)
        omega = eig_scaled(M.reshape(-1, n, n), 1.0 / np.sqrt(K.reshape(-1, n)))
    except (SolveError, BeamInputError, np.linalg.LinAlgError):
        if B == 1:
            nan = np.full((1, reps), np.nan)
            return BatchLosses(np.full((1, m), np.nan), nan if static else None,
                               nan.copy() if static else None)
        parts = [batch_losses(problem, L[i:i + 1], f[i:i + 1], deflection) for i in range(B)]
        def cat(name: str) -> np.ndarray | None:
            if getattr(parts[0], name) is None:
                return None
            return np.concatenate([getattr(p, name) for p in parts])

        return BatchLosses(cat("eigen_errors"), cat("position_errors"),
                           cat("displacement_errors"))
    eig = eigen_errors(omega[:, : problem.n_freq], problem.target.omega_truth_rad_s,
                       problem.squared, problem.eigen_norm).reshape(B, m)
    if not static:
        return BatchLosses(eig)
    rows = P.static_rows(K)
    Lr = np.repeat(L, reps, axis=0)
    pos = np.zeros((B, reps))
    disp = np.zeros((B, reps))
    cases = problem.target.load_cases
    for c in cases:
        q, ok = static_deflection_planar_batch(Lr, rows, c.tip_force_N)
        tips = planar_tips(Lr, np.where(ok[:, None], q, 0.0))
        e_pos = tip_position_errors(tips, c.tip_position_m)
        e_disp = tip_displacement_errors(tips, c.tip_position_m, c.tip_displacement_m)
        e_pos[~ok] = np.nan
        e_disp[~ok] = np.nan
        pos += e_pos.reshape(B, reps)
        disp += e_disp.reshape(B, reps)
    return BatchLosses(eig, pos / len(cases), disp / len(cases))

