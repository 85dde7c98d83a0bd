"""The multistart fit: start points drawn up front, solved in order (in processes when
``workers > 1``), the best chosen by (loss, start index), so the same seed gives the same result
whatever the number of workers."""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from ..errors import BeamInputError
from ..geometry import Beam
from ..layout import sample_lengths
from ..objectives import DEFAULT_EIGEN_NORM, check_deflection_norm, check_eigen_norm
from ..problem import FitProblem, make_problem, unit_from_lengths
from ..results import FitResult
from ..target import FitTarget
from ..workers import pool_scope
from .local import polish_paper_eigen, solve_start
from .paper import PaperEigenResiduals
from .pool import fit_pool
from .progress import start_bar
from .result import result_from_design
from .spec import OBJECTIVES, FitSpec, StartResult

__all__ = ["fit", "run_starts", "draw_starts"]




def run_starts(spec: FitSpec, tasks: list, workers: int = 1, progress: bool = True,
               loss_tol: float | None = None) -> list[StartResult]:
    """Solve the starts in order, in ``workers`` processes; stop after the first (in start
    order) whose loss is <= ``loss_tol`` (%). Returns the results of the starts run, in order."""
    out: list[StartResult] = []
    bar = start_bar(len(tasks), progress)
    try:
        if workers <= 1:
            for t in tasks:
                res = solve_start(spec, *t)
                out.append(res)
                bar.update()
                if loss_tol is not None and res.loss_pct <= loss_tol:
                    break
            return out
        with pool_scope(fit_pool(workers)) as ex:
            # the spec travels with each start: a worker must not unpickle arrays before it
            # has pinned BLAS (workers.pin_blas), and a spec is small beside a start's solve
            futures = [ex.submit(solve_start, spec, *t) for t in tasks]
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


def _check_fit_args(objective, starts, workers, target: FitTarget) -> None:
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


def draw_starts(problem: FitProblem, starts: int, seed: int) -> list:
    """``starts`` tasks (index, lengths m, factors) from ``default_rng(seed)``: lengths uniform
    on the bounded simplex (Eq. 23), factors log-uniform within a factor 2 of 1."""
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
    check_deflection_norm(deflection_norm)
    problem = make_problem(beam, target, joints, frequencies, stiffness, xi, eps, squared,
                           joint_sweep, min_fraction, check_eigen_norm(eigen_norm))
    _check_fit_args(objective, starts, workers, target)
    spec = FitSpec(problem, objective, deflection_norm, int(max_nfev))
    tasks = draw_starts(problem, int(starts), int(seed))
    if stiffness == "paper" and objective != "eigen":
        # random SCFs around each start's projected eigen optimum (the SCF scale is beam-specific)
        P = PaperEigenResiduals(FitSpec(problem, "eigen", deflection_norm, int(max_nfev)))
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


