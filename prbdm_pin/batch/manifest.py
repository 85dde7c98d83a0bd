"""``batch.json``: the arguments that determine a batch's results.

Written by the first run and checked by every resume (field by field, naming the one that
differs).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import BeamInputError
from ..options.objects import FitOptions
from .files import check_records_match, read_manifest, write_output
from .records import read_records
from .spec import BatchSpec, BeamTask

__all__ = ["MANIFEST", "build_manifest", "check_manifest"]

MANIFEST = "batch.json"


def build_manifest(spec: BatchSpec, tasks: Sequence[BeamTask]) -> dict[str, Any]:
    """Return what ``batch.json`` records for ``spec`` (``tasks``: from :func:`plan_tasks`)."""
    from ..version import __version__

    s = spec.settings
    o = s.options
    settings: dict[str, Any] = {
        "joints": s.joints, "frequencies": o.frequencies, "objective": o.objective.value,
        "stiffness": o.stiffness.value, "starts": o.starts, "truth_model": s.truth_model,
        "eigen_norm": o.eigen_norm.value}
    # every other option only where it is not the default, so that folders written before it
    # could be set resume (the fit seed is each beam's own, not an option of the batch)
    default = FitOptions().to_dict()
    for key, value in o.to_dict().items():
        if key not in settings and key not in ("kind", "seed") and value != default[key]:
            settings[key] = value
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


def check_manifest(path: Path, wanted: dict[str, Any], jsonl: Path) -> None:
    """Refuse a folder made with other arguments than ``wanted`` (naming the field).

    A folder without ``batch.json`` has its records in ``jsonl`` checked, then gets one.
    """
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
