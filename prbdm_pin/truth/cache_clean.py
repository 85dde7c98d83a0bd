"""Stale temporary files of the truth cache: what a killed writer left behind, removed.

An entry is written to ``.truth-<pid>-<random>.tmp`` in the cache folder and renamed into place
(``truth.cache.store_cached``). A writer killed in between (a batch stopped with SIGKILL, a
machine that lost power) leaves the temporary file; nothing would ever remove it. Every lookup
of the cache (:func:`~prbdm_pin.truth.cache.load_cached`) first removes the temporary files that
are stale:

* older than ``STALE_AFTER_S`` (an hour; an entry is written in well under a second), or
* whose writer, named by the process id in the file name, no longer runs on this machine.

A live writer's file is neither old nor orphaned, so it is left alone. In a folder shared by
several machines the process id is checked on this machine only: a file of a writer that runs
elsewhere is removed only once an hour old. Files named as older versions wrote them
(``.truth-<random>.tmp``, no process id) are removed by age.
"""

from __future__ import annotations

import os
import re
import time
from pathlib import Path

__all__ = ["STALE_AFTER_S", "TEMP_PREFIX", "temp_prefix", "clean_stale"]

STALE_AFTER_S = 3600.0
TEMP_PREFIX = ".truth-"
_TEMP = re.compile(r"^\.truth-(?:(\d+)-)?[0-9a-f]+\.tmp$")


def temp_prefix() -> str:
    """Return the prefix of this process's temporary entry files, ``.truth-<pid>-``."""
    return f"{TEMP_PREFIX}{os.getpid()}-"


def _running(pid: int) -> bool:
    """Whether a process ``pid`` runs on this machine (one of another user's counts)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # another user's process, or a pid this system cannot hold: keep it
    return True


def clean_stale(cache_dir, now: float | None = None) -> list[Path]:
    """Remove the stale temporary files in ``cache_dir``; return those removed.

    Stale: older than ``STALE_AFTER_S`` or written by a process that no longer runs (see the
    module notes). A folder that does not exist or cannot be read is left as it is.
    """
    now = time.time() if now is None else now
    removed = []
    try:
        entries = list(os.scandir(cache_dir))
    except OSError:
        return removed
    for entry in entries:
        m = _TEMP.match(entry.name)
        if m is None:
            continue
        try:
            age = now - entry.stat(follow_symlinks=False).st_mtime
        except OSError:
            continue  # renamed into place meanwhile
        orphan = m.group(1) is not None and not _running(int(m.group(1)))
        if not (orphan or age > STALE_AFTER_S):
            continue
        try:
            os.unlink(entry.path)
        except OSError:
            continue
        removed.append(Path(entry.path))
    return removed
