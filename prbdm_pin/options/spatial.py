"""The options a spatial fit checks beside the others (numpy-free, as every options module)."""

from __future__ import annotations

from typing import Any

from ..errors import BeamInputError
from .choices import POINT_NAMES, UniqueRule

__all__ = ["gain_points", "check_spatial_fit"]


def gain_points(value: Any) -> tuple[str, ...]:
    """Check ``gain_points``: distinct names of :data:`~.choices.POINT_NAMES`, as a tuple."""
    if isinstance(value, str) or not isinstance(value, (tuple, list)):
        raise BeamInputError(f"gain_points = {value!r:.60}: must be a list of point names "
                             f"({', '.join(POINT_NAMES)})")
    for i, v in enumerate(value):
        if v not in POINT_NAMES:
            raise BeamInputError(f"gain_points[{i}] = {v!r:.60}: must be one of "
                                 f"{', '.join(POINT_NAMES)}")
    if len(set(value)) != len(value):
        raise BeamInputError(f"gain_points = {list(value)}: a point appears twice")
    return tuple(value)


def check_spatial_fit(o) -> None:
    """Refuse the options a spatial fit does not have; each error names the field."""
    for name, bad in (("joint_sweep", o.joint_sweep), ("unique", o.unique is not UniqueRule.NONE),
                      ("start_lengths_m", o.start_lengths_m is not None),
                      ("squared", o.squared)):
        if bad:
            raise BeamInputError(f"{name} = {getattr(o, name)!r}: not an option of a spatial "
                                 f"fit (axes = {o.axes.value!r}); leave it at its default")
