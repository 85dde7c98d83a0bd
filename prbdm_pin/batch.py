"""Batch studies: many beams, each one truth (cached) plus one fit, over a concurrent.futures
executor (a local process pool by default; a Dask cluster when asked).

Only the driver writes. Every finished beam becomes one JSON line appended to
``DIR/results.jsonl`` (flushed and fsynced), failures included with their error; at the end the
lines are consolidated, sorted by beam index, into ``DIR/results.csv`` (atomic). ``DIR/batch.json``
records the arguments that determine the results, so a rerun resumes (finished beams are skipped)
and a rerun with other arguments is refused; every record carries them too, so a folder that lost
its batch.json still refuses them. Both files are checked on read (``batch_files``).

Beam i of a random batch is ``random_beam(default_rng(SeedSequence(seed, spawn_key=(i,))))`` and
its fit seed is the first 32-bit word of that sequence's first child, so no result depends on the
scheduling order, the worker count or the shard.

This module imports numpy only inside functions: a spawned worker imports it to unpickle the pool
initializer, which must set the BLAS thread variables before numpy loads its BLAS.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import csv
import io
import json
import math
import multiprocessing
import os
import signal
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import BeamInputError

if TYPE_CHECKING:
    from .geometry import Beam

__all__ = [
    "FitSettings",
    "BatchSpec",
    "BeamTask",
    "BatchSummary",
    "LocalPool",
    "DaskCluster",
    "plan_tasks",
    "beam_of",
    "beam_features",
    "evaluate_beam",
    "run_batch",
    "read_records",
    "record_to_json",
    "latest_records",
    "parse_shard",
    "RESULTS_JSONL",
    "RESULTS_CSV",
    "MANIFEST",
    "RUN_DEPENDENT_FIELDS",
]

RESULTS_JSONL = "results.jsonl"
RESULTS_CSV = "results.csv"
MANIFEST = "batch.json"
_LOCK = ".batch.lock"
_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")
# Fields that describe a run rather than its result: they legitimately differ between two runs.
RUN_DEPENDENT_FIELDS = frozenset({"wall_s", "truth_s", "fit_s", "attempts", "worker_pid",
                                  "worker_peak_rss_mb"})

OBJECTIVES = ("eigen", "deflection", "combined")
STIFFNESS_KINDS = ("paper", "joint")
TRUTH_MODELS = ("plate", "plate-morley", "solid", "beam")
EIGEN_NORMS = ("paper", "relative")  # objectives.EIGEN_NORMS (numpy-free here)
DEFAULT_EIGEN_NORM = "relative"  # fitting.fit's default


# ------------------------------------------------------------------------------------------------
# What is computed


@dataclass(frozen=True)
class FitSettings:
    """What every beam of a batch computes: one truth and one fit.

    Attributes
    ----------
    joints : int
        Number of PRBDM joints n (n + 1 links).
    frequencies : int or None
        Number of truth frequencies matched (default: ``joints``).
    objective : str
        ``"eigen"``, ``"deflection"`` or ``"combined"``.
    stiffness : str
        ``"paper"`` (Eq. 14, one SCF per pose) or ``"joint"`` (one factor per joint).
    starts : int
        Multistart start points per fit.
    truth_model : str
        ``"plate"``, ``"solid"`` or ``"beam"`` (1D Euler-Bernoulli, milliseconds).
    eigen_norm : str
        ``"paper"`` (Eq. 16) or ``"relative"`` (rms of the per-mode relative errors).
    cache_dir : str or None
        Truth cache folder (does not change results, so it is not part of the manifest).
    min_fraction : float
        Eq. 15's lower bound on every link, a fraction of L (0.02); 0 < f < 1/(joints+1).
    """

    joints: int
    frequencies: int | None = None
    objective: str = "eigen"
    stiffness: str = "paper"
    starts: int = 64
    truth_model: str = "plate"
    eigen_norm: str = DEFAULT_EIGEN_NORM
    cache_dir: str | None = None
    min_fraction: float = 0.02

    def __post_init__(self) -> None:
        from .layout import check_min_fraction

        _check_int("joints", self.joints, 1)
        object.__setattr__(self, "min_fraction", check_min_fraction(self.min_fraction,
                                                                    self.joints))
        if self.frequencies is not None:
            _check_int("frequencies", self.frequencies, 1)
        _check_int("starts", self.starts, 1)
        _check_choice("objective", self.objective, OBJECTIVES)
        _check_choice("stiffness", self.stiffness, STIFFNESS_KINDS)
        _check_choice("truth_model", self.truth_model, TRUTH_MODELS)
        _check_choice("eigen_norm", self.eigen_norm, EIGEN_NORMS)

    @property
    def n_frequencies(self) -> int:
        """Frequencies matched (``frequencies`` or ``joints``)."""
        return self.joints if self.frequencies is None else self.frequencies


@dataclass(frozen=True)
class BeamTask:
    """One work item: the beam of index ``index`` and what to compute for it.

    ``beam`` is None for a random batch: the worker regenerates beam ``index`` from ``seed``
    (cheaper to ship than the beam, and reproducible anywhere).
    """

    index: int
    seed: int
    settings: FitSettings
    name: str
    beam: Beam | None = None


@dataclass(frozen=True)
class BatchSpec:
    """The arguments that determine a batch's results (they go into ``DIR/batch.json``).

    Attributes
    ----------
    seed : int
        Root seed of the per-beam ``SeedSequence``.
    settings : FitSettings
    n_beams : int or None
        Number of random beams; None when the beams come from ``beams_dir``.
    beams_dir : str or None
        Folder of beam JSON files (sorted by file name; index = position).
    shard : tuple of int
        ``(i, N)``: this run takes the beams with index % N == i.
    """

    seed: int
    settings: FitSettings
    n_beams: int | None = None
    beams_dir: str | None = None
    shard: tuple[int, int] = (0, 1)

    def __post_init__(self) -> None:
        _check_int("seed", self.seed, 0)
        if (self.n_beams is None) == (self.beams_dir is None):
            raise BeamInputError(
                f"beams = {self.n_beams!r}, beams_dir = {self.beams_dir!r}: give exactly one"
            )
        if self.n_beams is not None:
            _check_int("beams", self.n_beams, 1)
        i, n = self.shard
        _check_int("shard count", n, 1)
        if not (isinstance(i, int) and 0 <= i < n):
            raise BeamInputError(f"shard = {i}/{n}: the index must be in 0 .. {n - 1}")


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


def _check_int(name: str, value: Any, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise BeamInputError(f"{name} = {value!r}: must be an integer >= {minimum}")
    return value


def _check_choice(name: str, value: Any, choices: Sequence[str]) -> str:
    if value not in choices:
        raise BeamInputError(f"{name} = {value!r}: must be one of {', '.join(choices)}")
    return value


def parse_shard(text: str) -> tuple[int, int]:
    """Parse ``"i/N"`` into ``(i, N)`` with 0 <= i < N."""
    try:
        i_s, n_s = text.split("/")
        i, n = int(i_s), int(n_s)
    except ValueError:
        raise BeamInputError(f"shard = {text!r}: must be i/N, e.g. 0/4") from None
    if n < 1 or not 0 <= i < n:
        raise BeamInputError(f"shard = {text!r}: needs N >= 1 and 0 <= i < N")
    return i, n


# ------------------------------------------------------------------------------------------------
# Beams and per-beam work


def _beam_seed_sequence(seed: int, index: int):
    import numpy as np

    return np.random.SeedSequence(seed, spawn_key=(index,))


def beam_of(task: BeamTask) -> Beam:
    """The beam of a task: the file's beam, or random beam ``index`` of root seed ``seed``."""
    if task.beam is not None:
        return task.beam
    import numpy as np

    from .geometry import random_beam

    rng = np.random.default_rng(_beam_seed_sequence(task.seed, task.index))
    return random_beam(rng, name=task.name)


