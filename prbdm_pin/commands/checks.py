"""Checks of command-line options, run before any work starts.

Each command's ``run()`` starts with these: ranges of numbers (a refusal names the option, the
value and the range) and checks that an output folder or file can be written, so that a bad
``--out`` is refused before minutes of computation rather than after, and nothing is created on
refusal. The writability checks create nothing: they look at the nearest existing ancestor of
the path. :class:`CliParser` makes argparse's own errors one line as well.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import stat
import sys
from pathlib import Path

from ..errors import BeamInputError
from ..validate import MAX_SEED, MAX_WORKERS  # shared with the API

__all__ = ["CliParser", "one_line", "in_range", "writable_dir", "writable_file", "existing_dir",
           "MAX_SEED", "MAX_WORKERS"]

# Kernel and device trees: writing there fails (or, as root, does harm) after the work is done.
SYSTEM_ROOTS = ("/proc", "/sys", "/dev")

_ARG = re.compile(r"^argument (\S+): (.*)$", re.DOTALL)
# a value that starts like a negative number: -1:0.1, -10,0,0, -.5e3
_DASH_VALUE = re.compile(r"^-\.?\d")


def one_line(text: str) -> str:
    """``text`` with control characters (newlines of a hostile value ...) escaped: one line."""
    return "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in str(text))


class CliParser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line ``PROG: error: MESSAGE`` and exit code 2.

    argparse prints a usage block above the error; the rest of ``prbdm`` reports every refusal
    as one line, so scripts and logs see the same shape for all of them. ``--help`` is unchanged.
    """

    def parse_known_args(self, args=None, namespace=None):  # noqa: D102 - argparse's contract
        args = sys.argv[1:] if args is None else list(args)
        return super().parse_known_args(self._joined_dash_values(args), namespace)

    def _joined_dash_values(self, args: list[str]) -> list[str]:
        """Join ``--opt -1:0.1`` into ``--opt=-1:0.1`` for options that take one value.

        argparse reads a value starting with '-' that is not a plain negative number
        (``-1:0.1``, ``-10,0,0``) as an option and answers "expected one argument"; joined,
        the value reaches the option's own check, which names what is wrong with it.
        """
        out: list[str] = []
        i = 0
        while i < len(args):
            a = args[i]
            if a == "--":
                return out + args[i:]
            action = self._option_string_actions.get(a)
            if (action is not None and action.nargs is None and i + 1 < len(args)
                    and isinstance(args[i + 1], str) and _DASH_VALUE.match(args[i + 1])
                    and args[i + 1] not in self._option_string_actions):
                out.append(f"{a}={args[i + 1]}")
                i += 2
                continue
            out.append(a)
            i += 1
        return out

    def error(self, message: str):  # noqa: D102 - argparse's contract
        m = _ARG.match(message)
        if m:
            option, rest = m.groups()
            message = f"{option}: {rest}"
        self.exit(2, f"{self.prog}: error: {one_line(message)}\n")


def _num(x: float) -> str:
    if x == MAX_SEED:
        return "2**63 - 1"
    return str(x) if isinstance(x, int) else f"{x:g}"


def _bounds_text(lo, hi, lo_open, hi_open, integer) -> str:
    kind = "an integer" if integer else "a finite number"
    if integer and lo is not None and hi is not None and not (lo_open or hi_open):
        return f"must be {kind} in {lo}..{hi}"
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {_num(lo)}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {_num(hi)}")
    return f"must be {kind}" + (" " + " and ".join(parts) if parts else "")


def in_range(field: str, value: object, lo: float | None = None, hi: float | None = None, *,
             lo_open: bool = False, hi_open: bool = False, integer: bool = False,
             unit: str = "", why: str = "") -> None:
    """Refuse a number outside ``[lo, hi]``, a non-finite one, and a non-integer if asked.

    ``lo_open``/``hi_open`` exclude an end; None: no bound on that side; ``integer`` refuses a
    non-integer.

    Raises
    ------
    BeamInputError
        ``"--pop = 1: must be an integer >= 4"``: the option, the value, the range (``unit``
        and ``why`` appended).
    """
    want = _bounds_text(lo, hi, lo_open, hi_open, integer)
    want += f" ({unit})" if unit else ""
    want += f": {why}" if why else ""
    if value is None:
        return
    if integer:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) \
            and math.isfinite(value)
    if ok and lo is not None:
        ok = value > lo if lo_open else value >= lo
    if ok and hi is not None:
        ok = value < hi if hi_open else value <= hi
    if not ok:
        raise BeamInputError(f"{field} = {value!r}: {want}")


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
