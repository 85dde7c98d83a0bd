"""The ``joint`` parametrisation: one pose-independent factor per joint on its segment springs.

Joint j's spring is ``K_j = s_j E / integral(dx / I)`` over its segment
(``stiffness.finite_segment_stiffness``); the design vector is [gamma, s] and the frequencies are
compared at the straight pose unless a sweep is asked for (``joint_sweep``). One spring per
joint, valid in every pose: the model a simulation exports as it is. The interface is
:class:`prbdm_pin.fitting.parametrisation.Parametrisation`'s, whose docstrings say what each
method returns.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from ..chain.stiffness import (
    finite_segment_stiffness,
    finite_segment_stiffness_unchecked,
    pose_sweep,
)
from ..errors import BeamInputError
from ..options.choices import Objective, StiffnessKind
from .local import solve_joint_start
from .problem import FitProblem
from .result import EXACT_MATCH_PCT, ExportedSprings
from .spec import FitSpec, StartResult

__all__ = ["JointSprings"]


class JointSprings:
    """One factor per joint on the finite-segment springs, the same in every pose."""

    name: ClassVar[str] = StiffnessKind.JOINT.value
    pose_independent: ClassVar[bool] = True
    export_advice: ClassVar[str] = ""

    def poses(self, joints: int, options: Any) -> np.ndarray:
        """Return the straight pose (1, n), or the sweep of equations 10-11 (``joint_sweep``)."""
        if options.joint_sweep:
            return np.asarray(pose_sweep(joints, xi=options.xi_rad, eps=options.eps_rad),
                              dtype=float)
        return np.zeros((1, joints))

    def n_factors(self, n_poses: int, n_joints: int) -> int:
        """Return n: one factor per joint."""
        return n_joints

    def chain_unit_springs(self, beam, lengths_m, area_moment_m4, mass_kg) -> np.ndarray:
        """Return the finite-segment springs of valid lengths, N m/rad, shape (..., n)."""
        return finite_segment_stiffness_unchecked(beam, lengths_m)

    def build(self, problem: FitProblem, lengths_m: np.ndarray):
        """Return the model with the finite-segment springs, and those springs (N m/rad)."""
        from ..model.prbdm_model import build_model  # Pinocchio loads with the first model

        lengths = np.asarray(lengths_m, dtype=float)
        f = problem.min_fraction  # the fit's own bound (below 0.02 for long chains)
        K0 = np.asarray(finite_segment_stiffness(problem.beam, lengths, f), dtype=float)
        return build_model(problem.beam, lengths, K0, min_fraction=f), K0

    def frequencies(self, problem: FitProblem, model, K0: np.ndarray,
                    factors: np.ndarray) -> np.ndarray:
        """Return the frequencies of the springs ``s K0`` over the poses, rad/s, (m, N)."""
        # the joint factors change the spring ratios: a new eigensolve per pose
        return np.asarray(model.natural_frequencies_batch(
            problem.poses_rad, stiffness=factors * K0))[:, : problem.n_freq]

    def pose_springs(self, K0: np.ndarray, factors: np.ndarray, n_poses: int) -> np.ndarray:
        """Return ``s K0`` repeated for every pose, N m/rad, shape (..., m, n)."""
        k = np.asarray(factors, dtype=float) * K0
        return np.broadcast_to(k[..., None, :], (*k.shape[:-1], n_poses, k.shape[-1])).copy()

    def n_static_rows(self, n_poses: int) -> int:
        """Return 1: the springs are the same in every pose."""
        return 1

    def static_rows(self, springs: np.ndarray) -> np.ndarray:
        """Return the one spring set of each design, N m/rad, shape (B, n) (one design: (n,))."""
        return springs[..., 0, :]

    def export(self, problem: FitProblem, ev, K0: np.ndarray) -> ExportedSprings:
        """Return the fitted springs ``s K0`` and the straight pose."""
        return ExportedSprings(
            springs_Nm_per_rad=ev.factors * K0, pose_rad=np.zeros(problem.n_joints),
            scf_mean=float(np.mean(ev.factors)), scf_deviation_pct=np.zeros(problem.n_poses),
            described="joint: pose-independent springs, fitted " + (
                "over the pose sweep" if problem.n_poses > 1 else "at the straight pose"))

    def fit_notes(self, problem: FitProblem, objective: Objective, eigen_loss_pct: float,
                  starts_run: int) -> list[str]:
        """Return a note when an eigen fit of n frequencies at the straight pose missed them.

        Such a fit matches them exactly when they are within a chain's reach (its 2n
        parameters against n frequencies).
        """
        if (not objective.has_deflection_term and problem.n_poses == 1
                and problem.n_freq == problem.n_joints and eigen_loss_pct > EXACT_MATCH_PCT):
            return [f"the {problem.n_freq} truth frequencies were not matched (eigen loss "
                    f"{eigen_loss_pct:.3g} % after {starts_run} starts): a joint model "
                    "matches n frequencies exactly when they are within a chain's reach"]
        return []

    def start_tasks(self, spec: FitSpec, tasks: list) -> list:
        """Return the tasks as drawn (factors around 1 on the physical springs)."""
        return tasks

    def explores(self, spec: FitSpec, options: Any, n_tasks: int) -> bool:
        """Whether to explore every start and refine the best ``options.refine_starts``.

        With a deflection term each start crawls along a curved valley; the starts that reach
        the best optimum are among the best few after a short exploration (``explore.py``).
        """
        return (spec.objective.has_deflection_term and options.refine_starts > 0
                and n_tasks > options.refine_starts)

    def polish(self, spec: FitSpec, runs: list[StartResult], order: list[int],
               options: Any) -> tuple[StartResult, list[StartResult]]:
        """Return the best start as it is (the solver polishes a sweep's optimum itself)."""
        return runs[order[0]], runs

    def solve_start(self, spec: FitSpec, index: int, lengths0: np.ndarray,
                    factors0: np.ndarray) -> StartResult:
        """Run ``local.solve_joint_start``."""
        return solve_joint_start(spec, index, lengths0, factors0)

    def default_log10_bounds(self, problem: FitProblem) -> tuple[float, float]:
        """Return (-1, 1): a decade either side of the physical springs."""
        return (-1.0, 1.0)

    def start_factors(self, beam, lengths_m, springs, factors, min_fraction) -> np.ndarray:
        """Return the previous springs (N m/rad) as factors on this beam's finite-segment ones.

        Raises BeamInputError unless there is one finite spring > 0 per joint.
        """
        n = np.asarray(lengths_m).size - 1
        if springs.size != n or not np.all(np.isfinite(springs)) or np.any(springs <= 0):
            raise BeamInputError(f"start springs = {springs.tolist()}: need {n} finite "
                                 "values > 0 (N m/rad)")
        return springs / finite_segment_stiffness(beam, lengths_m, min_fraction)
