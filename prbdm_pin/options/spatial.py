"""The options a spatial fit, and a planar fit with modal gains, check beside the others.

Numpy-free, as every options module.
"""

from __future__ import annotations

from typing import Any

from ..errors import BeamInputError
from .choices import POINT_NAMES, Objective, StiffnessKind, UniqueRule

__all__ = ["gain_points", "check_spatial_fit", "check_planar_gains"]


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


def check_planar_gains(o) -> None:
    """Refuse what a planar fit's ``gain_points`` term cannot take; each error names the field.

    The term (``fitting/planar_gains.py``) is the joint-spring fit's, at the straight pose, beside
    the frequencies (eigen or combined objective); a planar chain moves its tip corners as its
    tip, so its one gain point is ``tip``.
    """
    if not o.gain_points:
        return
    corners = [p for p in o.gain_points if p != "tip"]
    if corners:
        raise BeamInputError(f"gain_points = {list(o.gain_points)}: a planar chain (axes 'y') "
                             f"moves {', '.join(corners)} as its tip; give 'tip' alone, or "
                             "a spatial chain (axes 'xy', 'yz', 'xyz') for the corners")
    for name, bad, why in (
            ("stiffness", o.stiffness is not StiffnessKind.JOINT,
             "the planar modal gains are fitted with the joint springs (stiffness 'joint')"),
            ("objective", o.objective is Objective.DEFLECTION,
             "the modal gains go beside the frequencies (objective 'eigen' or 'combined')"),
            ("joint_sweep", o.joint_sweep, "the modal gains are the straight pose's"),
            ("unique", o.unique is not UniqueRule.NONE,
             "the 'nearest' rule picks among exact frequency fits; leave it at 'none'")):
        if bad:
            value = getattr(o, name)
            value = getattr(value, "value", value)
            raise BeamInputError(f"{name} = {value!r}: not with gain_points "
                                 f"{list(o.gain_points)}: {why}")
