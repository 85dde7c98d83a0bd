"""Sensors at a station of the member: the section's slope and twist, a planform point's motion.

A station ``x`` (m from the root along the undeformed beam) lies on one rigid link of the
chain: link i spans [x_i, x_i+1] between the joints (link 0 from the root, link n to the tip).
The section at ``x`` moves with its link, so

- ``slope@X``: the section's rotation about y, rad: the pitch theta of the link's rotation R
  (world from link) in its yaw-pitch-roll (z, y, x) decomposition, theta = asin(-R_zx), in the
  sense of the joint angles about y (a positive slope turns the beam axis toward -z, as a
  positive joint angle does; on a planar chain it is the sum of the joint angles inboard of
  ``x``, the hub angle included);
- ``twist@X``: the section's rotation about the link's own axis, rad: the roll phi of R, the
  same angle as ``tip_twist`` (:func:`prbdm_pin.chain.points.twist_angle`); 0 on a planar
  chain;
- ``point_x|y|z@X:Y``: the world displacement, m, of the planform point at ``x`` along and
  ``y`` across the beam (|y| <= w(x), the half-width; y along the link's y axis): its
  position rigidly carried by the link, less its position on the straight member (every
  angle, the hub's included, zero).

All three are world quantities, as the tip outputs are: on a hub model they include the hub's
turn. A station on a joint (within ``ON_JOINT_RTOL`` L) belongs to both links: it reads the
mean of the two (the joint's lumped compliance stands for the beam on both sides of it, as a
strain actuator's end on a joint gives it half the moment, :mod:`prbdm_pin.model.inputs`).

Limits: inside a link the slope and the twist are the link's, constant along it; the beam's
own slope varies along it, so a station between joints reads the chord of the bent beam, not
its tangent (the error is the link's bending, O(M l / EI) with l the link length). The
points' motion is exact for the chain and as good as the chain for the beam.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain.points import point_kinematics, twist_angle, twist_jacobian
from ..errors import BeamInputError
from .inputs import ON_JOINT_RTOL

__all__ = ["check_station", "check_point", "section_links", "slope", "twist",
           "point_position", "point_displacement"]

_LWA = pin.LOCAL_WORLD_ALIGNED


def check_station(model, x_m: float, field: str) -> float:
    """Return station ``x_m`` (m) on the model's member, or raise BeamInputError naming ``field``.

    It must lie in [0, L], L the sum of the link lengths (a rounding of ``ON_JOINT_RTOL`` L
    beyond an end is taken as the end).
    """
    L = float(np.sum(model.lengths_m))
    tol = ON_JOINT_RTOL * L
    if not np.isfinite(x_m) or x_m < -tol or x_m > L + tol:
        raise BeamInputError(f"{field}: station x = {x_m!r} m is off the member, which spans "
                             f"[0, {L:g}] m")
    return min(max(float(x_m), 0.0), L)


def check_point(model, x_m: float, y_m: float, field: str) -> tuple[float, float]:
    """Return the planform point (x, y) (m), or raise BeamInputError naming ``field``.

    ``x_m`` as :func:`check_station`; ``y_m`` within the half-width w(x) of the model's beam
    (either side's at a width step). A model without its beam (read from a URDF) has no
    planform: refused.
    """
    if model.beam is None:
        raise BeamInputError(f"{field}: this model carries no beam (read from a URDF), so no "
                             "planform to put a point on")
    x = check_station(model, x_m, field)
    w = max(float(model.beam.half_width_at(x, "left")), float(model.beam.half_width_at(x)))
    if not np.isfinite(y_m) or abs(y_m) > w * (1.0 + ON_JOINT_RTOL):
        raise BeamInputError(f"{field}: point y = {y_m!r} m is off the planform, whose "
                             f"half-width at x = {x:g} m is {w:g} m")
    return x, float(y_m)


def section_links(model, x_m: float) -> tuple[tuple[int, float], ...]:
    """Return the links the section at ``x_m`` (m, on the member) moves with, and their weights.

    One link (weight 1), or the two links at a joint (1/2 each; module notes).
    """
    lengths = np.asarray(model.lengths_m, dtype=float)
    joints = np.cumsum(lengths)[:-1]
    tol = ON_JOINT_RTOL * float(lengths.sum())
    on = np.flatnonzero(np.abs(joints - x_m) <= tol)
    if on.size:
        j = int(on[0])  # joint j (0-based) joins link j and link j + 1
        return ((j, 0.5), (j + 1, 0.5))
    return ((int(np.count_nonzero(joints < x_m)), 1.0),)


def _link_frame(model, link: int) -> int:
    name = f"link_{link}"
    if not model.pin_model.existFrame(name):
        raise BeamInputError(f"link {link}: the model has no frame {name!r} to read a station "
                             "on (a chain built by build_model or read from its URDF has one)")
    return int(model.pin_model.getFrameId(name))


def _link_start_m(model, link: int) -> float:
    return float(np.sum(model.lengths_m[:link]))


def _rotation(model, data, q: np.ndarray, link: int) -> tuple[np.ndarray, np.ndarray]:
    """World rotation of ``link`` and its world angular Jacobian (3, nv) at ``q``."""
    fid = _link_frame(model, link)
    J = pin.computeFrameJacobian(model.pin_model, data, q, fid, _LWA).reshape(6, -1)
    R = pin.updateFramePlacement(model.pin_model, data, fid).rotation
    return R.copy(), J[3:]


def _pitch(R: np.ndarray, Jw: np.ndarray) -> tuple[float, np.ndarray]:
    # theta = asin(-R_zx); dR = [omega]_x R gives dR_zx = omega_x R_yx - omega_y R_xx
    c = float(np.hypot(R[0, 0], R[1, 0]))  # cos(theta) >= 0
    theta = float(np.arctan2(-R[2, 0], c))
    return theta, -(R[1, 0] * Jw[0] - R[0, 0] * Jw[1]) / c


def _mean(model, q, x_m, data, one) -> tuple[np.ndarray | float, np.ndarray]:
    d = model._workspace(data)
    qv = np.asarray(q, dtype=float)
    value, grad = 0.0, 0.0
    for link, w in section_links(model, x_m):
        v, g = one(d, qv, link)
        value, grad = value + w * np.asarray(v), grad + w * np.asarray(g)
    return value, grad


def slope(model, q: np.ndarray, x_m: float, data: pin.Data | None = None
          ) -> tuple[float, np.ndarray]:
    """Return the section's slope at ``x_m`` (rad) and its gradient (rad/rad, (nv,)) at ``q``.

    See the module notes; ``x_m`` (m) is taken as checked (:func:`check_station`).
    """
    v, g = _mean(model, q, x_m, data, lambda d, qv, k: _pitch(*_rotation(model, d, qv, k)))
    return float(v), g


def twist(model, q: np.ndarray, x_m: float, data: pin.Data | None = None
          ) -> tuple[float, np.ndarray]:
    """Return the section's twist at ``x_m`` (rad) and its gradient (rad/rad, (nv,)) at ``q``."""
    def one(d, qv, k):
        R, Jw = _rotation(model, d, qv, k)
        return twist_angle(R), twist_jacobian(R, Jw)

    v, g = _mean(model, q, x_m, data, one)
    return float(v), g


def point_position(model, q: np.ndarray, x_m: float, y_m: float,
                   data: pin.Data | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Return the world position (m, (3,)) of the point (x, y) and its Jacobian (m/rad, (3, nv)).

    The point (m) is taken as checked (:func:`check_point`).
    """
    def position(d, qv, k):
        offset = np.array([x_m - _link_start_m(model, k), y_m, 0.0])
        return point_kinematics(model.pin_model, d, qv, _link_frame(model, k), offset)

    return _mean(model, q, x_m, data, position)


def point_displacement(model, q: np.ndarray, x_m: float, y_m: float,
                       data: pin.Data | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Return the world displacement (m, (3,)) of the point (x, y) and its Jacobian (m/rad).

    The displacement from the point's position on the straight member (every angle zero); the
    Jacobian is (3, nv); the point (m) is taken as checked (:func:`check_point`).
    """
    p, J = point_position(model, q, x_m, y_m, data)
    return p - point_position(model, np.zeros(model.pin_model.nq), x_m, y_m, data)[0], J
