"""The Pareto fit's pymoo pieces: the problem, the length repair and a design's two objectives.

The problem is over [gamma (n+1), log10 factors]; the repair keeps the link lengths on the
bounded simplex.

Both pymoo classes are module-level, so a problem pickles (to a worker, a checkpoint); how a
generation's rows are evaluated is injected as ``runner`` (in-process by default, a process pool
in ``fit_pareto``), as pymoo's own ``elementwise_runner`` is.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from pymoo.core.problem import Problem
from pymoo.core.repair import Repair

from ..chain.layout import repair_lengths
from ..errors import BeamInputError, SolveError
from ..options.choices import MIN_FRACTION
from .evaluate import batch_losses, evaluate
from .problem import FitProblem

__all__ = ["LengthRepair", "ParetoProblem", "pareto_objectives", "pareto_objectives_batch"]

# (eigen %, deflection %) given to a design whose model cannot be solved
PENALTY_PCT = 1e3


class LengthRepair(Repair):
    """A pymoo Repair projecting the length fractions gamma onto the bounded simplex.

    The first ``n_links`` variables are projected (Euclidean projection,
    ``layout.repair_lengths``).

    Parameters
    ----------
    n_links : int
        n + 1, the number of length fractions at the start of each row.
    min_fraction : float
        The smallest link length, as a fraction of the beam length.
    """

    def __init__(self, n_links: int, min_fraction: float = MIN_FRACTION) -> None:
        super().__init__()
        self.n_links = int(n_links)
        self.min_fraction = float(min_fraction)

    def _do(self, problem, X, **kwargs):
        X = np.array(X, dtype=float, copy=True)
        X[:, :self.n_links] = repair_lengths(X[:, :self.n_links], 1.0,
                                             min_fraction=self.min_fraction)
        return X


class ParetoProblem(Problem):
    """A pymoo Problem over x = [gamma (n+1), log10 factors]: F = (eigen %, deflection %).

    The deflection loss is in the problem's normalisation (``problem.deflection_norm``: Eq. 19
    or the tip displacement).
    Designs whose static solve fails get ``penalty`` (%) in both objectives. ``runner``, when
    given, maps the rows X (B, n_var) of a generation to F (B, 2) (e.g. over a process pool);
    it is not pickled with the problem, whose copy evaluates in its own process.

    Parameters
    ----------
    problem : FitProblem
        The fit problem; its target needs a truth tip.
    log10_bounds : tuple of float
        Bounds of the log10 factors (dimensionless).
    penalty : float
        Both objectives (%) of a design whose model cannot be solved.
    runner : callable, optional
        Maps a generation's rows X (B, n_var) to F (B, 2), %.
    """

    def __init__(self, problem: FitProblem, log10_bounds: tuple[float, float],
                 penalty: float = PENALTY_PCT,
                 runner: Callable[[np.ndarray], np.ndarray] | None = None) -> None:
        if not problem.target.has_static:
            raise BeamInputError("target has no truth tip position: a Pareto fit needs one")
        n1 = problem.n_joints + 1
        nf = problem.n_factors
        lo = np.r_[np.full(n1, problem.min_fraction), np.full(nf, log10_bounds[0])]
        hi = np.r_[np.full(n1, 1.0 - problem.min_fraction), np.full(nf, log10_bounds[1])]
        super().__init__(n_var=n1 + nf, n_obj=2, xl=lo, xu=hi,
                         exclude_from_serialization=["runner"])
        self.fit_problem = problem
        self.penalty = float(penalty)
        self.runner = runner

    def _evaluate(self, X, out, *args, **kwargs):
        if self.runner is not None:
            out["F"] = np.asarray(self.runner(X), dtype=float).reshape(-1, 2)
            return
        out["F"] = pareto_objectives_batch(self.fit_problem, X, self.penalty)


def pareto_objectives(problem: FitProblem, lengths_m, factors,
                      penalty: float = PENALTY_PCT) -> np.ndarray:
    """Return (eigen loss %, deflection loss %) of a design; ``penalty`` for both if a solve fails.

    Parameters
    ----------
    problem : FitProblem
        The fit problem (beam, target with its truth tip, poses).
    lengths_m : array_like, shape (n+1,)
        Link lengths, m.
    factors : array_like
        The spring factors of the parametrisation (dimensionless).
    penalty : float
        Both objectives (%) when a solve fails.

    Returns
    -------
    ndarray, shape (2,)
        The eigen and deflection losses (the problem's ``deflection_norm``), %.
    """
    try:
        ev = evaluate(problem, lengths_m, factors, deflection=True)
    except (SolveError, BeamInputError):
        return np.array([penalty, penalty])
    d = ev.tip_loss_pct(problem.deflection_norm)
    if not (math.isfinite(ev.eigen_loss_pct) and math.isfinite(d)):
        return np.array([penalty, penalty])
    return np.array([ev.eigen_loss_pct, d])


def pareto_objectives_batch(problem: FitProblem, X: np.ndarray,
                            penalty: float = PENALTY_PCT) -> np.ndarray:
    """Return (eigen loss %, deflection loss %) of the design rows of X, in one batch.

    The batch is ``evaluate.batch_losses``; ``penalty`` goes to both where a design cannot be
    solved.

    Parameters
    ----------
    problem : FitProblem
        The fit problem (beam, target with its truth tip, poses).
    X : array_like, shape (B, n_var)
        Rows x = [gamma (n+1), log10 factors] (dimensionless).
    penalty : float
        Both objectives (%) where a design cannot be solved.

    Returns
    -------
    ndarray, shape (B, 2)
        The eigen and deflection losses (the problem's ``deflection_norm``), %.
    """
    X = np.atleast_2d(np.asarray(X, dtype=float))
    n1 = problem.n_joints + 1
    r = batch_losses(problem, X[:, :n1] * problem.length_m, 10.0 ** X[:, n1:])
    d = 100.0 * r.tip_errors(problem.deflection_norm).mean(axis=1)
    F = np.column_stack([r.eigen_pct, d])
    F[~np.all(np.isfinite(F), axis=1)] = penalty
    return F
