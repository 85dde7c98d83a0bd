"""Points on the tip link a controller sees: the tip centre and the tip corners.

A point is rigidly attached to the tip link at an offset (m, tip frame) from the tip frame (the
centre of the free end): ``tip`` at 0, ``tip_corner_left`` at +w(L) along y and
``tip_corner_right`` at -w(L) (w the member's half-width at its tip). Off the centre line a
force twists the member and a twist moves the point: what a planar chain cannot show.

The tip twist is the roll of the tip frame R (world from tip) in its yaw-pitch-roll (z, y, x)
decomposition R = R_z(psi) R_y(theta) R_x(phi): phi = atan2(R_zy, R_zz), the rotation of the
tip section about the tip link's own axis once that axis has been bent (yawed and pitched) into
place. A bent, untwisted tip has phi = 0 whatever its bending; at small angles phi is the
rotation about x, and the corners' z difference is 2 w sin(phi) cos(theta) (2 w phi at the
straight pose). It is singular where the tip axis is vertical (cos(theta) = 0).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from ..options.choices import POINT_NAMES

__all__ = ["POINTS", "point_offset_m", "point_kinematics", "point_frame", "twist_angle",
           "twist_jacobian"]

# the named points and their side across the width (+1 left, -1 right, 0 centre)
POINTS = dict(zip(POINT_NAMES, (0.0, 1.0, -1.0), strict=True))
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


def twist_angle(rotation: np.ndarray) -> float:
    """Return the tip twist phi = atan2(R_zy, R_zz) (rad) of a rotation (module notes).

    ``rotation``: world from tip frame, (3, 3).
    """
    R = np.asarray(rotation, dtype=float)
    return float(np.arctan2(R[2, 1], R[2, 2]))


def twist_jacobian(rotation: np.ndarray, angular_jacobian: np.ndarray) -> np.ndarray:
    """Return d(phi)/dq (rad/rad, (nv,)) of the tip twist at rotation R.

    From the tip's world angular Jacobian J_w ((3, nv), rad/s per rad/s): dR = [omega]_x R, so
    dR_zy = (omega x R e_y)_z = omega_x R_yy - omega_y R_xy and likewise dR_zz with e_z, and
    d(atan2(a, b)) = (b da - a db) / (a^2 + b^2).
    """
    R = np.asarray(rotation, dtype=float)
    Jw = np.asarray(angular_jacobian, dtype=float)
    a, b = R[2, 1], R[2, 2]
    da = R[1, 1] * Jw[0] - R[0, 1] * Jw[1]
    db = R[1, 2] * Jw[0] - R[0, 2] * Jw[1]
    return (b * da - a * db) / (a * a + b * b)


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
