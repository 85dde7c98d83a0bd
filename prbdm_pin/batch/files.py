"""The files of a batch folder as data, checked on read.

``batch.json`` and ``results.jsonl`` checked on read, the arguments a resume must share with
the records already there, and one file mode.

A batch folder outlives the process that wrote it: it is copied between machines, merged from
shards, edited, truncated by a full disk. Every defect found here is a BeamInputError that names
the file, the line and the field. This module imports no numpy (the batch driver's workers
import the batch package before BLAS is pinned).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from ..errors import BeamInputError
from ..io.jsonfile import field_int, field_str, parse_json, read_json, require_mapping
from ..options.choices import MIN_FRACTION

__all__ = [
    "read_manifest", "parse_record", "check_records_match", "missing_shards", "output_mode",
    "write_output", "CLI_OPTION", "STAMPED",
]

# The option that sets each argument a batch records (settings keys, then the top level).
CLI_OPTION = {
    "joints": "--joints", "frequencies": "--frequencies", "objective": "--objective",
    "stiffness": "--stiffness", "starts": "--starts", "truth_model": "--truth-model",
    "eigen_norm": "--eigen-norm", "min_fraction": "--min-link", "seed": "--seed",
    "n_beams": "--beams", "beams": "--beams-dir", "source": "--beams/--beams-dir",
    "shard": "--shard",
}

# The arguments every record carries besides its seed: a resume that lost batch.json can still
# tell records of another batch.
STAMPED = ("joints", "frequencies", "objective", "stiffness", "starts", "truth_model",
           "eigen_norm", "min_fraction")

# Record fields that are numbers (or null, written for NaN); lists of numbers (or nulls).
_NUMBERS = frozenset({
    "length_m", "thickness_m", "root_width_m", "tip_width_m", "taper_ratio", "mean_width_m",
    "min_width_m", "max_width_m", "n_vertices", "mass_kg", "load_index", "fit_seed", "truth_s",
    "fit_s", "wall_s", "worker_peak_rss_mb", "scf_mean", "eigen_loss_pct",
    "worst_mode_error_pct", "worst_export_error_pct", "deflection_loss_pct",
    "displacement_loss_pct", "combined_loss_pct", "nfev", "starts_run", "gamma_1", "frequencies",
    "attempts", "worker_pid", "joints", "starts", "min_fraction",
})
_NUMBER_LISTS = frozenset({
    "lengths_m", "stiffness_Nm_per_rad", "factors", "omega_truth_rad_s", "eigen_errors_pct",
    "omega_export_errors_pct", "gamma", "mac",
})
_STRINGS = frozenset({"beam_name", "status", "stage", "error", "eigen_norm", "objective",
                      "stiffness", "truth_model"})


def _is_number(v: Any) -> bool:
    return v is None or (not isinstance(v, bool) and isinstance(v, (int, float)))


def read_manifest(path: str | os.PathLike) -> dict[str, Any]:
    """``batch.json`` checked: an object whose recorded arguments have their types.

    Parameters
    ----------
    path : path
        The manifest file.

    Returns
    -------
    dict
        The manifest as stored.
    """
    what = f"batch.json {str(path)!r}"
    m = require_mapping(read_json(path, "batch.json"), what)
    if "seed" in m:
        field_int(f"{what}: seed", m["seed"], minimum=0)
    settings = require_mapping(m.get("settings", {}), f"{what}: settings")
    for key in ("joints", "starts"):
        if key in settings:
            field_int(f"{what}: settings.{key}", settings[key], minimum=1)
    if settings.get("frequencies") is not None:
        field_int(f"{what}: settings.frequencies", settings["frequencies"], minimum=1)
    for key in ("objective", "stiffness", "truth_model", "eigen_norm"):
        if key in settings:
            field_str(f"{what}: settings.{key}", settings[key])
    if "shard" in m:
        shard = m["shard"]
        if not (isinstance(shard, list) and len(shard) == 2
                and all(isinstance(v, int) and not isinstance(v, bool) for v in shard)
                and shard[1] >= 1 and 0 <= shard[0] < shard[1]):
            raise BeamInputError(f"{what}: shard = {shard!r}: must be [i, N] with 0 <= i < N")
    if "n_beams" in m:
        field_int(f"{what}: n_beams", m["n_beams"], minimum=1)
    if "source" in m:
        field_str(f"{what}: source", m["source"])
    if "beams" in m and not (isinstance(m["beams"], list) and all(
            isinstance(b, list) and len(b) == 2 and all(isinstance(s, str) for s in b)
            for b in m["beams"])):
        raise BeamInputError(f"{what}: beams: must be a list of [name, fingerprint] pairs")
    return m


def parse_record(raw: bytes, where: str) -> dict[str, Any]:
    """One line of ``results.jsonl`` as a checked record; ``where`` ("FILE line N") names it."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BeamInputError(f"{where}: not UTF-8 text ({exc.reason} at byte {exc.start})"
                             ) from None
    # the depth scan is skipped: a line is flat and a deep one fails as a RecursionError
    rec = parse_json(text, where, scan_depth=False)
    if not isinstance(rec, dict) or not isinstance(rec.get("beam_index"), int) \
            or isinstance(rec.get("beam_index"), bool) or rec["beam_index"] < 0:
        raise BeamInputError(f"{where}: not a beam record (no integer beam_index >= 0)")
    for key, value in rec.items():
        if key in _NUMBERS and not _is_number(value):
            raise BeamInputError(f"{where}: {key} = {value!r:.60}: must be a number or null")
        if key in _NUMBER_LISTS and not (isinstance(value, list)
                                         and all(_is_number(v) for v in value)):
            raise BeamInputError(f"{where}: {key} = {value!r:.60}: must be a list of numbers")
        if key in _STRINGS and not isinstance(value, str):
            raise BeamInputError(f"{where}: {key} = {value!r:.60}: must be a string")
    if "seed" in rec:
        field_int(f"{where}: seed", rec["seed"], minimum=0)
    return rec


