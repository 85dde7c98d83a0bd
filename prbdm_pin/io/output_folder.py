"""Whole-folder outputs: a command's files appear in ``--out`` all together or not at all.

``with output_folder(out, OWNED) as stage:`` gives a new folder ``.OUT.staging-XXXX`` beside
OUT (same filesystem) for the command to write every file into. On success the staged folder
and OUT are exchanged in one ``renameat2(RENAME_EXCHANGE)`` call, so a reader sees either the
whole old set or the whole new one (where the filesystem cannot exchange, OUT is renamed aside
first: for a moment there is no OUT, never a mix). On an exception or KeyboardInterrupt the staged
folder is removed and OUT is left as it was.

What the new OUT keeps of the old one: every entry the command does not own (``owned``: the
names it may write) is carried over, so the user's own files, another command's outputs and the
truth cache ``OUT/truth-cache`` survive a rerun; the old owned files are replaced as a set (a
3R fit leaves no scf.png of an earlier 2R paper fit), and temporary files ``.*.tmp`` are not
carried. A run killed at any point leaves at most a ``.OUT.staging-*`` or ``.OUT.old-*`` folder;
the next successful run moves the entries it finds there that are not package outputs back into
OUT and removes it (each staging folder is locked while its run lives, so a concurrent run's
folder is left alone).

Where OUT cannot be exchanged (the working directory or one of its parents, a mount point, a
parent folder that is not writable) the files are staged in ``OUT/.staging-XXXX`` and moved in one
by one, ``marker`` (the file whose presence marks a complete folder) last.
"""

from __future__ import annotations

import ctypes
import errno
import os
import secrets
import shutil
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import BeamInputError

try:
    import fcntl
except ImportError:  # no flock: a concurrent run's staging folder is not told apart
    fcntl = None

__all__ = ["output_folder", "OUTPUT_NAMES"]

# every file a folder-writing command owns; a leftover's entries with these names are dropped
OUTPUT_NAMES = frozenset({
    "fit.json", "model.urdf", "planform.png", "scf.png",  # fit (and the knee of pareto)
    "pareto.csv", "pareto.json", "pareto.png",  # pareto
    "truth.json", "modes.vtu",  # truth
    "trajectory.csv", "response.png", "truth_comparison.png", "truth_comparison.json",
    "results.md", "results.json", "error_vs_cost.png",  # bench
    "linear_model.npz", "linear_model.json", "bode.png",  # linearize
    "comparison.json", "comparison.png",  # linearize --compare-truth
    "modes.png", "model_modes.vtu", "truth_modes.vtu", "response.gif", "response.mp4",
    "trajectory.pvd",  # view (and its trajectory_NNNN.vtu)
})
_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _is_temp(name: str) -> bool:
    return name.startswith(".") and (name.endswith(".tmp") or ".staging-" in name
                                     or ".old-" in name)


def _mkdir_new(parent: Path, prefix: str) -> Path:
    # os.mkdir applies the umask (tempfile.mkdtemp would make the renamed OUT 0700)
    for _ in range(100):
        p = parent / f"{prefix}{secrets.token_hex(4)}"
        try:
            p.mkdir(0o777)
            return p
        except FileExistsError:
            continue
    raise FileExistsError(f"no free folder name in {str(parent)!r}")


