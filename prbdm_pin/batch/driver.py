"""The batch driver: plan, run and record every beam of a batch.

It checks the folder, keeps the executor full, records every beam as it finishes, retries the
beams of a dead worker alone, and stops cleanly on Ctrl-C or SIGTERM.

Only the driver writes, and one driver per folder (a lock).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import os
import signal
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import BeamInputError
from ..io.paths import check_out_dir
from ..options.validate import check_type
from .executors import DaskCluster, LocalPool
from .manifest import MANIFEST, build_manifest, check_manifest
from .records import (
    RESULTS_CSV,
    RESULTS_JSONL,
    RecordWriter,
    latest_records,
    read_records,
    write_csv,
)
from .spec import BatchSpec, BeamTask, plan_tasks
from .work import evaluate_beam, record_header

__all__ = ["BatchSummary", "run_batch"]

_LOCK = ".batch.lock"


@dataclass(frozen=True)
class BatchSummary:
    """What a call of :func:`run_batch` did.

    Attributes
    ----------
    out_dir : Path
    n_tasks : int
        Beams in this run's shard.
    n_skipped : int
        Already in ``results.jsonl`` when the run started (resumed).
    n_ok, n_failed : int
        Records written by this run.
    n_retried : int
        Beams whose worker process died and that were run again.
    wall_s : float
        Wall time of this run, s.
    interrupted : bool
    """

    out_dir: Path
    n_tasks: int
    n_skipped: int
    n_ok: int
    n_failed: int
    n_retried: int
    wall_s: float
    interrupted: bool = False



@dataclass
class _Run:
    writer: RecordWriter
    records: list[dict[str, Any]]
    progress: Any
    n_ok: int = 0
    n_failed: int = 0
    n_retried: int = 0
    attempts: dict[int, int] = field(default_factory=dict)

    def record(self, task: BeamTask, rec: dict[str, Any]) -> None:
        rec.setdefault("status", "ok")
        rec["attempts"] = self.attempts.get(task.index, 1)
        self.writer.write(rec)
        self.records.append(rec)
        if rec["status"] == "ok":
            self.n_ok += 1
        else:
            self.n_failed += 1
        self.progress.update(1)
        self.progress.set_postfix(failed=self.n_failed, refresh=False)


def _failure(task: BeamTask, reason: str) -> dict[str, Any]:
    return {**record_header(task), "status": "failed", "stage": "worker", "error": reason}


@contextlib.contextmanager
def _exclusive(out_dir: Path):
    try:
        import fcntl
    except ImportError:  # not POSIX: no guard against two drivers on one folder
        yield
        return
    with open(out_dir / _LOCK, "w") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise BeamInputError(
                f"out = {str(out_dir)!r}: another batch is running in this folder"
            ) from None
        yield


def _raise_interrupt(signum: int, frame: Any) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


def _stop_on_sigterm() -> Any:
    # A job scheduler ends a job with SIGTERM (then SIGKILL): stop as cleanly as on Ctrl-C.
    import threading

    if threading.current_thread() is not threading.main_thread():
        return None
    return signal.signal(signal.SIGTERM, _raise_interrupt)


def run_batch(
    spec: BatchSpec,
    out_dir: str | os.PathLike,
    *,
    work: Callable[[BeamTask], dict[str, Any]] = evaluate_beam,
    backend: LocalPool | DaskCluster | None = None,
    progress: bool = True,
    retry_failed: bool = False,
) -> BatchSummary:
    """Compute every beam of ``spec`` (this shard) not yet in ``out_dir/results.jsonl``.

    Parameters
    ----------
    spec : BatchSpec
    out_dir : path
        Output folder: ``batch.json``, ``results.jsonl``, ``results.csv``.
    work : callable
        Module-level (picklable) ``work(task) -> dict`` returning a flat JSON-ready record;
        default :func:`evaluate_beam` (truth + fit).
    backend : LocalPool or DaskCluster
        Where beams run; default ``LocalPool(1)``.
    progress : bool
        Show a tqdm bar.
    retry_failed : bool
        Also recompute beams recorded as failed (their new record supersedes the old).

    Returns
    -------
    BatchSummary

    Raises
    ------
    BeamInputError
        Bad arguments, or ``out_dir`` holds a batch made with other arguments.
    KeyboardInterrupt
        After Ctrl-C (or SIGTERM), once every finished beam is on disk and ``results.csv`` is
        written.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> options = pp.FitOptions(objective="eigen", stiffness="joint", starts=1)
    >>> settings = pp.FitSettings(joints=2, options=options, truth_model="beam")
    >>> _ = pp.save_beam(beam, folder / "beams" / "strip.json")
    >>> spec = pp.BatchSpec(seed=0, settings=settings, beams_dir=str(folder / "beams"))
    >>> summary = pp.run_batch(spec, folder / "out", progress=False)
    >>> summary.n_ok, summary.n_failed
    (1, 0)
    >>> sorted(p.name for p in (folder / "out").iterdir())
    ['.batch.lock', 'batch.json', 'results.csv', 'results.jsonl']
    """
    t0 = time.perf_counter()
    check_type("spec", spec, BatchSpec)
    out = check_out_dir("out_dir", out_dir)  # a file, /proc, an unwritable folder: refused
    backend = backend or LocalPool(1)
    tasks = plan_tasks(spec)  # the beam files are checked before OUT is made
    out.mkdir(parents=True, exist_ok=True)
    with _exclusive(out):
        jsonl = out / RESULTS_JSONL
        check_manifest(out / MANIFEST, build_manifest(spec, tasks), jsonl)
        records = read_records(jsonl, repair=True)
        wanted = {t.index for t in tasks}
        stray = sorted({r["beam_index"] for r in records} - wanted)
        if stray:
            raise BeamInputError(f"{jsonl}: holds beam {stray[0]}, which is not in this batch")
        done = {r["beam_index"] for r in latest_records(records)
                if r.get("status") == "ok" or not retry_failed}
        todo = [t for t in tasks if t.index not in done]
        from ..io.progress import progress_bar

        bar = progress_bar(len(tasks), enabled=progress, initial=len(tasks) - len(todo),
                           unit="beam", desc="batch")
        run = _Run(RecordWriter(jsonl), records, bar)
        interrupted = False
        previous = _stop_on_sigterm()
        try:
            suspects = _drive(todo, work, backend, run)
            if suspects:
                _retry_isolated(suspects, work, backend, run)
        except KeyboardInterrupt:
            interrupted = True
            raise
        finally:
            if previous is not None:
                signal.signal(signal.SIGTERM, previous)
            run.writer.close()
            bar.close()
            # the CSV is rebuilt from the file, not from memory: a signal can land between a
            # record's durable write and its append to run.records
            write_csv(read_records(jsonl), out / RESULTS_CSV)
            backend.close()
    return BatchSummary(out, len(tasks), len(tasks) - len(todo), run.n_ok, run.n_failed,
                        run.n_retried, time.perf_counter() - t0, interrupted)


def _drive(todo: Sequence[BeamTask], work: Callable, backend: Any, run: _Run) -> list[BeamTask]:
    """Run ``todo`` keeping ``backend.slots`` beams in flight.

    Returns the beams that were in flight when a worker process died (to be retried).
    """
    pending = deque(todo)
    suspects: list[BeamTask] = []
    executor = backend.executor()
    inflight: dict[cf.Future, BeamTask] = {}

    def collect(futures: Iterable[cf.Future]) -> bool:
        broken = False
        for fut in sorted(futures, key=lambda f: inflight[f].index):
            task = inflight.pop(fut)
            try:
                run.record(task, fut.result())
            except cf.process.BrokenProcessPool:
                broken = True
                suspects.append(task)
            except Exception as exc:  # noqa: BLE001 -- recorded as the beam's failure
                run.record(task, _failure(task, f"{type(exc).__name__}: {exc}"))
        return broken

    try:
        while pending or inflight:
            broken = False
            while pending and len(inflight) < backend.slots:
                task = pending.popleft()
                try:
                    inflight[executor.submit(work, task)] = task
                except cf.process.BrokenProcessPool:
                    pending.appendleft(task)
                    broken = True
                    break
            if not broken:
                finished, _ = cf.wait(inflight, return_when=cf.FIRST_COMPLETED)
                broken = collect(finished)
            if broken:
                # A worker died and the pool is unusable: every beam still in flight either
                # finished before the break or failed with it; the failed ones are retried.
                collect(cf.wait(inflight).done)
                executor.shutdown(wait=False, cancel_futures=True)
                executor = backend.executor()
    except BaseException:
        backend.abort(executor)
        raise
    executor.shutdown(wait=True)
    return suspects


def _retry_isolated(suspects: list[BeamTask], work: Callable, backend: Any, run: _Run) -> None:
    """Run once more, alone, each beam that was in flight when a worker died.

    Each runs in a fresh one-worker pool, so a beam that kills its worker again is identified
    and recorded failed.
    """
    queue = deque(sorted(suspects, key=lambda t: t.index))
    running: dict[cf.Future, tuple[BeamTask, cf.Executor]] = {}
    try:
        while queue or running:
            while queue and len(running) < backend.slots:
                task = queue.popleft()
                run.attempts[task.index] = run.attempts.get(task.index, 1) + 1
                run.n_retried += 1
                ex = backend.executor(1)
                running[ex.submit(work, task)] = (task, ex)
            finished, _ = cf.wait(running, return_when=cf.FIRST_COMPLETED)
            for fut in sorted(finished, key=lambda f: running[f][0].index):
                task, ex = running.pop(fut)
                try:
                    rec = fut.result()
                except cf.process.BrokenProcessPool as exc:
                    rec = _failure(task, f"worker process died twice while computing this beam "
                                         f"(BrokenProcessPool: {exc})")
                except Exception as exc:  # noqa: BLE001
                    rec = _failure(task, f"{type(exc).__name__}: {exc}")
                ex.shutdown(wait=False)
                run.record(task, rec)
    except BaseException:
        for _, ex in running.values():
            backend.abort(ex)
        raise
