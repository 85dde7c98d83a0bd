"""Output paths checked before anything is written, as the commands check ``--out``.

A path is refused, naming the field (the option or the argument), when it is a file where a
folder is wanted or a folder where a file is, lies under a file, in ``/proc``, ``/sys`` or
``/dev``, or below a folder this process cannot write. Nothing is created. The command line
and the public functions that write (``export_model``, ``save_fit``, ``save_beam``,
``run_batch``, the examples' ``--out``) share these checks.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import Any

from ..errors import BeamInputError
from ..options.validate import check_path

__all__ = ["SYSTEM_ROOTS", "writable_dir", "writable_file", "existing_dir", "check_out_file",
           "check_out_dir"]

SYSTEM_ROOTS = ("/proc", "/sys", "/dev")


def _absolute(path: str | os.PathLike, field: str) -> Path:
    text = os.fspath(path)
    if not isinstance(text, str) or text.strip() == "":
        raise BeamInputError(f"{field} = {text!r}: must be a path")
    if "\x00" in text:
        raise BeamInputError(f"{field} = {text!r}: a path cannot contain a NUL character")
    return Path(os.path.abspath(text))


def _under_system(p: Path) -> str | None:
    for candidate in (str(p), os.path.realpath(p)):
        for root in SYSTEM_ROOTS:
            if candidate == root or candidate.startswith(root + os.sep):
                return root
    return None


def _lstat(p: Path, field: str, shown: str):
    """``os.stat`` of ``p`` (following links), None if nothing is there."""
    try:
        return os.stat(p)
    except FileNotFoundError:
        if os.path.islink(p):
            raise BeamInputError(f"{field} = {shown!r}: {p} is a broken symbolic link") from None
        return None
    except NotADirectoryError:
        return None  # a file further up: found while walking up
    except OSError as exc:
        raise BeamInputError(f"{field} = {shown!r}: cannot be used ({exc.strerror})") from None


def writable_dir(path: str | os.PathLike, field: str) -> Path:
    """Check that ``path`` is, or can be created as, a folder this process can write into.

    Nothing is created. Refused: a path that is a file, lies under a file, lies in ``/proc``,
    ``/sys`` or ``/dev``, or whose nearest existing folder is not writable.

    Returns
    -------
    Path
        The absolute path.

    Raises
    ------
    BeamInputError
        Naming ``field`` (the option, e.g. ``"--out"``) and the value.
    """
    shown = os.fspath(path)
    p = _absolute(path, field)
    root = _under_system(p)
    if root is not None:
        raise BeamInputError(f"{field} = {shown!r}: lies in {root}, a system folder: "
                             "give a folder for results")
    return _dir_ok(p, p, field, shown)


def _dir_ok(p: Path, target: Path, field: str, shown: str) -> Path:
    """``p`` is or can become a folder (``target``: the path the user gave, for messages)."""
    cur = p
    while True:
        st = _lstat(cur, field, shown)
        if st is not None:
            break
        if cur.parent == cur:
            raise BeamInputError(f"{field} = {shown!r}: no existing folder above it")
        cur = cur.parent
    if not stat.S_ISDIR(st.st_mode):
        where = "is a file, not a folder" if cur == target else \
            f"lies under {cur}, which is a file"
        raise BeamInputError(f"{field} = {shown!r}: {where}")
    if not os.access(cur, os.W_OK | os.X_OK):
        what = "is not writable" if cur == target else \
            f"cannot be created: {cur} is not writable"
        raise BeamInputError(f"{field} = {shown!r}: {what}")
    return target


def writable_file(path: str | os.PathLike, field: str) -> Path:
    """Check that ``path`` names a file that can be written (atomically, beside itself).

    Refused: an existing folder, a path ending in a separator, a device, FIFO or socket, and
    anything :func:`writable_dir` refuses for the folder it goes into. Nothing is created.
    """
    shown = os.fspath(path)
    p = _absolute(path, field)
    if isinstance(shown, str) and (shown.endswith(os.sep) or shown.endswith(os.sep + ".")
                                   or Path(shown).name in ("", ".", "..")):
        raise BeamInputError(f"{field} = {shown!r}: names a folder; give a file name")
    root = _under_system(p)
    if root is not None:
        raise BeamInputError(f"{field} = {shown!r}: lies in {root}, a system folder: "
                             "give a file for results")
    st = _lstat(p, field, shown)
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise BeamInputError(f"{field} = {shown!r}: is a folder; give a file name")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise BeamInputError(f"{field} = {shown!r}: is not a regular file")
    if st is not None and not os.access(p.parent, os.W_OK | os.X_OK):
        raise BeamInputError(f"{field} = {shown!r}: its folder {p.parent} is not writable")
    return _dir_ok(p.parent, p, field, shown)


def existing_dir(path: str | os.PathLike, field: str) -> Path:
    """Check that ``path`` is an existing, readable folder (an input)."""
    shown = os.fspath(path)
    p = _absolute(path, field)
    st = _lstat(p, field, shown)
    if st is None:
        raise BeamInputError(f"{field} = {shown!r}: no such folder")
    if not stat.S_ISDIR(st.st_mode):
        raise BeamInputError(f"{field} = {shown!r}: is not a folder")
    if not os.access(p, os.R_OK | os.X_OK):
        raise BeamInputError(f"{field} = {shown!r}: is not readable")
    return p


def check_out_file(name: str, value: Any) -> Path:
    """Check that ``value`` names a file that can be written, as ``prbdm export --out`` does.

    Refused before anything is written: a wrong type, an existing folder, a path under a file,
    in ``/proc``, ``/sys`` or ``/dev``, or in a folder that cannot be written.
    """
    return writable_file(check_path(name, value), name)


def check_out_dir(name: str, value: Any) -> Path:
    """Check that ``value`` is, or can be created as, a folder to write results into.

    As ``--out`` of the commands: refused before anything is made are a wrong type, a path
    that is a file or lies under one, in ``/proc``, ``/sys`` or ``/dev``, or below a folder
    that cannot be written. Nothing is created.
    """
    return writable_dir(check_path(name, value, "output folder"), name)