def _recorded(rec: Mapping[str, Any]) -> dict[str, Any]:
    # the arguments a record shows: stamped by the driver, or implied by the fit itself
    got = {k: rec[k] for k in (*STAMPED, "seed") if k in rec}
    if "joints" not in got and isinstance(rec.get("lengths_m"), list) and rec["lengths_m"]:
        got["joints"] = len(rec["lengths_m"]) - 1
    return got


def check_records_match(records: Iterable[Mapping[str, Any]], manifest: Mapping[str, Any],
                        where: str | os.PathLike) -> None:
    """Refuse records computed with other arguments than ``manifest``.

    This catches a resume whose ``batch.json`` was lost; the message names the option.

    Parameters
    ----------
    records : iterable of dict
        Records already in the folder.
    manifest : dict
        The manifest of this run (what ``batch.json`` would say).
    where : path
        The results file, for the message.
    """
    s = manifest["settings"]
    wanted = {**s, "min_fraction": s.get("min_fraction", MIN_FRACTION), "seed": manifest["seed"],
              "frequencies": s["joints"] if s.get("frequencies") is None else s["frequencies"]}
    for rec in records:
        for key, value in _recorded(rec).items():
            if key in wanted and value != wanted[key]:
                option = CLI_OPTION.get(key, key)
                raise BeamInputError(
                    f"{option} = {wanted[key]!r}: {where} holds beam {rec['beam_index']} "
                    f"computed with {option} = {value!r} (and no batch.json); resume with the "
                    f"same arguments or use another output folder")


def missing_shards(shards: Iterable[tuple[int, int]]) -> tuple[int, list[int]]:
    """Return the shard count N and the shard indices absent from ``shards`` (pairs ``(i, N)``).

    Raises
    ------
    BeamInputError
        When the shards disagree on N.
    """
    shards = list(shards)
    counts = sorted({n for _, n in shards})
    if len(counts) > 1:
        raise BeamInputError(f"shard = {shards!r}: the folders were split into different "
                             f"shard counts {counts}: not shards of one study")
    n = counts[0] if counts else 1
    return n, sorted(set(range(n)) - {i for i, _ in shards})


def output_mode() -> int:
    """Return the mode of a file the package writes: 0o666 less the umask (0o644 under 022)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # no /proc: read it by setting it (and restore at once)
    os.umask(mask)
    return 0o666 & ~mask


def write_output(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically with :func:`output_mode`.

    A file that already holds exactly ``text`` is left alone (a resume with nothing to do
    changes nothing).
    """
    from ..io.atomic import atomic_write_text

    p = Path(path)
    data = text.encode("utf-8")
    try:
        if p.is_file() and p.stat().st_size == len(data) and p.read_bytes() == data:
            return p
    except OSError:
        pass
    atomic_write_text(p, text)
    os.chmod(p, output_mode())
    return p
