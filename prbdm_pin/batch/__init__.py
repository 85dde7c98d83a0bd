"""Batch studies: many beams, each one truth (cached) plus one fit.

The beams run over a concurrent.futures executor (a local process pool by default; a Dask
cluster when asked).

Only the driver writes. Every finished beam becomes one JSON line appended to
``DIR/results.jsonl`` (flushed and fsynced), failures included with their error; at the end the
lines are consolidated, sorted by beam index, into ``DIR/results.csv`` (atomic). ``DIR/batch.json``
records the arguments that determine the results, so a rerun resumes (finished beams are skipped)
and a rerun with other arguments is refused; every record carries them too, so a folder that lost
its batch.json still refuses them. Both files are checked on read (``files``).

The parts: ``spec`` (what is computed, over which beams), ``work`` (one beam: truth + fit ->
record), ``records`` (results.jsonl and results.csv), ``manifest`` (batch.json), ``files`` (both
read back checked), ``executors`` (local pool, Dask), ``driver`` (run_batch), ``report`` (the
study's summary) and ``plots`` (its figures).

The package imports numpy only inside functions: a spawned worker imports it to unpickle the
pool initializer, which must set the BLAS thread variables before numpy loads its BLAS.
"""

from __future__ import annotations

from .driver import BatchSummary, run_batch
from .executors import DaskCluster, LocalPool
from .files import missing_shards, read_manifest
from .manifest import MANIFEST
from .records import (
    RESULTS_CSV,
    RESULTS_JSONL,
    RUN_DEPENDENT_FIELDS,
    latest_records,
    read_records,
    record_to_json,
)
from .report import BatchReport, load_study, missing_warning, summarise, to_markdown
from .spec import BatchSpec, BeamTask, FitSettings, parse_shard, plan_tasks
from .work import beam_features, beam_of, evaluate_beam, fit_seed_of

__all__ = [
    "FitSettings",
    "BatchSpec",
    "BeamTask",
    "BatchSummary",
    "LocalPool",
    "DaskCluster",
    "plan_tasks",
    "beam_of",
    "fit_seed_of",
    "beam_features",
    "evaluate_beam",
    "run_batch",
    "read_records",
    "record_to_json",
    "latest_records",
    "parse_shard",
    "read_manifest",
    "missing_shards",
    "load_study",
    "summarise",
    "missing_warning",
    "to_markdown",
    "BatchReport",
    "RESULTS_JSONL",
    "RESULTS_CSV",
    "MANIFEST",
    "RUN_DEPENDENT_FIELDS",
]
