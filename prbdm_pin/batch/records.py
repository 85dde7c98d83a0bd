"""``results.jsonl`` and ``results.csv``: the records of a batch.

One JSON line per finished beam (appended durably), read back checked, and consolidated into a
CSV of the latest record of each beam.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from .files import parse_record, write_output

__all__ = ["RESULTS_JSONL", "RESULTS_CSV", "RUN_DEPENDENT_FIELDS", "record_to_json",
           "read_records", "latest_records", "RecordWriter", "write_csv"]

RESULTS_JSONL = "results.jsonl"
RESULTS_CSV = "results.csv"
# Fields that describe a run rather than its result: they legitimately differ between two runs.
RUN_DEPENDENT_FIELDS = frozenset({"wall_s", "truth_s", "fit_s", "attempts", "worker_pid",
                                  "worker_peak_rss_mb"})


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
    return [parse_record(line, f"{p} line {n}")
            for n, line in enumerate(data[:end].splitlines(), 1) if line.strip()]


def latest_records(records: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """Return the last record of every beam, sorted by beam index."""
    last: dict[int, dict[str, Any]] = {}
    for rec in records:
        last[rec["beam_index"]] = rec
    return [last[i] for i in sorted(last)]


class RecordWriter:
    """Appends one JSON line per record, durably (flush + fsync), as each beam finishes."""

    def __init__(self, path: Path) -> None:
        self._fh = open(path, "a", encoding="utf-8")  # noqa: SIM115 -- closed by close()

    def write(self, record: dict[str, Any]) -> None:
        """Append ``record`` as one JSON line, flushed and fsynced."""
        self._fh.write(record_to_json(record) + "\n")
        self._fh.flush()
        os.fsync(self._fh.fileno())

    def close(self) -> None:
        """Close the file."""
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
    """Write the latest record of each beam, sorted by index, as CSV, atomically.

    Lists become ``key_j`` columns.
    """
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
