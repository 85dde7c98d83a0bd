"""The NSGA-II Pareto fit over (eigen loss, deflection loss).

The initial population is seeded with single-objective fits, the generations are evaluated in
one batch (or over a process pool), and the knee of Eq. 27 is polished by the single-objective
local solver.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from ..chain.layout import sample_lengths
from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.choices import Objective
from ..options.objects import FitOptions, ParetoOptions
from ..workers import stop_pool
from .checks import check_fit_inputs
from .load_cases import with_extra_loads
from .local import solve_start
from .multistart import fit, resolve_options
from .objectives import knee_index
from .pareto_problem import (
    LengthRepair,
    ParetoProblem,
    pareto_objectives,
    pareto_objectives_batch,
)
from .pareto_result import ParetoResult
from .pool import fit_pool
from .problem import FitProblem, make_problem
from .progress import PymooBar
from .result import result_from_design
from .spec import FitSpec
from .target import FitTarget

__all__ = ["fit_pareto", "PoolRows"]

INTERPOLATED_SEEDS = 5  # per segment between two anchors of the initial population


def fit_pareto(
    beam: Beam,
    target: FitTarget,
    joints: int,
    options: ParetoOptions | None = None,
    *,
    workers: int = 1,
    progress: bool = True,
    extra_loads: Any = (),
    **changes: Any,
) -> ParetoResult:
    """Fit an nR PRBDM's Pareto front over (eigen loss, deflection loss) by NSGA-II.

    Design vector [gamma (n+1), log10 factors]; a Repair projects gamma onto the bounded
    simplex; termination after ``options.generations`` generations. ``workers > 1`` evaluates
    each generation's designs in that many processes (results do not depend on it); ``changes``
    are options by name applied to ``options`` (a :class:`~prbdm_pin.options.objects.ParetoOptions`,
    whose docstring says what each does; the result records it whole).

    With ``seed_with_fits`` the initial population holds the single-objective optima
    (eigen-only, deflection-only and the Eq. 27 combined optimum, each the best of a
    ``seed_starts`` multistart :func:`fit` with the same seed) and designs on the segments
    between them, the rest drawn uniformly (lengths on the bounded simplex, log10 factors in
    their bounds), so the front spans its anchors and the knee region. ``polish_knee`` runs the
    single-objective local solver on Eq. 27 from the NSGA-II knee and adds the result to the
    front if no front design dominates it; the knee is then taken on that front, and
    ``message`` records the raw NSGA-II knee beside it. Each generation is evaluated as one
    batch (``pareto_problem.pareto_objectives_batch``: every design's and pose's static solve
    in one vectorised Newton), so a ``paper`` front with a static solve per pose costs
    seconds, not minutes.

    Parameters
    ----------
    beam : Beam
        The planform, thickness, material and tip load.
    target : FitTarget
        Truth frequencies (rad/s) and the truth tip under the beam's tip load.
    joints : int
        n, the number of revolute joints.
    options : ParetoOptions, optional
        What determines the fit (population, generations, seed, parametrisation, norms,
        bounds, seeding and knee polish); default ``ParetoOptions()``.
    workers : int
        Processes to evaluate each generation in (results do not depend on it).
    progress : bool
        Show a tqdm progress bar over the generations.
    extra_loads : sequence of float or LoadCase
        Further load cases of the deflection objective, as in :func:`fit`.
    **changes
        Options by name, applied to ``options``.

    Returns
    -------
    ParetoResult
        The front (losses in %, designs with lengths in m and factors) and its knee (Eq. 27) as
        a FitResult.

    Raises
    ------
    BeamInputError
        On invalid options or workers, or a target without a truth tip or a tip load.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> options = pp.ParetoOptions(pop=12, generations=3, stiffness="joint", seed_starts=1)
    >>> front = pp.fit_pareto(beam, target, 2, options, progress=False)
    >>> front.F_pct.shape[1], bool(0 <= front.knee_index < front.F_pct.shape[0])
    (2, True)
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize
    from pymoo.termination import get_termination

    t0 = time.perf_counter()
    check_fit_inputs(beam, target, joints, workers)
    o = resolve_options(options, ParetoOptions, changes)
    if o.axes.spatial:
        from .spatial_pareto import fit_spatial_pareto

        if workers != 1 or extra_loads:
            raise BeamInputError("workers, extra_loads: a spatial front (axes = "
                                 f"{o.axes.value!r}) runs in one process on its one load case")
        return fit_spatial_pareto(beam, target, joints, o, progress=progress)
    target = with_extra_loads(target, beam, extra_loads)
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise BeamInputError(f"workers = {workers!r}: must be an integer >= 1")
    pop, generations, seed = o.pop, o.generations, o.seed
    problem = make_problem(beam, target, joints, o)
    if not target.has_static:
        raise BeamInputError("target has no truth tip position: a Pareto fit needs one")
    if not np.any(target.tip_force_N):
        raise BeamInputError("tip_force = [0, 0, 0] N: a Pareto fit needs a tip load "
                             "(the beam's tip_force)")
    n1 = problem.n_joints + 1
    log10_bounds = o.log10_bounds
    if log10_bounds is None:
        log10_bounds = problem.parametrisation.default_log10_bounds(problem)
    X0, n_seed_evals = _initial_population(beam, target, problem, o, log10_bounds, workers)
    algo = NSGA2(pop_size=int(pop), sampling=X0, repair=LengthRepair(n1, problem.min_fraction),
                 eliminate_duplicates=True)
    kw = {}
    if progress:
        kw["callback"] = PymooBar(int(generations))
    pool = None
    if workers > 1:
        pool = fit_pool(workers)
    pp = ParetoProblem(problem, log10_bounds,
                       runner=None if pool is None else PoolRows(pool, int(workers), problem))
    try:
        res = minimize(pp, algo, get_termination("n_gen", int(generations)), seed=int(seed),
                       verbose=False, **kw)
    except BaseException:
        if pool is not None:
            stop_pool(pool)
            pool = None
        raise
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        if progress:
            kw["callback"].close()
    F = np.atleast_2d(res.F)
    X = np.atleast_2d(res.X)
    n_evals = int(res.algorithm.evaluator.n_eval) + n_seed_evals
    ki = knee_index(F)
    raw = F[ki].copy()
    note = (f"raw NSGA-II knee: eigen {raw[0]:.6g} %, deflection {raw[1]:.6g} %, "
            f"combined {math.hypot(raw[0], raw[1]):.6g} %")
    if o.polish_knee:
        x_p, f_p, nfev_p = _polish_knee(problem, X[ki], log10_bounds)
        n_evals += nfev_p
        dominated = np.any(np.all(F <= f_p, axis=1) & np.any(F < f_p, axis=1))
        if np.all(np.isfinite(f_p)) and not dominated:
            keep = ~(np.all(f_p <= F, axis=1) & np.any(f_p < F, axis=1))
            F, X = np.vstack([F[keep], f_p]), np.vstack([X[keep], x_p])
            note += (f"; polished knee (Eq. 27 local solver): combined "
                     f"{math.hypot(f_p[0], f_p[1]):.6g} %")
        else:
            note += "; the knee polish did not improve on the front"
    order = np.lexsort((F[:, 1], F[:, 0]))
    F, X = F[order], X[order]
    ki = knee_index(F)
    lengths = X[:, :n1] * problem.length_m
    factors = 10.0 ** X[:, n1:]
    wall = time.perf_counter() - t0
    knee = result_from_design(
        problem, lengths[ki], factors[ki], objective=Objective.COMBINED, seed=int(seed),
        starts=int(pop), starts_run=int(pop), nfev=n_evals,
        start_losses_pct=np.hypot(F[:, 0], F[:, 1]), wall_time_s=wall, success=True,
        message=f"knee (Eq. 27) of an NSGA-II front of {F.shape[0]} designs; {note}")
    return ParetoResult(
        beam_name=beam.name, joints=problem.n_joints, frequencies=problem.n_freq,
        stiffness=problem.parametrisation.name, deflection_norm=o.deflection_norm.value,
        F_pct=F, X=X, front_lengths_m=lengths, front_factors=factors, knee_index=ki, pop=int(pop),
        generations=int(generations), n_evals=n_evals,
        seed=int(seed), xi=o.xi_rad, eps=o.eps_rad, wall_time_s=wall, success=True,
        eigen_norm=o.eigen_norm.value,
        message=f"NSGA-II, {generations} generations of {pop}"
                f"{', seeded with single-objective fits' if o.seed_with_fits else ''}; {note}",
        knee=knee, options=o)