def _lock(path: Path, block: bool = True) -> int | None:
    """Open an fd holding an exclusive flock on the folder ``path``; None if another has it."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    if fcntl is None:
        return fd
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | (0 if block else fcntl.LOCK_NB))
    except BlockingIOError:
        os.close(fd)
        return None
    return fd


def _exchange(a: Path, b: Path) -> bool:
    """Swap the folders ``a`` and ``b`` atomically; False where the system cannot."""
    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _carry_over(old: Path, new: Path, drop) -> None:
    """Move the entries of ``old`` that ``drop`` does not claim and ``new`` lacks into ``new``."""
    for entry in list(os.scandir(old)):
        if drop(entry.name) or os.path.lexists(new / entry.name):
            continue
        try:
            os.rename(entry.path, new / entry.name)
        except FileNotFoundError:
            pass  # taken by a concurrent cleanup


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def _clean_leftovers(folder: Path, prefixes: tuple[str, ...], out: Path) -> None:
    """Carry the non-output entries of killed runs' staging folders into ``out``, remove them."""
    for entry in list(os.scandir(folder)):
        if not entry.name.startswith(prefixes):
            continue
        p = Path(entry.path)
        if not entry.is_dir(follow_symlinks=False):
            _remove(p)
            continue
        fd = _lock(p, block=False)
        if fd is None:
            continue  # a live run's folder
        try:
            _carry_over(p, out, lambda n: n in OUTPUT_NAMES or _is_temp(n))
            shutil.rmtree(p, ignore_errors=True)
        finally:
            os.close(fd)


def _in_place(out: Path) -> bool:
    try:
        cwd = Path.cwd().resolve()
    except OSError:
        cwd = None
    return (not os.access(out.parent, os.W_OK | os.X_OK) or os.path.ismount(out)
            or (cwd is not None and (cwd == out or out in cwd.parents)))


@contextmanager
def output_folder(out: str | os.PathLike, owned: Iterable[str],
                  marker: str | None = None) -> Iterator[Path]:
    """Stage a command's outputs and put them in place as one set (see the module notes).

    Parameters
    ----------
    out : path
        The output folder (``--out``); created if missing, a symlink is followed.
    owned : iterable of str
        The file names the command may write into OUT.
    marker : str, optional
        The file written last where files must be moved in one by one.

    Yields
    ------
    Path
        The folder to write every output file into.
    """
    out = Path(os.path.abspath(out))
    if out.is_symlink():
        out = out.resolve()
    if out.exists() and not out.is_dir():
        raise BeamInputError(f"out = {str(out)!r}: exists and is not a folder")
    owned = frozenset(owned)
    out.parent.mkdir(parents=True, exist_ok=True)
    in_place = out.exists() and _in_place(out)
    if not in_place:
        try:
            stage = _mkdir_new(out.parent, f".{out.name}.staging-")
        except PermissionError:
            in_place = True
    if in_place:
        stage = _mkdir_new(out, ".staging-")
    fd = _lock(stage)
    try:
        yield stage
    except BaseException:
        os.close(fd)
        shutil.rmtree(stage, ignore_errors=True)
        raise
    try:
        # from here on a failure leaves a leftover for the next run, never removes the old files
        if in_place:
            _commit_in_place(stage, out, owned, marker)
            shutil.rmtree(stage, ignore_errors=True)
        else:
            _commit(stage, out, owned)
    finally:
        os.close(fd)
    if in_place:
        _clean_leftovers(out, (".staging-",), out)
    else:
        _clean_leftovers(out.parent, (f".{out.name}.staging-", f".{out.name}.old-"), out)


def _commit(stage: Path, out: Path, owned: frozenset) -> None:
    if not out.exists():
        os.rename(stage, out)
        return
    old_fd = _lock(out)  # follows the old folder through the exchange
    try:
        if _exchange(stage, out):
            old = stage
        else:
            old = out.parent / f".{out.name}.old-{secrets.token_hex(4)}"
            os.rename(out, old)
            os.rename(stage, out)
        _carry_over(old, out, lambda n: n in owned or _is_temp(n))
        shutil.rmtree(old, ignore_errors=True)
    finally:
        os.close(old_fd)


def _commit_in_place(stage: Path, out: Path, owned: frozenset, marker: str | None) -> None:
    names = sorted(os.listdir(stage), key=lambda n: n == marker)
    if marker in names:
        (out / marker).unlink(missing_ok=True)  # the folder is incomplete until it is back
    for n in names:
        os.replace(stage / n, out / n)
    for entry in list(os.scandir(out)):
        if (entry.name in owned and entry.name not in names) or (
                entry.name.endswith(".tmp") and entry.name.startswith(".")):
            _remove(Path(entry.path))
