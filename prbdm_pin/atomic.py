"""Temporary files for atomic writes, created with the mode of any other new file.

``tempfile.mkstemp`` creates 0600 files, so every output renamed into place from one stayed 0600
while files opened normally got 0644 (under umask 022). ``mkstemp`` here asks for 0666 and lets the
umask decide, as ``open(path, "w")`` does: one file mode for every output of the package.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path

__all__ = ["mkstemp"]


def mkstemp(dir: str | os.PathLike, prefix: str = ".", suffix: str = ".tmp") -> tuple[int, str]:
    """Create a new file ``dir/prefix<random>suffix`` for writing, mode 0666 & ~umask.

    Returns the open file descriptor and the path, like ``tempfile.mkstemp``.
    """
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        path = str(Path(dir) / f"{prefix}{secrets.token_hex(6)}{suffix}")
        try:
            return os.open(path, flags, 0o666), path
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name in {str(dir)!r}")
