"""The multistart fit: start points drawn up front, solved in order, the best one chosen.

The starts run in processes when ``workers > 1``; the best is chosen by (loss, start index), so
the same seed gives the same result whatever the number of workers.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from ..chain.layout import sample_lengths
from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.choices import UniqueRule
from ..options.objects import FitOptions
from ..options.validate import check_type
from ..workers import pool_scope
from .checks import check_fit_inputs
from .explore import run_explored
from .load_cases import with_extra_loads
from .local import solve_start
from .pool import fit_pool
from .problem import FitProblem, make_problem
from .progress import start_bar
from .result import result_from_design
from .results import FitResult
from .spec import FitSpec, StartResult
from .target import FitTarget

__all__ = ["fit", "run_starts", "draw_starts", "resolve_options"]


def run_starts(spec: FitSpec, tasks: list, workers: int = 1, progress: bool = True,
               loss_tol: float | None = None) -> list[StartResult]:
    """Solve the starts in order, in ``workers`` processes.

    Parameters
    ----------
    spec : FitSpec
        The fit problem, objective, deflection norm and evaluation cap.
    tasks : list of tuple
        The starts (index, lengths m, factors), as from :func:`draw_starts`.
    workers : int
        Processes to spread the starts over (1: in this process).
    progress : bool
        Show a tqdm progress bar.
    loss_tol : float, optional
        Stop after the first start (in start order) whose loss is <= ``loss_tol`` (%).

    Returns
    -------
    list of StartResult
        The results of the starts run, in start order.
    """
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


def _check_fit_args(options: FitOptions, workers, target: FitTarget) -> None:
    objective = options.objective
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise BeamInputError(f"workers = {workers!r}: must be an integer >= 1")
    if objective.has_deflection_term and not target.has_static:
        raise BeamInputError(
            f"objective = {objective.value!r}: the target has no truth tip position/displacement"
        )
    if objective.has_deflection_term and not np.any(target.tip_force_N):
        raise BeamInputError(f"tip_force = [0, 0, 0] N: a {objective.value} fit needs a tip "
                             "load (the beam's tip_force)")


def resolve_options(options: Any, cls: type, changes: dict[str, Any]):
    """Return ``options`` (default ``cls()``) with keyword ``changes`` applied, validated."""
    if options is None:
        options = cls()
    elif not isinstance(options, cls):
        check_type("options", options, cls)
    return options.replace(**changes) if changes else options


def draw_starts(problem: FitProblem, starts: int, seed: int) -> list:
    """Draw ``starts`` start tasks from ``default_rng(seed)``.

    Parameters
    ----------
    problem : FitProblem
        The fit problem (beam length, joints, minimum link fraction, number of factors).
    starts : int
        How many starts to draw.
    seed : int
        Seed of ``numpy.random.default_rng``.

    Returns
    -------
    list of tuple
        (index, lengths m, factors): lengths uniform on the bounded simplex (Eq. 23), factors
        (dimensionless) log-uniform within a factor 2 of 1.
    """
    rng = np.random.default_rng(seed)
    L0 = sample_lengths(rng, problem.length_m, problem.n_joints + 1, starts,
                        min_fraction=problem.min_fraction)
    # random factors: log-uniform within a factor 2 either side of the start's reference
    F0 = np.exp(rng.uniform(-math.log(2.0), math.log(2.0), (starts, problem.n_factors)))
    return [(i, L0[i], F0[i]) for i in range(starts)]


def _warm_task(problem: FitProblem, o: FitOptions) -> tuple:
    L, F = np.array(o.start_lengths_m), np.array(o.start_factors)
    if L.size != problem.n_joints + 1 or F.size != problem.n_factors:
        raise BeamInputError(f"start_lengths_m, start_factors: {L.size} lengths and {F.size} "
                             f"factors: this fit needs {problem.n_joints + 1} and "
                             f"{problem.n_factors}")
    return (0, L * (problem.length_m / L.sum()), F)


def _fit_unique(problem: FitProblem, o: FitOptions, t0: float) -> FitResult:
    from .unique import check_unique_problem, solve_unique

    check_unique_problem(problem, o.objective)
    best, _ = solve_unique(problem)
    return result_from_design(
        problem, best.lengths_m, best.factors, objective=o.objective, seed=o.seed,
        starts=1, starts_run=1, nfev=best.nfev, start_losses_pct=np.array([best.loss_pct]),
        wall_time_s=time.perf_counter() - t0, success=True, message=best.message)


def _fit_spatial(beam, target, joints, o: FitOptions, workers, progress, start, extra_loads):
    """Run :func:`~prbdm_pin.fitting.spatial_fit.fit_spatial`; refuse what it does not take."""
    from .spatial_fit import fit_spatial

    for name, bad in (("start", start is not None), ("extra_loads", bool(extra_loads)),
                      ("workers", workers != 1)):
        if bad:
            raise BeamInputError(f"{name}: not available for a spatial fit (axes = "
                                 f"{o.axes.value!r}), which runs its starts in one process "
                                 "on the frequencies alone")
    return fit_spatial(beam, target, joints, o, progress=progress)


def fit(
    beam: Beam,
    target: FitTarget,
    joints: int,
    options: FitOptions | None = None,
    *,
    workers: int = 1,
    progress: bool = True,
    start: Any = None,
    extra_loads: Any = (),
    **changes: Any,
) -> FitResult:
    """Fit an nR PRBDM to a target by a multistart of a local solver.

    Parameters
    ----------
    beam : Beam
        The planform, thickness, material and tip load.
    target : FitTarget
        Truth frequencies (rad/s) and, for deflection terms, the truth tip under the load.
    joints : int
        n, the number of revolute joints.
    options : FitOptions, optional
        What determines the fit (objective, parametrisation, starts, seed, sweep, norms,
        bounds); the result records it whole (``FitResult.options``, fit.json).
    workers : int
        Processes to spread the starts over (BLAS pinned to one thread in each); the result
        does not depend on it.
    progress : bool
        Show a tqdm progress bar.
    start : FitResult or (lengths m, springs N m/rad), optional
        Warm start: the local solver runs from there only (``fitting/warm.py``); recorded in
        the result's options (``start_lengths_m``, ``start_factors``).
    extra_loads : sequence of float or LoadCase
        Further load cases for the deflection objective (the command line's
        ``--extra-loads``): multiples of the beam's tip force, whose truth tips come from the
        target's large-deflection model (:mod:`prbdm_pin.load_cases`), or
        :class:`~prbdm_pin.LoadCase` objects; added to ``target.extra_loads``.
    **changes
        Options by name, applied to ``options`` (``fit(beam, target, 3, objective="combined")``).

    Returns
    -------
    FitResult
        For ``paper`` its exported springs (``stiffness_Nm_per_rad``) are those of the sweep's
        first pose, the one nearest straight (``export_pose_rad``); the whole per-pose table is
        ``stiffness_per_pose_Nm_per_rad`` (``FitResult.stiffness_schedule``).

    Raises
    ------
    BeamInputError
        On invalid options, workers or warm start, or a deflection objective without a truth
        tip or a tip load.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> rho_A = beam.material.rho_kg_m3 * 0.05 * 0.01  # kg/m
    >>> w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, L = 1 m
    >>> target = pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> result.omega_model_rad_s.round(2)  # rad/s, the targets above
    array([[ 51.87, 325.05]])
    >>> result.stiffness_Nm_per_rad.shape
    (2,)
    """
    t0 = time.perf_counter()
    check_fit_inputs(beam, target, joints, workers)
    o = resolve_options(options, FitOptions, changes)
    if target.gravity_m_s2 is not None:  # the chain evaluated in the truth's gravity
        from .gravity_fit import fit_in_gravity

        return fit_in_gravity(beam, target, joints, o, workers=workers, progress=progress,
                              start=start, extra_loads=extra_loads)
    if o.axes.spatial:
        return _fit_spatial(beam, target, joints, o, workers, progress, start, extra_loads)
    target = with_extra_loads(target, beam, extra_loads)
    if start is not None:
        from .warm import start_changes

        o = o.replace(**start_changes(start, beam, joints, o))
    problem = make_problem(beam, target, joints, o)
    _check_fit_args(o, workers, target)
    spec = FitSpec(problem, o.objective, o.max_nfev)
    if o.unique is not UniqueRule.NONE:
        return _fit_unique(problem, o, t0)
    P = problem.parametrisation
    tasks = draw_starts(problem, o.starts, o.seed)
    if o.start_lengths_m is not None:
        tasks = [_warm_task(problem, o)]
    else:
        tasks = P.start_tasks(spec, tasks)
    if P.explores(spec, o, len(tasks)):
        runs = run_explored(spec, tasks, o.explore_nfev, o.refine_starts, workers, progress,
                            o.loss_tol_pct)
    else:
        runs = run_starts(spec, tasks, workers, progress, o.loss_tol_pct)
    order = sorted(range(len(runs)), key=lambda i: (runs[i].loss_pct, i))
    best, runs = P.polish(spec, runs, order, o)
    nfev = sum(r.nfev for r in runs)
    return result_from_design(
        problem, best.lengths_m, best.factors, objective=o.objective, seed=o.seed,
        starts=o.starts, starts_run=len(runs), nfev=nfev,
        start_losses_pct=np.array([r.loss_pct for r in runs]),
        wall_time_s=time.perf_counter() - t0, success=bool(best.success),
        message=f"best of {len(runs)} starts (start {best.index}): {best.message}",
    )