def fit_seed_of(task: BeamTask) -> int:
    """The fit seed of a task: first 32-bit word of its beam sequence's first child."""
    import numpy as np

    child = _beam_seed_sequence(task.seed, task.index).spawn(1)[0]
    return int(child.generate_state(1, dtype=np.uint32)[0])


def beam_features(beam: Beam) -> dict[str, float]:
    """Simple geometry features of a beam (for reports): widths in m, mass in kg.

    ``taper_ratio`` is the tip width over the root width; ``mean_width_m`` the planform area over
    the length.
    """
    L = beam.length_m
    root_w = 2.0 * float(beam.half_width_m[0])
    tip_w = 2.0 * float(beam.half_width_m[-1])
    return {
        "length_m": L,
        "thickness_m": beam.thickness_m,
        "root_width_m": root_w,
        "tip_width_m": tip_w,
        "taper_ratio": tip_w / root_w,
        "mean_width_m": beam.planform_area_m2 / L,
        "min_width_m": 2.0 * float(beam.half_width_m.min()),
        "max_width_m": 2.0 * float(beam.half_width_m.max()),
        "n_vertices": int(beam.x_m.size),
        "mass_kg": beam.mass_kg,
        "load_index": beam.load_index() if float(abs(beam.tip_force_N).max()) > 0 else 0.0,
    }


