"""On-disk cache of truth results, keyed by a hash of every input that changes the answer.

The key covers the beam's physical content (``Beam.fingerprint``), the model, mesh level, mode
count, selection policy, static options, the package version and a digest of the code the truth
depends on (``truth.digest``: the truth package and every package module it imports, and the
numerical libraries' versions), so edited code never serves results computed by the code it
replaced.

An entry ``truth-<key>.npz`` is data only: an uncompressed NPZ of numeric arrays (read with
``allow_pickle=False``) plus one member holding UTF-8 JSON metadata (format, key, beam
fingerprint, the scalar fields and a SHA-256 checksum of the metadata and every array). On load
the format, key, fingerprint and checksum are verified and every field is type-checked; any
mismatch (an entry edited in place, copied from another key or beam, truncated, of another
format) is a miss: it is recomputed with a :class:`TruthCacheWarning` naming the entry, never
served. Entries are written to a temporary file (``.truth-<pid>-<random>.tmp``) and renamed into
place, so a crashed or concurrent writer never leaves a half-written entry; the temporary files
a killed writer leaves are removed by the next lookup once stale (``truth.cache_clean``: an hour
old, or their writer gone). Entries of older versions (``truth-*.pkl``
pickles) are never opened.
"""

from __future__ import annotations

import hashlib
import json
import warnings
import zipfile
from pathlib import Path

import numpy as np

from ..io.atomic import AtomicFile
from ..member.geometry import Beam
from .cache_clean import clean_stale, temp_prefix
from .digest import code_digest
from .entry import EntryError, check_truth, decode, encode
from .result import TruthResult

__all__ = ["FORMAT", "TruthCacheWarning", "cache_key", "code_digest", "entry_path",
           "entry_checksum", "load_cached", "store_cached"]

FORMAT = "prbdm_pin truth cache 1"
_META = "__meta__"


class TruthCacheWarning(UserWarning):
    """A cache entry was refused (and the truth recomputed)."""


def cache_key(beam: Beam, **inputs) -> str:
    """Return the cache key: a SHA-256 hex digest of the beam and the inputs.

    It digests the beam fingerprint, the keyword inputs (JSON-serialisable) and
    :func:`code_digest`.
    """
    payload = json.dumps({"beam": beam.fingerprint(), "code": code_digest(), **inputs},
                         sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()


def entry_path(cache_dir, key: str) -> Path:
    """Return the file of the entry ``key`` in ``cache_dir``."""
    return Path(cache_dir) / f"truth-{key}.npz"


def entry_checksum(meta: dict, arrays: dict[str, np.ndarray]) -> str:
    """Return the checksum of an entry: SHA-256 of its metadata and arrays.

    The metadata without its checksum, and every array's name, dtype, shape and bytes.
    """
    h = hashlib.sha256()
    body = {k: v for k, v in meta.items() if k != "checksum"}
    h.update(json.dumps(body, sort_keys=True).encode())
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"\0{name}\0{a.dtype.str}\0{a.shape}\0".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _refuse(path: Path, why: str) -> None:
    warnings.warn(f"truth cache entry {str(path)!r} refused ({why}): recomputing the truth",
                  TruthCacheWarning, stacklevel=3)


def _read_entry(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    """Metadata and arrays of the entry file (EntryError when it is not one)."""
    size = path.stat().st_size
    try:
        with zipfile.ZipFile(path) as zf:
            infos = zf.infolist()
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:
        raise EntryError(f"not an NPZ file ({exc})") from None
    for info in infos:
        # stored members only: an entry cannot inflate beyond its size on disk
        if info.compress_type != zipfile.ZIP_STORED or not info.filename.endswith(".npy"):
            raise EntryError(f"member {info.filename!r} is not a stored .npy array")
    if sum(i.file_size for i in infos) > size:
        raise EntryError("members larger than the file")
    arrays: dict[str, np.ndarray] = {}
    try:
        with np.load(path, allow_pickle=False) as npz:
            for name in npz.files:
                arrays[name] = npz[name]
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        raise EntryError(f"unreadable array data ({exc})") from None
    raw = arrays.pop(_META, None)
    if raw is None or raw.dtype != np.uint8 or raw.ndim != 1:
        raise EntryError("no metadata")
    try:
        meta = json.loads(raw.tobytes().decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise EntryError(f"metadata is not JSON ({exc})") from None
    if not isinstance(meta, dict):
        raise EntryError("metadata is not a JSON object")
    return meta, arrays


def load_cached(cache_dir, key: str, beam_fingerprint: str) -> TruthResult | None:
    """Return the cached result for ``key`` or None.

    A missing entry is a silent miss; an entry that fails any check (format, key, beam
    fingerprint, checksum, field types, shapes) is a miss with a :class:`TruthCacheWarning`.
    """
    clean_stale(cache_dir)  # what killed writers left behind (truth.cache_clean)
    path = entry_path(cache_dir, key)
    if not path.is_file():
        return None
    try:
        meta, arrays = _read_entry(path)
        if meta.get("format") != FORMAT:
            raise EntryError(f"format {meta.get('format')!r}, expected {FORMAT!r}")
        if meta.get("key") != key:
            raise EntryError(f"written for key {str(meta.get('key'))[:16]}..., not this key "
                             f"{key[:16]}...")
        if meta.get("beam_fingerprint") != beam_fingerprint:
            raise EntryError(f"written for beam fingerprint "
                             f"{str(meta.get('beam_fingerprint'))[:16]}..., not this beam's "
                             f"{beam_fingerprint[:16]}...")
        if meta.get("checksum") != entry_checksum(meta, arrays):
            raise EntryError("checksum mismatch: the entry was changed after it was written")
        result = decode("TruthResult", meta.get("result"), arrays)
        if result.beam_fingerprint != beam_fingerprint:
            raise EntryError("result.beam_fingerprint is another beam's")
        check_truth(result)
    except EntryError as exc:
        _refuse(path, str(exc))
        return None
    except OSError as exc:
        _refuse(path, f"cannot be read: {exc.strerror or exc}")
        return None
    return result


def store_cached(cache_dir, key: str, result: TruthResult) -> Path | None:
    """Write ``result`` under ``key`` atomically.

    Returns the path, or None (with a :class:`TruthCacheWarning`) when the folder cannot take
    it: the truth is still returned.
    """
    arrays: dict[str, np.ndarray] = {}
    meta = {"format": FORMAT, "key": key, "beam_fingerprint": result.beam_fingerprint,
            "result": encode(result, arrays)}
    meta["checksum"] = entry_checksum(meta, arrays)
    blob = np.frombuffer(json.dumps(meta, sort_keys=True).encode("utf-8"), dtype=np.uint8)
    d = Path(cache_dir)
    try:
        d.mkdir(parents=True, exist_ok=True)
        staged = AtomicFile(entry_path(d, key), "wb", fsync=True, prefix=temp_prefix())
    except OSError as exc:
        _not_stored(d, exc)
        return None
    try:
        with staged as fh:
            np.savez(fh, **{_META: blob}, **arrays)
    except OSError as exc:
        _not_stored(entry_path(d, key), exc)
        return None
    return entry_path(d, key)


def _not_stored(where: Path, exc: OSError) -> None:
    warnings.warn(f"truth not cached: {str(where)!r}: {exc.strerror or exc}",
                  TruthCacheWarning, stacklevel=3)
