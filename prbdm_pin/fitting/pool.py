"""The process pool of a fit's starts and of a Pareto fit's generations.

BLAS is pinned to one thread in each worker, the caller's environment left as it is.
"""

from __future__ import annotations

import concurrent.futures as cf
import os

from ..workers import pin_blas, process_pool

__all__ = ["fit_pool"]


def fit_pool(workers: int) -> cf.ProcessPoolExecutor:
    """Return a pool of ``workers`` processes with one BLAS thread each; tasks carry their data.

    Forked from a caller whose BLAS is already pinned (the CLI's, a pinned script's), else
    spawned: a worker then sets the thread variables before it loads numpy
    (``workers.pin_blas``), since BLAS reads them once, when it loads.
    """
    import multiprocessing as mp

    pinned = all(os.environ.get(v) == "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"))
    if pinned and "fork" in mp.get_all_start_methods():
        context = mp.get_context("fork")
    else:
        context = mp.get_context("spawn")
    return process_pool(workers, context, pin_blas)
