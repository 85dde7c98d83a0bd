"""The Pareto front of a spatial chain: frequencies by kind against the tip in 3D and its twist.

NSGA-II (pymoo) over the spatial fit's design [u (n), ln s] (``fitting/spatial_design.py``:
the stick-breaking lengths live in the unit box, so no repair is needed), with the two
objectives of the spatial fit's terms: the eigen loss (rms of the selected modes' relative
errors, %) and the deflection loss (tip position and twist, %, ``fitting/spatial_deflection``).
The knee is the front's design nearest the origin (Eq. 27). With ``seed_with_fits`` the initial
population holds the eigen, deflection and combined spatial fits (``seed_starts`` starts each);
the rest is drawn uniformly in the box. The knee is not polished (``polish_knee`` applies to
the planar front only): the combined spatial fit seeds the front instead.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..errors import SolveError
from ..options.choices import Objective
from ..options.objects import FitOptions, ParetoOptions
from .objectives import knee_index
from .pareto_result import ParetoResult
from .problem import unit_from_lengths
from .spatial_deflection import DeflectionTerm
from .spatial_design import LOG_FACTOR_BOUND, EigenTerm, SpatialDesign
from .spatial_fit import fit_spatial, spatial_result
from .spatial_target import select_spatial

__all__ = ["fit_spatial_pareto"]

# the objectives of a design whose chain is not valid (a pymoo front needs finite numbers)
_INVALID_PCT = 1e6


def _fit_options(o: ParetoOptions, objective: Objective, starts: int) -> FitOptions:
    return FitOptions(axes=o.axes, stiffness=o.stiffness, objective=objective,
                      frequencies=o.frequencies, seed=o.seed, starts=starts,
                      deflection_norm=o.deflection_norm, eigen_norm=o.eigen_norm,
                      min_fraction=o.min_fraction)


def _objectives(d: SpatialDesign, eig: EigenTerm, defl: DeflectionTerm, x: np.ndarray):
    try:
        model = d.model(x)
        r = eig.residual(d, model)
        return 100.0 * float(np.sqrt(np.mean(r * r))), defl.loss_pct(model)
    except SolveError:
        return _INVALID_PCT, _INVALID_PCT


def _row(d: SpatialDesign, result) -> np.ndarray:
    """Return the design vector [u, ln s] of a spatial fit's result."""
    u = unit_from_lengths(result.lengths_m, d.beam.length_m, d.o.min_fraction)
    return np.r_[u, np.clip(np.log(result.factors), -LOG_FACTOR_BOUND, LOG_FACTOR_BOUND)]


def fit_spatial_pareto(beam, target, joints: int, options: ParetoOptions, *,
                       progress: bool = True) -> ParetoResult:
    """Fit a spatial chain's front of (eigen loss, deflection loss) by NSGA-II.

    Parameters
    ----------
    beam : Beam
    target : FitTarget
        With every truth mode and its label, and a 3D tip truth (``spatial_load_target``).
    joints : int
        n, the joint nodes.
    options : ParetoOptions
        ``axes`` spatial; ``pop``, ``generations``, ``seed``, ``seed_with_fits``,
        ``seed_starts``, ``stiffness``, ``frequencies`` (modes of each kind), the norms.
    progress : bool
        Show a tqdm bar over the generations.

    Returns
    -------
    ParetoResult
        The front (losses %, lengths m, factors; ``X`` as [gamma, log10 factors]) and its knee
        as a spatial FitResult (``axes``, ``modes``).
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize
    from pymoo.termination import get_termination

    t0 = time.perf_counter()
    combined = _fit_options(options, Objective.COMBINED, options.seed_starts)
    sel = select_spatial(target, options.axes, joints, options.frequencies)
    eig, defl = EigenTerm(sel), DeflectionTerm(target, combined)
    d = SpatialDesign(beam, sel, joints, combined, (eig, defl))
    nx = joints + d.n_factors
    lo = np.r_[np.zeros(joints), np.full(d.n_factors, -LOG_FACTOR_BOUND)]
    hi = np.r_[np.ones(joints), np.full(d.n_factors, LOG_FACTOR_BOUND)]

    class _Front(Problem):
        def __init__(self):
            super().__init__(n_var=nx, n_obj=2, xl=lo, xu=hi)

        def _evaluate(self, X, out, *args, **kwargs):
            out["F"] = np.array([_objectives(d, eig, defl, x) for x in X])

    rng = np.random.default_rng(options.seed)
    X0 = rng.uniform(lo, hi, (options.pop, nx))
    n_seed = 0
    if options.seed_with_fits:
        for i, objective in enumerate((Objective.COMBINED, Objective.EIGEN,
                                       Objective.DEFLECTION)[: options.pop]):
            r = fit_spatial(beam, target, joints,
                            _fit_options(options, objective, options.seed_starts),
                            progress=False)
            n_seed += r.nfev
            X0[i] = _row(d, r)
    algo = NSGA2(pop_size=int(options.pop), sampling=X0, eliminate_duplicates=True)
    kw = {}
    if progress:
        from .progress import PymooBar

        kw["callback"] = PymooBar(int(options.generations))
    try:
        res = minimize(_Front(), algo, get_termination("n_gen", int(options.generations)),
                       seed=int(options.seed), verbose=False, **kw)
    finally:
        if progress:
            kw["callback"].close()
    F, X = np.atleast_2d(res.F), np.atleast_2d(res.X)
    order = np.lexsort((F[:, 1], F[:, 0]))
    F, X = F[order], X[order]
    ki = knee_index(F)
    lengths = np.array([d.lengths(x[:joints]) for x in X])
    factors = np.exp(X[:, joints:])
    n_evals = int(res.algorithm.evaluator.n_eval) + n_seed
    wall = time.perf_counter() - t0
    note = (f"NSGA-II, {options.generations} generations of {options.pop}"
            f"{', seeded with spatial fits' if options.seed_with_fits else ''}; knee: eigen "
            f"{F[ki, 0]:.6g} %, deflection {F[ki, 1]:.6g} %, combined "
            f"{math.hypot(*F[ki]):.6g} %")
    best = (float(math.hypot(*F[ki])), 0.0, ki, X[ki], True, "knee (Eq. 27)")
    runs = [(float(math.hypot(*f)), 0.0, i, x, True, "")
            for i, (f, x) in enumerate(zip(F, X, strict=True))]
    knee = spatial_result(beam, target, d, best, runs, wall,
                          f"knee (Eq. 27) of a spatial NSGA-II front of {F.shape[0]} designs; "
                          f"{note}")
    gamma = lengths / beam.length_m
    return ParetoResult(
        beam_name=beam.name, joints=joints, frequencies=int(sel.omega_truth_rad_s.size),
        stiffness=options.stiffness.value, deflection_norm=options.deflection_norm.value,
        F_pct=F, X=np.hstack([gamma, X[:, joints:] / math.log(10.0)]), front_lengths_m=lengths,
        front_factors=factors, knee_index=ki, pop=int(options.pop),
        generations=int(options.generations), n_evals=n_evals, seed=int(options.seed),
        xi=options.xi_rad, eps=options.eps_rad, wall_time_s=wall, success=True, message=note,
        knee=knee, eigen_norm="relative", options=options)
