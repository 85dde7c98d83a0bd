"""The multistart of the joint deflection and combined fits: explore every start, refine the best.

Every start first runs ``explore_nfev`` residual evaluations of the geodesic Levenberg-Marquardt
solver; then the ``refine`` best of them (by loss, then start index) continue from where they
stand to convergence or the evaluation cap. The others keep their explored loss, marked as such
in their message. Both stages run in ``workers`` processes and each start is solved the same
way wherever it runs, so the result does not depend on the number of workers.

Why: each start of these fits crawls along a curved valley to a fold, and the starts that
converge to the best optimum are already among the best few after a short exploration
(``scripts/bench_fit_jacobian.py`` measures the same optimum as refining every start, on shipped
and random panels).
"""

from __future__ import annotations

from contextlib import nullcontext
from dataclasses import replace

from ..workers import pool_scope
from .local import explore_start, refine_start
from .pool import fit_pool
from .progress import start_bar
from .spec import FitSpec, StartResult

__all__ = ["run_explored"]


def run_explored(spec: FitSpec, tasks: list, explore_nfev: int, refine: int, workers: int = 1,
                 progress: bool = True, loss_tol: float | None = None) -> list[StartResult]:
    """Explore every start, then refine the ``refine`` best.

    Parameters
    ----------
    spec : FitSpec
        The fit problem (``joint`` parametrisation, objective ``deflection`` or ``combined``).
    tasks : list of tuple
        The starts (index, lengths m, factors), as from ``multistart.draw_starts``.
    explore_nfev : int
        Residual evaluations of each start's exploration.
    refine : int
        How many of the best explored starts continue (at least 1).
    workers : int
        Processes to spread the starts over (1: in this process).
    progress : bool
        Show a tqdm progress bar (one tick per exploration and per refinement).
    loss_tol : float, optional
        Stop refining at the first refined start whose loss is <= ``loss_tol`` (%).

    Returns
    -------
    list of StartResult
        One per start, in start order: refined starts' optima and the others' explored points.
    """
    refine = min(refine, len(tasks))
    bar = start_bar(len(tasks) + refine, progress)
    try:
        with pool_scope(fit_pool(workers)) if workers > 1 else nullcontext() as ex:
            explored = _map(ex, explore_start, [(spec, *t, explore_nfev) for t in tasks], bar)
            runs = [replace(r, message=f"explored only ({r.message})") for r, _ in explored]
            order = sorted(range(len(runs)), key=lambda i: (runs[i].loss_pct, i))[:refine]
            jobs = [(spec, explored[i][0], explored[i][1]) for i in order]
            for i, res in zip(order, _map(ex, refine_start, jobs, bar, loss_tol), strict=False):
                runs[i] = res
        return runs
    finally:
        bar.close()


def _map(ex, fn, jobs: list, bar, loss_tol: float | None = None) -> list:
    """Return fn(*job) for each job in order, run in ``ex`` (None: here).

    Stops after a result whose ``loss_pct`` is <= ``loss_tol``.
    """
    out = []
    if ex is None:
        for job in jobs:
            out.append(fn(*job))
            bar.update()
            if loss_tol is not None and out[-1].loss_pct <= loss_tol:
                break
        return out
    futures = [ex.submit(fn, *job) for job in jobs]
    for fut in futures:
        out.append(fut.result())
        bar.update()
        if loss_tol is not None and out[-1].loss_pct <= loss_tol:
            for f in futures:
                f.cancel()
            break
    return out
