"""On-disk cache of truth results, keyed by a hash of every input that changes the answer.

The key covers the beam's physical content (``Beam.fingerprint``), the model, mesh level, mode
count, selection policy, static options, the package version and a digest of the truth code
itself (every module of this package), so an edited mesh or solver never serves results computed
by the code it replaced. Entries are pickles of the frozen
``TruthResult`` written atomically (temporary file + ``os.replace``), so a crashed or concurrent
writer never leaves a half-written entry.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import pickle
import tempfile
from pathlib import Path

from ..geometry import Beam
from .result import TruthResult

__all__ = ["cache_key", "load_cached", "store_cached"]


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 hex digest of the source of every module of the truth package."""
    h = hashlib.sha256()
    for path in sorted(Path(__file__).resolve().parent.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def cache_key(beam: Beam, **inputs) -> str:
    """SHA-256 hex digest of the beam fingerprint, the keyword inputs (JSON-serialisable) and
    :func:`code_digest`."""
    payload = json.dumps({"beam": beam.fingerprint(), "code": code_digest(), **inputs},
                         sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()


def _path(cache_dir, key: str) -> Path:
    return Path(cache_dir) / f"truth-{key}.pkl"


def load_cached(cache_dir, key: str) -> TruthResult | None:
    """The cached result for ``key`` or None (a corrupt entry counts as a miss)."""
    path = _path(cache_dir, key)
    if not path.is_file():
        return None
    try:
        with open(path, "rb") as fh:
            obj = pickle.load(fh)
    except Exception:  # noqa: BLE001 - any unreadable entry is recomputed
        return None
    return obj if isinstance(obj, TruthResult) else None


def store_cached(cache_dir, key: str, result: TruthResult) -> Path:
    """Write ``result`` under ``key`` atomically; returns the path."""
    d = Path(cache_dir)
    d.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".truth-", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(result, fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, _path(d, key))
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return _path(d, key)
