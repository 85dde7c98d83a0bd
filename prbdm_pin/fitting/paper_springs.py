"""The ``paper`` parametrisation (equation 14): one stiffness correction factor per sweep pose.

Pose i uses the springs ``K_j(i) = k_i sqrt(E I_{j+1} / m_{j+1})``, one SCF k_i per pose; the
design vector is [gamma, k] (Eq. 22) and the frequencies are compared over the pose sweep of
Eqs. 10-11. Scaling every spring of a pose by k_i scales its omega^2 by k_i (the mass matrix does
not depend on the springs), so one eigensolve at unit SCF gives a design's frequencies at every
k, and the eigen fit projects the SCFs out (``paper.PaperEigenResiduals``). The interface is
:class:`prbdm_pin.fitting.parametrisation.Parametrisation`'s, whose docstrings say what each
method returns.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, ClassVar

import numpy as np

from ..chain.stiffness import paper_stiffness, paper_unit_stiffness, pose_sweep
from ..options.choices import Objective, StiffnessKind
from .local import polish_paper_eigen, solve_paper_start
from .objectives import best_scale, scf_deviation_pct, scf_mean
from .paper import PaperEigenResiduals
from .problem import FitProblem, unit_frequencies, unit_from_lengths
from .result import ExportedSprings
from .spec import FitSpec, StartResult

__all__ = ["PaperSprings"]


class PaperSprings:
    """One SCF per pose on ``sqrt(E I / m)`` of each joint's outboard link (equation 14)."""

    name: ClassVar[str] = StiffnessKind.PAPER.value
    pose_independent: ClassVar[bool] = False
    export_advice: ClassVar[str] = (
        "; Eq. 14's springs, one SCF times sqrt(E I_j / m_j), cannot follow every planform: "
        "joint springs (stiffness='joint') fit each joint")

    def poses(self, joints: int, options: Any) -> np.ndarray:
        """Return the pose sweep of equations 10-11, rad, shape (m, n)."""
        return np.asarray(pose_sweep(joints, xi=options.xi_rad, eps=options.eps_rad),
                          dtype=float)

    def n_factors(self, n_poses: int, n_joints: int) -> int:
        """Return m: one SCF per pose."""
        return n_poses

    def chain_unit_springs(self, beam, lengths_m, area_moment_m4, mass_kg) -> np.ndarray:
        """Return equation 14 at unit SCF from the links' sections, N m/rad, shape (..., n)."""
        return paper_unit_stiffness(beam.material.E_Pa, area_moment_m4, mass_kg)

    def build(self, problem: FitProblem, lengths_m: np.ndarray):
        """Return the model with equation 14's springs at unit SCF, and those springs (N m/rad)."""
        from ..model.prbdm_model import build_model  # Pinocchio loads with the first model

        lengths = np.asarray(lengths_m, dtype=float)
        # the springs need the model's link sections: build it, then set them
        model = build_model(problem.beam, lengths, np.ones(problem.n_joints),
                            min_fraction=problem.min_fraction)
        K0 = np.asarray(paper_stiffness(model.sections, problem.beam.material.E_Pa, 1.0),
                        dtype=float)
        return model.with_stiffness(K0), K0

    def frequencies(self, problem: FitProblem, model, K0: np.ndarray,
                    factors: np.ndarray) -> np.ndarray:
        """Return the frequencies over the sweep, rad/s, (m, N): unit-SCF ones times sqrt(k_i)."""
        W = np.asarray(model.natural_frequencies_batch(problem.poses_rad, stiffness=K0))
        return W[:, : problem.n_freq] * np.sqrt(factors)[:, None]

    def pose_springs(self, K0: np.ndarray, factors: np.ndarray, n_poses: int) -> np.ndarray:
        """Return ``k_i K0`` for every pose i, N m/rad, shape (..., m, n)."""
        f = np.asarray(factors, dtype=float)
        return f[..., :, None] * K0[..., None, :]

    def n_static_rows(self, n_poses: int) -> int:
        """Return m: every pose's springs are solved (equation 18 averages over them)."""
        return n_poses

    def static_rows(self, springs: np.ndarray) -> np.ndarray:
        """Return every pose's springs as rows, N m/rad, shape (B m, n)."""
        return springs.reshape(-1, springs.shape[-1])

    def export(self, problem: FitProblem, ev, K0: np.ndarray) -> ExportedSprings:
        """Return the springs fitted at the sweep's first pose, the one nearest straight.

        The frequencies move by O(q^2) from there to q = 0, the straight pose where users
        linearise and simulate; the whole per-pose table stays in the result.
        """
        pose = problem.poses_rad[0]
        return ExportedSprings(
            springs_Nm_per_rad=ev.stiffness_Nm_per_rad[0], pose_rad=pose,
            scf_mean=scf_mean(ev.factors),  # a diagnostic (Eq. 25): no pose was fitted with it
            scf_deviation_pct=scf_deviation_pct(ev.factors),
            described=(f"paper: the springs fitted at sweep pose 0 (every joint at "
                       f"{pose[0]:.6g} rad, the pose nearest straight; SCF "
                       f"{ev.factors[0]:.6g})"))

    def fit_notes(self, problem: FitProblem, objective: Objective, eigen_loss_pct: float,
                  starts_run: int) -> list[str]:
        """Return no notes: a ``paper`` fit has no loss it should reach."""
        return []

    def start_tasks(self, spec: FitSpec, tasks: list) -> list:
        """Return the tasks, their SCFs scaled by each start's projected eigen optimum.

        With a deflection term the SCF scale is beam-specific: the random factors are taken
        around the closed-form SCFs of the start's lengths. The eigen fit projects them out.
        """
        if not spec.objective.has_deflection_term:
            return tasks
        p = spec.problem
        P = PaperEigenResiduals(FitSpec(p, Objective.EIGEN, spec.max_nfev))
        return [(i, L, F * P.factors(unit_from_lengths(L, p.length_m, p.min_fraction)))
                for i, L, F in tasks]

    def explores(self, spec: FitSpec, options: Any, n_tasks: int) -> bool:
        """Return False: every start runs to convergence."""
        return False

    def polish(self, spec: FitSpec, runs: list[StartResult], order: list[int],
               options: Any) -> tuple[StartResult, list[StartResult]]:
        """Polish the best ``options.polish`` distinct eigen optima on the paper's loss.

        The projected least squares weighs the poses by their squared errors; the polish
        (``local.polish_paper_eigen``) minimises the mean of the errors (Eq. 17) itself.
        """
        best = runs[order[0]]
        if spec.objective.has_deflection_term or not options.polish > 0:
            return best, runs
        # starts that ended in the same local optimum polish to the same design: polish
        # only distinct ones among the best ``polish``
        chosen: list[int] = []
        for i in order[:options.polish]:
            if all(np.max(np.abs(runs[i].lengths_m - runs[j].lengths_m))
                   > 1e-3 * spec.problem.length_m for j in chosen):
                chosen.append(i)
        polished = [polish_paper_eigen(spec, runs[i]) for i in chosen]
        best = min(polished, key=lambda r: (r.loss_pct, r.index))
        runs = [*runs]
        for q, i in zip(polished, chosen, strict=True):
            runs[i] = replace(runs[i], nfev=q.nfev)  # count the polishing evaluations too
        return best, runs

    def solve_start(self, spec: FitSpec, index: int, lengths0: np.ndarray,
                    factors0: np.ndarray) -> StartResult:
        """Run ``local.solve_paper_start``."""
        return solve_paper_start(spec, index, lengths0, factors0)

    def default_log10_bounds(self, problem: FitProblem) -> tuple[float, float]:
        """Return 1.5 decades either side of the projected eigen SCF at equal link lengths."""
        n1 = problem.n_joints + 1
        _, _, W = unit_frequencies(problem, np.full(n1, problem.length_m / n1))
        k_ref = float(np.mean(best_scale(W, problem.target.omega_truth_rad_s, problem.squared,
                                         problem.eigen_norm)))
        return (math.log10(k_ref) - 1.5, math.log10(k_ref) + 1.5)

    def start_factors(self, beam, lengths_m, springs, factors, min_fraction) -> np.ndarray:
        """Return the previous fit's SCFs (``fit`` checks there is one per pose)."""
        return factors
