"""Where the beams of a batch run: a local process pool or an existing Dask cluster.

The local pool runs one BLAS thread per worker; both give the driver a concurrent.futures
executor.

No numpy at import: a spawned worker imports this module to unpickle the pool initializer, which
must set the BLAS thread variables before numpy loads its BLAS.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
from typing import Any

from ..errors import BeamInputError
from ..options.checks import check_choice, check_int

__all__ = ["LocalPool", "DaskCluster"]

_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


def _init_worker() -> None:
    """Pool initializer: one BLAS/OpenMP thread per worker.

    ``workers.init_worker`` leaves Ctrl-C to the driver and ends the worker with it.

    It runs before the first task is unpickled, and the batch package imports no numpy at
    import, so the variables are set before BLAS loads (OpenBLAS reads them once, when it loads).
    """
    for var in _THREAD_VARS:
        os.environ[var] = "1"


class LocalPool:
    """A local process pool: ``workers`` processes, one BLAS thread each.

    Parameters
    ----------
    workers : int
        Number of worker processes.
    mp_context : str
        ``"spawn"`` (default) or ``"forkserver"``: a fresh interpreter, so BLAS starts pinned.
    """

    isolates_deaths = True  # a dead worker breaks the pool: the driver retries its beams

    def __init__(self, workers: int = 1, mp_context: str = "spawn") -> None:
        check_int("workers", workers, 1)
        check_choice("mp_context", mp_context, ("spawn", "forkserver"))
        self.workers = workers
        self.mp_context = mp_context

    @property
    def slots(self) -> int:
        """Beams in flight at once."""
        return self.workers

    def executor(self, workers: int | None = None) -> cf.Executor:
        """Return a fresh pool (``workers`` processes, default ``self.workers``)."""
        from ..workers import process_pool

        return process_pool(workers or self.workers,
                            multiprocessing.get_context(self.mp_context), _init_worker)

    def abort(self, executor: cf.Executor) -> None:
        """Stop now: cancel queued beams and end the running worker processes."""
        from ..workers import stop_pool

        stop_pool(executor)

    def close(self) -> None:
        """Nothing to release (each pool is shut down by the driver)."""


class DaskCluster:
    """An existing Dask ``distributed`` cluster, through ``Client(...).get_executor()``.

    Parameters
    ----------
    scheduler : str or distributed.Client
        A scheduler address (``"tcp://host:8786"``) or a connected client.

    Dask retries a task whose worker died (``distributed.scheduler.allowed-failures``) and then
    raises ``KilledWorker``, which the driver records as the beam's failure. Dask's nanny already
    starts workers with one BLAS thread (``distributed.nanny.pre-spawn-environ``).
    """

    isolates_deaths = False

    def __init__(self, scheduler: Any) -> None:
        try:
            import distributed
        except ImportError:
            raise BeamInputError(
                "scheduler: Dask is not installed; install the extra: pip install prbdm_pin[dask]"
            ) from None
        if isinstance(scheduler, distributed.Client):
            self.client, self._owned = scheduler, False
        else:
            try:
                self.client, self._owned = distributed.Client(scheduler, timeout=30), True
            except (OSError, TimeoutError, ValueError) as exc:
                raise BeamInputError(f"scheduler = {scheduler!r}: cannot connect ({exc})") from None

    @property
    def slots(self) -> int:
        """Beams in flight: twice the cluster's threads, so no worker waits for the driver."""
        return max(1, 2 * sum(self.client.nthreads().values()))

    def executor(self, workers: int | None = None) -> cf.Executor:
        """Return the client's concurrent.futures executor."""
        return self.client.get_executor(pure=False)

    def abort(self, executor: cf.Executor) -> None:
        """Cancel every submitted beam."""
        executor.shutdown(wait=False)

    def close(self) -> None:
        """Close the client if this object opened it."""
        if self._owned:
            self.client.close()
