"""Worker process pools that stop with their driver and stop at once on Ctrl-C.

Every pool of the package (fit starts, Pareto rows, batch beams) is made here. A worker

- ignores SIGINT: a terminal sends Ctrl-C to the whole process group, and only the driver decides
  what an interrupt means (the batch keeps every finished record, a fit writes nothing);
- dies with its driver: on Linux the kernel sends it SIGTERM when its parent exits
  (``prctl(PR_SET_PDEATHSIG)``); elsewhere, and under a fork server, a daemon thread exits the
  process once the driver is gone (checked every ``PARENT_POLL_S``). Without this a killed
  driver left its workers blocked on the task queue for minutes, and the resource tracker too.

:func:`stop_pool` cancels the queued tasks and terminates the running workers: a
``with`` block on a ``ProcessPoolExecutor`` waits for every queued task instead (34 s after
Ctrl-C for 800 fit starts).

This module imports no numpy: a spawned worker imports it to unpickle the initializer, which runs
before BLAS is loaded.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["PARENT_POLL_S", "BLAS_THREAD_VARS", "init_worker", "process_pool", "stop_pool",
           "pool_scope", "pin_blas"]

PARENT_POLL_S = 0.5
# the thread-count variables a worker sets to 1 before it loads BLAS (see pin_blas)
BLAS_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
_PR_SET_PDEATHSIG = 1  # linux/prctl.h


def _die_with_parent() -> bool:
    """Ask the kernel for SIGTERM when the parent exits; True if it is armed (Linux)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _alive(pid: int) -> bool:
    if os.name != "posix":  # os.kill(pid, 0) would terminate the process on Windows
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by someone else
        return True
    return True


def _driver_gone(driver_pid: int, parent_pid: int) -> bool:
    # The parent is the driver (spawn, fork) or a fork server the driver started; a dead parent
    # shows as a changed parent id (the orphan is re-parented).
    if os.getppid() != parent_pid:
        return True
    return driver_pid != parent_pid and not _alive(driver_pid)


def _watch(driver_pid: int, parent_pid: int, poll_s: float) -> None:
    while True:
        if _driver_gone(driver_pid, parent_pid):
            os._exit(1)
        time.sleep(poll_s)


def init_worker(driver_pid: int, initializer: Callable[..., Any] | None = None,
                initargs: tuple = (), poll_s: float = PARENT_POLL_S) -> None:
    """Guard a pool worker: Ctrl-C left to the driver, exit when the driver is gone.

    Then run ``initializer(*initargs)``.

    Parameters
    ----------
    driver_pid : int
        Process id of the process that made the pool.
    initializer : callable, optional
        The pool's own initializer.
    initargs : tuple
        Its arguments.
    poll_s : float
        Interval of the parent check, s.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # a forked worker inherits the driver's handlers; SIGTERM must end it (PDEATHSIG, abort)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    parent_pid = os.getppid()
    armed = _die_with_parent()
    # the driver may have died before the line above armed the kernel's guard
    if parent_pid != driver_pid and not _alive(driver_pid):
        os._exit(1)
    if not armed or parent_pid != driver_pid:
        # A thread watches where the kernel cannot, and under a fork server, which outlives
        # the driver as long as a worker lives (workers hold its liveness pipe). A spawned
        # or forked worker with the kernel's guard keeps a single thread.
        threading.Thread(target=_watch, args=(driver_pid, parent_pid, poll_s), daemon=True,
                         name="prbdm-parent-watch").start()
    if initializer is not None:
        initializer(*initargs)


def process_pool(workers: int, mp_context: Any, initializer: Callable[..., Any] | None = None,
                 initargs: tuple = ()) -> cf.ProcessPoolExecutor:
    """Make a ``ProcessPoolExecutor`` of ``workers`` processes that run :func:`init_worker`.

    Parameters
    ----------
    workers : int
        Number of processes.
    mp_context : multiprocessing context
        How the workers start (``spawn``, ``fork``, ``forkserver``).
    initializer, initargs
        The pool's own initializer, run after the guards are in place.
    """
    return cf.ProcessPoolExecutor(
        max_workers=int(workers), mp_context=mp_context, initializer=init_worker,
        initargs=(os.getpid(), initializer, tuple(initargs)),
    )


def stop_pool(executor: cf.Executor, join_s: float = 5.0) -> None:
    """Stop now: cancel the queued tasks and terminate the running workers.

    Parameters
    ----------
    executor : concurrent.futures.Executor
        A process pool (others are only shut down without waiting).
    join_s : float
        How long to wait for each terminated worker, s.
    """
    terminate = getattr(executor, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        with contextlib.suppress(Exception):
            terminate()
        return
    # Before 3.14 the pool keeps its processes in a private mapping; without it the running
    # tasks finish before the interpreter exits.
    procs = list((getattr(executor, "_processes", None) or {}).values())
    executor.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(join_s)
    # The pool's manager thread notices the dead workers and closes its wake-up pipe; before
    # 3.12 the interpreter's exit hook can write to that pipe while it closes (an OSError
    # printed at exit), so let the thread finish first.
    manager = getattr(executor, "_executor_manager_thread", None)
    if manager is not None:
        with contextlib.suppress(Exception):
            manager.join(join_s)


@contextlib.contextmanager
def pool_scope(executor: cf.Executor) -> Iterator[cf.Executor]:
    """Use ``executor`` in a ``with`` block.

    On leaving normally wait for it; on any exception (Ctrl-C included) :func:`stop_pool` it.
    """
    try:
        yield executor
    except BaseException:
        stop_pool(executor)
        raise
    executor.shutdown(wait=True)


def pin_blas() -> None:
    """Set :data:`BLAS_THREAD_VARS` to 1 in a pool worker before anything loads numpy.

    BLAS reads them once, when it loads, so this runs as the pool's initializer.

    It takes no arguments on purpose: a spawned worker unpickles an initializer's arguments
    before running it, and arguments holding arrays would load numpy first. Work that needs
    data receives it with each task. The caller's own environment is left as it is.
    """
    for var in BLAS_THREAD_VARS:
        os.environ[var] = "1"