def _design_row(problem: FitProblem, lengths_m, factors, log10_bounds) -> np.ndarray:
    """Return [gamma, log10 factors] of a design, the factors clipped to the Pareto bounds."""
    lf = np.clip(np.log10(np.asarray(factors, dtype=float)), *log10_bounds)
    return np.r_[np.asarray(lengths_m, dtype=float) / problem.length_m, lf]


def _initial_population(beam, target, problem: FitProblem, o: ParetoOptions, log10_bounds,
                        workers: int) -> tuple[np.ndarray, int]:
    """Return NSGA-II's initial population and the model evaluations it took.

    The population holds single-objective optima (optional), then uniform draws.
    """
    pop = o.pop
    rng = np.random.default_rng(o.seed)
    n1 = problem.n_joints + 1
    X = np.empty((pop, n1 + problem.n_factors))
    X[:, :n1] = sample_lengths(rng, problem.length_m, n1, pop,
                               min_fraction=problem.min_fraction) / problem.length_m
    X[:, n1:] = rng.uniform(log10_bounds[0], log10_bounds[1], (pop, problem.n_factors))
    nfev = 0
    if o.seed_with_fits:
        rows = []
        seeding = FitOptions(
            frequencies=problem.n_freq, stiffness=o.stiffness, starts=o.seed_starts,
            seed=o.seed, xi_rad=o.xi_rad, eps_rad=o.eps_rad, squared=o.squared,
            deflection_norm=o.deflection_norm, eigen_norm=o.eigen_norm,
            min_fraction=o.min_fraction)
        for objective in (Objective.COMBINED, Objective.EIGEN, Objective.DEFLECTION)[:pop]:
            r = fit(beam, target, problem.n_joints, seeding.replace(objective=objective),
                    workers=workers, progress=False)
            nfev += r.nfev
            rows.append(_design_row(problem, r.lengths_m, r.factors, log10_bounds))
        # designs on the segments eigen -> combined -> deflection anchor (the bounded length
        # simplex is convex): a start for the middle of the front, which NSGA-II alone fills
        # slowly when the SCFs add tens of variables
        combined, eigen, deflection = rows[0], rows[1 % len(rows)], rows[-1]
        for a, b in ((eigen, combined), (combined, deflection)):
            for t in np.linspace(0.0, 1.0, INTERPOLATED_SEEDS + 2)[1:-1]:
                rows.append((1.0 - t) * a + t * b)
        rows = rows[:pop]
        X[:len(rows)] = rows
    return X, nfev


