"""``prbdm simulate --base-motion FILE.csv``: samples of a prescribed base motion.

A header row names the columns: ``t_s,x_m,y_m,z_m`` (time s, base position m, world) and
optionally ``roll_rad,pitch_rad,yaw_rad`` (all three: R = Rz(yaw) Ry(pitch) Rx(roll)), in any
order; then at least two rows of finite numbers, times strictly increasing. The samples are
interpolated by cubic splines (:meth:`prbdm_pin.BaseMotion.from_samples`), whose derivatives
give the base's rates and accelerations. Numpy-free: refused before any import, one message
naming the file and the column or row.
"""

from __future__ import annotations

import math

from ..errors import BeamInputError
from .input_signals import read_rows

__all__ = ["POSITION_COLUMNS", "ANGLE_COLUMNS", "read_base_motion"]

POSITION_COLUMNS = ("t_s", "x_m", "y_m", "z_m")
ANGLE_COLUMNS = ("roll_rad", "pitch_rad", "yaw_rad")


def read_base_motion(path: str) -> tuple[list[float], list[list[float]], list[list[float]] | None]:
    """Return (times s, positions (x, y, z) m, angles (roll, pitch, yaw) rad or None).

    Raises BeamInputError naming ``--base-motion``, the file and the column or row.
    """
    where = f"--base-motion {path!r}"
    rows = read_rows(path, "--base-motion")
    if not rows:
        raise BeamInputError(f"{where}: empty; needs a header {','.join(POSITION_COLUMNS)} and "
                             "rows")
    head = [c.strip() for c in rows[0]]
    for name in POSITION_COLUMNS:
        if name not in head:
            raise BeamInputError(f"{where}: missing column {name!r} (the header must name "
                                 f"{','.join(POSITION_COLUMNS)}, optionally "
                                 f"{','.join(ANGLE_COLUMNS)})")
    angles = [c for c in ANGLE_COLUMNS if c in head]
    if angles and len(angles) != 3:
        missing = next(c for c in ANGLE_COLUMNS if c not in head)
        raise BeamInputError(f"{where}: missing column {missing!r} (give roll_rad, pitch_rad "
                             "and yaw_rad together, or none)")
    known = set(POSITION_COLUMNS + ANGLE_COLUMNS)
    for name in head:
        if name not in known:
            raise BeamInputError(f"{where}: unknown column {name!r}; columns are "
                                 f"{','.join(POSITION_COLUMNS + ANGLE_COLUMNS)}")
    if len(set(head)) != len(head):
        raise BeamInputError(f"{where}: a column is named twice in the header {head!r}")
    cols = {name: i for i, name in enumerate(head)}
    t, pos, ang = [], [], []
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(head):
            raise BeamInputError(f"{where}: row {r} has {len(row)} values; the header has "
                                 f"{len(head)}")
        values = {}
        for name, i in cols.items():
            try:
                values[name] = float(row[i])
            except ValueError:
                values[name] = math.nan
            if not math.isfinite(values[name]):
                raise BeamInputError(f"{where}: row {r}, column {name!r} = {row[i]!r:.30}: must "
                                     "be a finite number")
        if t and values["t_s"] <= t[-1]:
            raise BeamInputError(f"{where}: row {r}, column 't_s': time {values['t_s']:g} s does "
                                 f"not increase (previous {t[-1]:g} s)")
        t.append(values["t_s"])
        pos.append([values[c] for c in POSITION_COLUMNS[1:]])
        ang.append([values[c] for c in ANGLE_COLUMNS] if angles else [])
    if len(t) < 2:
        raise BeamInputError(f"{where}: needs at least two rows of samples")
    return t, pos, (ang if angles else None)
