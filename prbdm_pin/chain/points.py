"""Points on the tip link a controller sees: the tip centre and the tip corners.

A point is rigidly attached to the tip link at an offset (m, tip frame) from the tip frame (the
centre of the free end): ``tip`` at 0, ``tip_corner_left`` at +w(L) along y and
``tip_corner_right`` at -w(L) (w the member's half-width at its tip). Off the centre line a
force twists the member and a twist moves the point: what a planar chain cannot show.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError

__all__ = ["POINTS", "point_offset_m", "point_kinematics", "point_frame"]

# the named points and their side across the width (+1 left, -1 right, 0 centre)
POINTS = {"tip": 0.0, "tip_corner_left": 1.0, "tip_corner_right": -1.0}
_LWA = pin.LOCAL_WORLD_ALIGNED


def point_offset_m(name: str, tip_half_width_m: float) -> np.ndarray:
    """Return the offset of point ``name`` from the tip frame, m, shape (3,) (tip frame axes).

    Raises
    ------
    BeamInputError
        ``name`` is none of :data:`POINTS`.
    """
    if name not in POINTS:
        raise BeamInputError(f"point = {name!r}: must be one of {', '.join(POINTS)}")
    return np.array([0.0, POINTS[name] * float(tip_half_width_m), 0.0])


def point_kinematics(pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int,
                     offset_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World position (m, (3,)) and world-aligned linear Jacobian (m/rad, (3, nv)) of a point.

    The point sits at ``offset_m`` (m, tip frame axes) from the tip frame: its velocity is the
    tip's plus omega x (R offset), so J = J_v - [R offset]_x J_w.
    """
    q = np.asarray(q, dtype=float)
    J = pin.computeFrameJacobian(pin_model, data, q, tip_frame_id, _LWA).reshape(6, -1)
    M = pin.updateFramePlacement(pin_model, data, tip_frame_id)
    r = M.rotation @ np.asarray(offset_m, dtype=float)
    return M.translation + r, J[:3] - pin.skew(r) @ J[3:]


def point_frame(pin_model: pin.Model, tip_frame_id: int, offset_m: np.ndarray
                ) -> tuple[pin.Model, int]:
    """Return a copy of the model with a frame at a point of the tip link, and the frame's id.

    The frame sits on the tip frame's joint at ``offset_m`` (m, tip frame axes) from the tip
    frame, its axes the tip frame's: a load on it is a load at the point (the statics take a
    frame, :func:`~prbdm_pin.chain.spatial_statics.spatial_static_deflection`). The model given
    is left as it is (a Pinocchio ``Data`` is sized to its frames).
    """
    m = pin.Model(pin_model)
    tip = m.frames[tip_frame_id]
    placement = tip.placement * pin.SE3(np.eye(3), np.asarray(offset_m, dtype=float))
    fid = m.addFrame(pin.Frame("load_point", tip.parentJoint, tip_frame_id, placement,
                               pin.FrameType.OP_FRAME))
    return m, int(fid)