def _polish_knee(problem: FitProblem, x: np.ndarray, log10_bounds):
    """Run the equation 27 local solver from a front design.

    Returns (design row, (eigen %, deflection %), nfev).
    """
    n1 = problem.n_joints + 1
    # the evaluation cap of a single-objective fit's start (ParetoOptions has none of its own)
    spec = FitSpec(problem, Objective.COMBINED, FitOptions.max_nfev)
    r = solve_start(spec, 0, x[:n1] * problem.length_m, 10.0 ** x[n1:])
    x_p = _design_row(problem, r.lengths_m, r.factors, log10_bounds)
    f_p = pareto_objectives(problem, x_p[:n1] * problem.length_m, 10.0 ** x_p[n1:])
    return x_p, f_p, int(r.nfev) + 1


def _pareto_rows(X: np.ndarray, problem: FitProblem) -> np.ndarray:
    return pareto_objectives_batch(problem, X)


class PoolRows:
    """A ``ParetoProblem`` runner that spreads a generation's rows over a process pool.

    The rows are split into ``workers`` chunks, each sent with the problem to ``pool`` (a worker
    must not unpickle arrays before it has pinned BLAS, so nothing travels in its initializer),
    and stacked back in order.
    """

    def __init__(self, pool, workers: int, problem: FitProblem) -> None:
        self.pool = pool
        self.workers = int(workers)
        self.problem = problem

    def __call__(self, X: np.ndarray) -> np.ndarray:
        """Return the objectives (eigen %, deflection %) of the design rows of X, shape (B, 2)."""
        chunks = np.array_split(X, self.workers)
        n = len(chunks)
        return np.vstack(list(self.pool.map(_pareto_rows, chunks, [self.problem] * n)))
