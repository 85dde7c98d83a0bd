"""Atomic writes: every file the package writes appears whole or not at all, mode 0666 & ~umask.

A file is written to a temporary name in its own folder and renamed over the target, so a killed
run never leaves a half-written output. ``tempfile.mkstemp`` would create the temporary file 0600,
and every output renamed into place from one stayed 0600 while files opened normally got 0644
(under umask 022); the temporary file here asks for 0666 and lets the umask decide, as
``open(path, "w")`` does: one file mode for every output of the package.
"""

from __future__ import annotations

import json
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

__all__ = [
    "AtomicFile", "atomic_path", "atomic_write_bytes", "atomic_write_json", "atomic_write_text",
]


def _temporary(folder: Path, prefix: str) -> tuple[int, str]:
    """Create a new file ``folder/<prefix><random>.tmp`` open for writing, mode 0666 & ~umask."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        path = str(folder / f"{prefix}{secrets.token_hex(6)}.tmp")
        try:
            return os.open(path, flags, 0o666), path
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name in {str(folder)!r}")


def _discard(tmp: str) -> None:
    if os.path.exists(tmp):
        os.unlink(tmp)


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[str]:
    """Yield a temporary path to write ``path`` through, for writers that take a file name.

    For ``savefig``, ``meshio.write`` and the like: the temporary file is renamed over ``path``
    when the block ends without error, removed in any case. The folder is created when missing.
    """
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = _temporary(p.parent, f".{p.name}.")
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, p)
    finally:
        _discard(tmp)


class AtomicFile:
    """``with AtomicFile(path, "wb") as fh:`` writes ``path`` atomically through an open file.

    The temporary file is created by the constructor (so a folder that cannot take it fails
    there, before anything is written); the rename happens when the block ends without error,
    after an ``fsync`` when ``fsync`` is set (a cache entry must survive a power cut whole).
    The temporary name is ``.<name>.<random>.tmp`` unless ``prefix`` replaces ``.<name>.``.
    """

    def __init__(self, path: str | os.PathLike, mode: str = "w", *, fsync: bool = False,
                 prefix: str | None = None) -> None:
        if mode not in ("w", "wb"):
            raise ValueError(f"mode = {mode!r}: must be 'w' or 'wb'")
        self.path = Path(path)
        self._mode, self._fsync = mode, fsync
        self._fd, self._tmp = _temporary(self.path.parent, prefix or f".{self.path.name}.")
        self._file: Any = None

    def __enter__(self) -> IO[Any]:
        """Open the temporary file and return it; on failure it is removed."""
        kw = {"encoding": "utf-8"} if self._mode == "w" else {}
        try:
            self._file = os.fdopen(self._fd, self._mode, **kw)
            return self._file.__enter__()
        except BaseException:
            if self._file is None:
                os.close(self._fd)
            _discard(self._tmp)
            raise

    def __exit__(self, exc_type, exc, tb) -> None:
        """Close the file and, without an exception, rename it over ``path``."""
        try:
            try:
                if exc_type is None and self._fsync:
                    self._file.flush()
                    os.fsync(self._file.fileno())
            finally:
                self._file.__exit__(exc_type, exc, tb)  # closes the file
            if exc_type is None:
                os.replace(self._tmp, self.path)
        finally:
            _discard(self._tmp)


def _write(path: str | os.PathLike, data: str | bytes, mode: str) -> Path:
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with AtomicFile(p, mode) as fh:
        fh.write(data)
    return p


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (the folder is created when missing)."""
    return _write(path, data, "wb")


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (the folder is created when missing)."""
    return _write(path, text, "w")


def atomic_write_json(path: str | os.PathLike, obj: Any, indent: int = 2) -> Path:
    """Write ``obj`` as JSON (``indent`` spaces, a final newline) to ``path`` atomically."""
    return atomic_write_text(path, json.dumps(obj, indent=indent) + "\n")
