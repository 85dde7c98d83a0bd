"""Single-objective multistart fits and the NSGA-II Pareto fit.

Modules: ``problem`` (the fit problem: beam, target, options and parametrisation),
``parametrisation`` with ``paper_springs`` and ``joint_springs`` (the two spring
parametrisations as strategy objects: what the fit asks of them instead of testing a name),
``spec`` (what a start is given and returns), ``joint`` and ``paper`` (the two
parametrisations' residuals and losses), ``joint_jacobian`` (the ``joint`` residuals' analytic
Jacobian), ``local`` (the local solver of a start), ``multistart``
(:func:`fit`), ``result`` (a design evaluated in full as a FitResult), ``pareto_problem`` (the
pymoo problem and repair), ``pareto`` (:func:`fit_pareto`), ``pool`` and ``progress``;
``warm`` (a previous fit as the one start), ``unique`` (the ``unique="nearest"`` rule: one
model per design, smooth in it), ``sweep`` (:func:`fit_sweep` along a design path),
``derivative`` (:func:`fit_derivative`, dtheta/dp by the implicit-function theorem) and
``design_gradient`` (:func:`fit_design_gradient`: the same for every design variable at once,
with the truth's analytic frequency gradient).

Local solvers (chosen for accuracy per model evaluation; see ``scripts/bench_fit.py``):

- ``joint`` parametrisation: ``scipy.optimize.least_squares`` (trust-region reflective) on the
  residual vector (frequency residuals over the poses, scaled by ``1/sqrt(m)``, and/or the tip
  position residual), over x = [u, ln s] with u in the box [0, 1]^n mapped onto the bounded
  length simplex by stick-breaking (``problem.lengths_from_unit``). With the straight pose
  (the default) the sum of squares is exactly the squared loss, and n frequencies are matched to
  round-off. With a sweep (m > 1) the least-squares optimum is polished on the true loss
  (mean of per-pose norms) by SLSQP. Its Jacobian is analytic (``joint_jacobian``: mode
  derivatives and the implicit derivative of each load case's equilibrium, through the exact
  section integrals and the finite-segment springs, ``chain_gradient``), computed from what the
  residuals at the same x already hold; it counts as one model evaluation.
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
  pose's static solve in one vectorised Newton (``evaluate.batch_losses``).

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
``evaluate.chain_mass_matrices`` (exact link sections and the closed-form mass matrix of the
planar chain, checked against Pinocchio's CRBA in the tests) and the vectorised static solver
``statics.static_deflection_planar_batch``; each finite-difference stencil of the ``paper``
fits, and each NSGA-II generation, is evaluated as one stacked batch (scipy's ``workers`` map,
``pareto_problem.pareto_objectives_batch``). The chosen design
is evaluated again through the exported ``PrbdmModel`` (``result.result_from_design``): its
frequencies from Pinocchio's mass matrix, its static equilibrium from the model's own planar
Newton solve and its tip from Pinocchio's kinematics, so every number of a FitResult is the
product's (a Pareto front's ``F_pct`` are the batch's).

Start points are uniform on the bounded simplex (``layout.sample_lengths``, Eq. 23) plus random
factors, all drawn up front from ``numpy.random.default_rng(seed)``; starts are solved in order
(in processes when ``workers > 1``) and the best is chosen by (loss, start index), so the same
seed gives the same result whatever the number of workers. ``loss_tol`` stops at the first start
(in start order) that reaches it.
"""


from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "fit": "multistart",
    "run_starts": "multistart",
    "draw_starts": "multistart",
    "fit_pareto": "pareto",
    "fit_sweep": "sweep",
    "SweepResult": "sweep",
    "check_path": "sweep",
    "start_changes": "warm",
    "solve_unique": "unique",
    "rule_lengths": "unique",
    "fit_derivative": "multistart_derivatives",
    "FitDerivative": "multistart_derivatives",
    "fit_design_gradient": "design_derivatives",
    "FitDesignGradient": "design_derivatives",
    "FitSpec": "spec",
    "StartResult": "spec",
    "OBJECTIVES": "spec",
    "solve_start": "local",
    "polish_paper_eigen": "local",
    "result_from_design": "result",
    "EXPORT_WARN_PCT": "result",
    "EXACT_MATCH_PCT": "result",
    "Parametrisation": "parametrisation",
    "PaperSprings": "paper_springs",
    "JointSprings": "joint_springs",
    "JointResiduals": "joint",
    "PaperEigenResiduals": "paper",
    "PaperScalarLoss": "paper",
    "LengthRepair": "pareto_problem",
    "ParetoProblem": "pareto_problem",
    "pareto_objectives": "pareto_problem",
    "pareto_objectives_batch": "pareto_problem",
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> Any:
    # imported on first use: pymoo and Pinocchio load only for the fits that need them
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


def __dir__() -> list[str]:
    return sorted(__all__)