def _task_header(task: BeamTask) -> dict[str, Any]:
    s = task.settings
    # the arguments travel with the record (a resume that lost batch.json still checks them)
    args = {"joints": s.joints, "frequencies": s.n_frequencies, "objective": s.objective,
            "stiffness": s.stiffness, "starts": s.starts, "truth_model": s.truth_model,
            "eigen_norm": s.eigen_norm, "min_fraction": s.min_fraction}
    return {"beam_index": task.index, "beam_name": task.name, "seed": task.seed, **args}


def evaluate_beam(task: BeamTask) -> dict[str, Any]:
    """The default per-beam work: truth (cached) then fit; a flat JSON-ready record.

    An error inside the truth or the fit is part of the result (``status = "failed"``, with
    ``error`` and ``stage``); only interrupts and process deaths escape.
    """
    from .fitting import fit
    from .target import target_from_truth
    from .truth import TruthRequest

    t0 = time.perf_counter()
    s = task.settings
    rec = _task_header(task)
    rec["worker_pid"] = os.getpid()
    stage = "beam"
    try:
        beam = beam_of(task)
        rec.update(beam_features(beam))
        rec["fit_seed"] = fit_seed_of(task)
        stage = "truth"
        t1 = time.perf_counter()
        # the eigen objective needs no static solve
        request = TruthRequest(model=s.truth_model, modes=s.n_frequencies)
        truth = request.compute(beam, cache_dir=s.cache_dir, static=s.objective != "eigen")
        rec["truth_s"] = time.perf_counter() - t1
        stage = "fit"
        t2 = time.perf_counter()
        result = fit(beam, target_from_truth(truth, beam.tip_force_N, request), s.joints,
                     frequencies=s.frequencies, objective=s.objective, stiffness=s.stiffness,
                     starts=s.starts, seed=rec["fit_seed"], workers=1, progress=False,
                     min_fraction=s.min_fraction,
                     eigen_norm=s.eigen_norm)
        rec["fit_s"] = time.perf_counter() - t2
        rec.update(_fit_fields(result, beam.length_m))
        rec["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 -- a failed beam is a result, not a crash
        rec["status"] = "failed"
        rec["stage"] = stage
        rec["error"] = f"{type(exc).__name__}: {exc}"
    rec["wall_s"] = time.perf_counter() - t0
    rec["worker_peak_rss_mb"] = _peak_rss_mb()
    return rec


def _peak_rss_mb() -> float | None:
    # the worker's peak resident memory so far (Linux reports KiB, macOS bytes)
    try:
        import resource
        import sys
    except ImportError:  # not POSIX
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 1024**2 if sys.platform == "darwin" else peak / 1024


# One row per beam: the per-pose arrays (model frequencies, springs, per-mode errors) stay in
# fit.json territory; the per-pose eigen errors and factors are kept (their length is the pose
# count), and so are the worst per-mode error and the exported model's per-mode errors.
_FIT_KEYS = ("frequencies", "eigen_norm", "lengths_m", "stiffness_Nm_per_rad", "factors",
             "scf_mean", "omega_truth_rad_s", "eigen_errors_pct", "eigen_loss_pct",
             "worst_mode_error_pct", "omega_export_errors_pct", "worst_export_error_pct",
             "deflection_loss_pct", "displacement_loss_pct", "combined_loss_pct", "mac",
             "success", "nfev", "starts_run")


def _fit_fields(result: Any, length_m: float) -> dict[str, Any]:
    import numpy as np

    out: dict[str, Any] = {}
    for key in _FIT_KEYS:
        value = getattr(result, key, None)
        if value is None:
            continue
        arr = np.asarray(value)
        out[key] = arr.tolist() if arr.ndim else arr.item()
    lengths = np.asarray(result.lengths_m, dtype=float)
    out["gamma"] = (lengths / length_m).tolist()
    # The paper's "characteristic pivot": the first link's fraction of the length (Sec. 4.1.1).
    out["gamma_1"] = float(lengths[0] / length_m)
    return out


# ------------------------------------------------------------------------------------------------
# Planning and the manifest


def plan_tasks(spec: BatchSpec) -> list[BeamTask]:
    """Every beam of this run's shard, by ascending index.

    Beam files are read and validated here, before any work starts, and shipped to the workers
    (a cluster needs no shared file system).
    """
    i_shard, n_shard = spec.shard
    if spec.n_beams is not None:
        return [BeamTask(i, spec.seed, spec.settings, f"beam-{i}")
                for i in range(i_shard, spec.n_beams, n_shard)]
    from .geometry import load_beam

    folder = Path(spec.beams_dir)
    if not folder.is_dir():
        raise BeamInputError(f"beams_dir = {str(folder)!r}: not a folder")
    files = sorted(folder.glob("*.json"))
    if not files:
        raise BeamInputError(f"beams_dir = {str(folder)!r}: holds no *.json beam files")
    tasks = []
    for i, path in enumerate(files):
        if i % n_shard != i_shard:
            continue
        try:
            beam = load_beam(path)
        except BeamInputError as exc:
            raise BeamInputError(f"beam file {path.name}: {exc}") from None
        tasks.append(BeamTask(i, spec.seed, spec.settings, path.stem, beam))
    return tasks


def _manifest(spec: BatchSpec, tasks: Sequence[BeamTask]) -> dict[str, Any]:
    from . import __version__

    settings = asdict(spec.settings)
    settings.pop("cache_dir")
    if settings["min_fraction"] == 0.02:
        del settings["min_fraction"]  # the default: folders written before it existed resume
    m: dict[str, Any] = {
        "seed": spec.seed,
        "settings": settings,
        "shard": list(spec.shard),
        "source": "random" if spec.n_beams is not None else "files",
    }
    if spec.n_beams is not None:
        m["n_beams"] = spec.n_beams
    else:
        # the beams' content, not the folder's path, determines the results
        m["beams"] = [[t.name, t.beam.fingerprint()] for t in tasks]
    m["version"] = __version__
    return m


def _check_manifest(path: Path, wanted: dict[str, Any], jsonl: Path) -> None:
    from .batch_files import check_records_match, read_manifest, write_output

    if not path.exists():
        # records without their manifest: they still show the arguments they were made with
        check_records_match(read_records(jsonl), wanted, jsonl)
        write_output(path, json.dumps(wanted, indent=2) + "\n")
        return
    stored = read_manifest(path)
    for key in sorted(set(stored) | set(wanted)):
        if key == "version":
            if stored.get(key) != wanted.get(key):
                # allowed (a fix may be worth resuming with), but results then mix versions
                import warnings

                warnings.warn(f"{path} was written by prbdm_pin {stored.get(key)}; resuming "
                              f"with {wanted.get(key)} mixes versions in one study",
                              stacklevel=3)
            continue
        a, b = stored.get(key), wanted.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            for sub in sorted(set(a) | set(b)):
                if a.get(sub) != b.get(sub):
                    raise _mismatch(path, f"{key}.{sub}", a.get(sub), b.get(sub))
        elif a != b:
            shown = ("(different beam files)", "(different beam files)") if key == "beams" \
                else (a, b)
            raise _mismatch(path, key, *shown)


def _mismatch(path: Path, key: str, stored: Any, wanted: Any) -> BeamInputError:
    return BeamInputError(
        f"{key} = {wanted!r}: {path} was written for {key} = {stored!r}; resume with the same "
        f"arguments or use another output folder"
    )


# ------------------------------------------------------------------------------------------------
# The results file


def _clean(value: Any) -> Any:
    # JSON has no NaN or infinity: write null
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def record_to_json(record: dict[str, Any]) -> str:
    """One JSON line (no newline); NaN and infinities become null."""
    return json.dumps({k: _clean(v) for k, v in record.items()}, sort_keys=True, allow_nan=False)


def read_records(path: str | os.PathLike, *, repair: bool = False) -> list[dict[str, Any]]:
    """Every record of a ``results.jsonl``, in file order.

    A last line without its newline is what a crash mid-write leaves: it is ignored, and with
    ``repair=True`` cut from the file so the next append starts on a clean line.
    """
    p = Path(path)
    if not p.exists():
        return []
    data = p.read_bytes()
    end = data.rfind(b"\n") + 1
    if repair and end < len(data):
        with open(p, "r+b") as fh:
            fh.truncate(end)
            fh.flush()
            os.fsync(fh.fileno())
    from .batch_files import parse_record

    return [parse_record(line, f"{p} line {n}")
            for n, line in enumerate(data[:end].splitlines(), 1) if line.strip()]


def latest_records(records: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The last record of every beam, sorted by beam index."""
    last: dict[int, dict[str, Any]] = {}
    for rec in records:
        last[rec["beam_index"]] = rec
    return [last[i] for i in sorted(last)]


class _Writer:
    """Appends one JSON line per record, durably (flush + fsync), as each beam finishes."""

    def __init__(self, path: Path) -> None:
        self._fh = open(path, "a", encoding="utf-8")  # noqa: SIM115 -- closed by close()

    def write(self, record: dict[str, Any]) -> None:
        self._fh.write(record_to_json(record) + "\n")
        self._fh.flush()
        os.fsync(self._fh.fileno())

    def close(self) -> None:
        self._fh.close()


# the losses with the worst per-mode errors beside them, then the rest alphabetically
_LEADING = ("beam_index", "beam_name", "status", "seed", "fit_seed", "eigen_loss_pct",
            "worst_mode_error_pct", "worst_export_error_pct", "deflection_loss_pct",
            "displacement_loss_pct", "combined_loss_pct")


def _flat_row(rec: dict[str, Any]) -> dict[str, Any]:
    row: dict[str, Any] = {}
    for k, v in rec.items():
        if isinstance(v, list):
            for j, item in enumerate(v):
                row[f"{k}_{j}"] = item
        else:
            row[k] = v
    return row


def write_csv(records: Sequence[dict[str, Any]], path: str | os.PathLike) -> Path:
    """Write the latest record of each beam, sorted by index, as CSV (lists become ``key_j``
    columns), atomically."""
    from .batch_files import write_output

    rows = [_flat_row(r) for r in latest_records(records)]
    keys = {k for r in rows for k in r}
    lead = [k for k in _LEADING if k in keys]
    cols = lead + sorted(keys - set(lead), key=_column_order)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        # NaN is blank, as it reads back from the JSON line (null): a resume writes the same bytes
        w.writerow({k: ("" if _clean(r.get(k)) is None else r[k]) for k in cols})
    return write_output(path, buf.getvalue())


def _column_order(name: str) -> tuple[str, int]:
    base, _, idx = name.rpartition("_")
    return (base, int(idx)) if base and idx.isdigit() else (name, -1)


# ------------------------------------------------------------------------------------------------
# Executors


def _init_worker() -> None:
    """Pool initializer: one BLAS/OpenMP thread per worker (``workers.init_worker`` leaves
    Ctrl-C to the driver and ends the worker with it).

    It runs before the first task is unpickled, and this module does not import numpy, so the
    variables are set before BLAS loads (OpenBLAS reads them once, when it loads).
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
        _check_int("workers", workers, 1)
        _check_choice("mp_context", mp_context, ("spawn", "forkserver"))
        self.workers = workers
        self.mp_context = mp_context

    @property
    def slots(self) -> int:
        """Beams in flight at once."""
        return self.workers

    def executor(self, workers: int | None = None) -> cf.Executor:
        """A fresh pool (``workers`` processes, default ``self.workers``)."""
        from .workers import process_pool

        return process_pool(workers or self.workers,
                            multiprocessing.get_context(self.mp_context), _init_worker)

    def abort(self, executor: cf.Executor) -> None:
        """Stop now: cancel queued beams and end the running worker processes."""
        from .workers import stop_pool

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
        """The client's concurrent.futures executor."""
        return self.client.get_executor(pure=False)

    def abort(self, executor: cf.Executor) -> None:
        """Cancel every submitted beam."""
        executor.shutdown(wait=False)

    def close(self) -> None:
        """Close the client if this object opened it."""
        if self._owned:
            self.client.close()


# ------------------------------------------------------------------------------------------------
# The driver


@dataclass
class _Run:
    writer: _Writer
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
    return {**_task_header(task), "status": "failed", "stage": "worker", "error": reason}


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
    """
    t0 = time.perf_counter()
    backend = backend or LocalPool(1)
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise BeamInputError(f"out = {str(out)!r}: exists and is not a folder")
    tasks = plan_tasks(spec)  # the beam files are checked before OUT is made
    out.mkdir(parents=True, exist_ok=True)
    with _exclusive(out):
        jsonl = out / RESULTS_JSONL
        _check_manifest(out / MANIFEST, _manifest(spec, tasks), jsonl)
        records = read_records(jsonl, repair=True)
        wanted = {t.index for t in tasks}
        stray = sorted({r["beam_index"] for r in records} - wanted)
        if stray:
            raise BeamInputError(f"{jsonl}: holds beam {stray[0]}, which is not in this batch")
        done = {r["beam_index"] for r in latest_records(records)
                if r.get("status") == "ok" or not retry_failed}
        todo = [t for t in tasks if t.index not in done]
        from tqdm.auto import tqdm

        bar = tqdm(total=len(tasks), initial=len(tasks) - len(todo), unit="beam",
                   desc="batch", disable=not progress, dynamic_ncols=True)
        run = _Run(_Writer(jsonl), records, bar)
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
            write_csv(run.records, out / RESULTS_CSV)
            backend.close()
    return BatchSummary(out, len(tasks), len(tasks) - len(todo), run.n_ok, run.n_failed,
                        run.n_retried, time.perf_counter() - t0, interrupted)


def _drive(todo: Sequence[BeamTask], work: Callable, backend: Any, run: _Run) -> list[BeamTask]:
    """Run ``todo`` keeping ``backend.slots`` beams in flight; returns the beams that were in
    flight when a worker process died (to be retried)."""
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
    """Run each beam that was in flight when a worker died once more, alone in a fresh
    one-worker pool, so a beam that kills its worker again is identified and recorded failed."""
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
