"""Measured data for :func:`~prbdm_pin.fitting.calibrate.calibrate`: a free ring-down.

A CSV file with a header: ``t_s`` (s, strictly increasing) then one column per measured output,
named as :func:`prbdm_pin.linearize` names its outputs (``tip_z``, ``q[0]``, ``tip_z_rate``)
or with the unit the trajectory CSV appends (``tip_z_m``, ``tip_z_rate_m_s``): the unit
suffix is dropped. Every value must be finite.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError

__all__ = ["RingDown", "channel_name", "ring_down", "read_ring_down", "read_table"]

# the unit suffixes the trajectory CSV writes (longest first: ``_m_s`` before ``_m``)
_SUFFIXES = ("_m_s2", "_rad_s", "_N_m", "_m_s", "_rad", "_m", "_N")
MIN_SAMPLES = 8  # below this no spectrum, whatever the parameters asked


@dataclass(frozen=True, eq=False)
class RingDown:
    """A free ring-down: times and the measured outputs.

    Attributes
    ----------
    t_s : ndarray, shape (N,)
        Sample times, s, strictly increasing.
    y : ndarray, shape (N, c)
        Measured outputs (SI units of each output), one column per channel.
    channels : tuple of str
        The outputs' names as :func:`prbdm_pin.linearize` spells them.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> t = np.arange(100) * 1e-3  # s
    >>> data = pp.RingDown(t_s=t, y=1e-3 * np.cos(60.0 * t)[:, None], channels=("tip_z",))
    >>> data.y.shape, data.channels
    ((100, 1), ('tip_z',))
    """

    t_s: np.ndarray
    y: np.ndarray
    channels: tuple[str, ...]


def channel_name(name: str) -> str:
    """Return ``name`` without the unit suffix the trajectory CSV appends (``tip_z_m``).

    And without the ``y:`` or ``u:`` prefix it gives outputs and inputs.
    """
    if name.startswith(("y:", "u:")):
        name = name[2:]
    for s in _SUFFIXES:
        if name.endswith(s):
            return name[: -len(s)]
    return name


def ring_down(t_s, y, channels, what: str = "data") -> RingDown:
    """Return a checked :class:`RingDown` (``y`` shape (N, c); ``channels`` c names).

    Raises
    ------
    BeamInputError
        Naming the field: a non-finite value (with its row), a time that does not increase,
        fewer than 8 samples, a repeated channel.
    """
    if isinstance(channels, str) or not isinstance(channels, (list, tuple)):
        raise InputTypeError(f"{what}: channels = {channels!r:.60}: must be a list of names")
    try:
        t = np.array(t_s, dtype=float)
        Y = np.array(y, dtype=float)
    except (TypeError, ValueError):
        raise InputTypeError(f"{what}: t_s and y must be numbers") from None
    if Y.ndim == 1:
        Y = Y[:, None]
    if t.ndim != 1 or Y.shape != (t.size, len(channels)) or not channels:
        raise BeamInputError(f"{what}: t_s {t.shape} and y {Y.shape}: need N times and N rows "
                             f"of {len(channels)} channel(s)")
    names = tuple(channel_name(str(c)) for c in channels)
    if len(set(names)) != len(names):
        raise BeamInputError(f"{what}: channels {list(channels)}: a channel is repeated")
    for j, name in enumerate(("t_s", *channels)):
        col = t if j == 0 else Y[:, j - 1]
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise BeamInputError(f"{what}: {name}: not finite at row {int(bad[0])} "
                                 f"({float(col[bad[0]])})")
    if t.size < MIN_SAMPLES:
        raise BeamInputError(f"{what}: t_s: {t.size} samples; need at least {MIN_SAMPLES}")
    step = np.flatnonzero(np.diff(t) <= 0.0)
    if step.size:
        i = int(step[0]) + 1
        raise BeamInputError(f"{what}: t_s: not increasing at row {i} ({t[i - 1]!r} then "
                             f"{t[i]!r})")
    for a in (t, Y):
        a.setflags(write=False)
    return RingDown(t_s=t, y=Y, channels=names)


def read_table(path: str | os.PathLike) -> tuple[str, list[str], np.ndarray]:
    """Return (the message prefix, the header's names, the values (rows, columns)) of a CSV.

    Raises
    ------
    BeamInputError
        Naming the file, the column and the row: unreadable, a row of another length, a
        field that is not a number.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputTypeError(f"path = {path!r:.60}: must be a path to a CSV file")
    what = f"data {str(path)!r}"
    try:
        with open(path, encoding="utf-8") as fh:
            head = fh.readline().strip().split(",")
            rows = [ln.strip().split(",") for ln in fh if ln.strip()]
    except (OSError, UnicodeDecodeError) as exc:
        raise BeamInputError(f"{what}: cannot read ({exc.__class__.__name__}: {exc})") from None
    head = [h.strip() for h in head]
    vals = np.full((len(rows), len(head)), np.nan)
    for i, r in enumerate(rows):
        if len(r) != len(head):
            raise BeamInputError(f"{what}: row {i}: {len(r)} fields, the header has "
                                 f"{len(head)}")
        for j, s in enumerate(r):
            try:
                vals[i, j] = float(s)
            except ValueError:
                raise BeamInputError(f"{what}: {head[j]}: {s!r:.30} at row {i} is not a "
                                     "number") from None
    return what, head, vals


def read_ring_down(path: str | os.PathLike) -> RingDown:
    """Read a ring-down CSV (module notes) into a :class:`RingDown`.

    Parameters
    ----------
    path : str or path-like
        The CSV file: header ``t_s,CHANNEL,...``, then one row per sample.

    Returns
    -------
    RingDown

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> t = np.arange(100) * 1e-3  # s
    >>> np.savetxt(folder / "ring.csv", np.c_[t, 1e-3 * np.cos(60.0 * t)], delimiter=",",
    ...            header="t_s,tip_z_m", comments="")
    >>> data = pp.read_ring_down(folder / "ring.csv")
    >>> data.channels, data.y.shape
    (('tip_z',), (100, 1))
    """
    what, head, vals = read_table(path)
    if not head or head[0] != "t_s" or len(head) < 2:
        raise BeamInputError(f"{what}: header {','.join(head)!r:.80}: must be t_s then one "
                             "column per output (e.g. t_s,tip_z_m)")
    return ring_down(vals[:, 0], vals[:, 1:], head[1:], what)
