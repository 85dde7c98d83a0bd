"""Loads beyond the tip force: follower tip moments, distributed forces, base acceleration.

Each maps onto the joints by virtual work, as a column of the input map (generalized force per
unit input, :func:`prbdm_pin.model.inputs.input_map`); all depend on the pose.

Follower tip moment (``tip_moment_follower_x``, ``_y``, ``_z``, N m): a moment about the tip
link's own axes. Its virtual work is M . omega_tip, omega_tip the tip's angular velocity in the
tip frame, so its column is the row of the tip frame's LOCAL angular Jacobian: exact, and on a
planar chain the ``y`` one equals the dead ``tip_moment_y`` (every axis stays parallel to y).

Distributed force (``distributed_force_x``, ``_y``, ``_z``, N/m, dead, world axes): a load per
unit length over [x_start_m, x_end_m] of the undeformed beam (m from the root), its intensity
linear from ``start_weight`` to ``end_weight`` times the input. Each link is rigid, so the part
of the load on it does the same virtual work as its resultant at the load's centroid on that
link: link i's share F_i acts at station c_i, and the column is sum_i J(c_i)^T e F_i, J(c_i)
the world linear Jacobian of the material point c_i of link i. It is computed from the share
and its first moment Q_i = F_i (c_i - s_i) about the link's start s_i (exact also where a
profile changing sign leaves a link a couple and no resultant). The plain name covers the whole beam
uniformly; ``distributed_force_z[i]`` the i-th :class:`DistributedLoad`. A uniform load
q = rho A g per unit length over a uniform member is its weight: the column is then the
generalized gravity of the chain (links of uniform section have their centre of mass at their
midpoints).

Base acceleration (``base_accel_x``, ``_y``, ``_z``, m/s^2): the clamp (or the hub's axis) of a
translating base accelerates by a. In the base frame every link feels the inertial load -m a
(d'Alembert), which is the weight of the chain under the gravity g = -a: the column is
Pinocchio's generalized gravity of the model under the unit gravity e_k (g_(e_k)(q) enters
M qdd + ... = tau + g_(e_k)(q) a_k). The joint angles and every output (``tip_z``, ...) are
then measured in the base frame: positions relative to the base, rates relative to it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError, InputTypeError
from ..options.checks import check_float
from ..options.validate import check_size
from .chain_names import node_links

__all__ = ["DistributedLoad", "FOLLOWER_MOMENTS", "DISTRIBUTED_FORCES", "BASE_ACCELS",
           "link_resultants", "check_load", "follower_moment_columns", "distributed_column",
           "base_accel_columns"]

# rows of the tip frame's LOCAL Jacobian (angular part) of each follower moment
FOLLOWER_MOMENTS = {"tip_moment_follower_x": 3, "tip_moment_follower_y": 4,
                    "tip_moment_follower_z": 5}
DISTRIBUTED_FORCES = {"distributed_force_x": 0, "distributed_force_y": 1,
                      "distributed_force_z": 2}  # world axis
BASE_ACCELS = {"base_accel_x": 0, "base_accel_y": 1, "base_accel_z": 2}  # world axis


@dataclass(frozen=True)
class DistributedLoad:
    """A force per unit length over the beam span [x_start_m, x_end_m], m from the root.

    Its intensity at station x is u (w_a + (w_b - w_a) (x - x_a) / (x_b - x_a)) N/m, u the
    input (N/m) and w_a, w_b the dimensionless ``start_weight`` and ``end_weight`` (default 1:
    uniform). Where the beam ends is checked where the load is used.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> load = pp.DistributedLoad(0.0, 1.0, start_weight=1.0, end_weight=0.0)  # a triangle
    >>> load.start_weight, load.end_weight
    (1.0, 0.0)
    """

    x_start_m: float
    x_end_m: float
    start_weight: float = 1.0
    end_weight: float = 1.0

    def __post_init__(self) -> None:
        """Check the stations and the weights (BeamInputError naming the field)."""
        for name in ("x_start_m", "x_end_m"):
            v = check_size(f"DistributedLoad {name}", getattr(self, name), low=0.0)
            object.__setattr__(self, name, v)
        if not self.x_start_m < self.x_end_m:
            raise BeamInputError(f"DistributedLoad x_start_m = {self.x_start_m!r}: must be < "
                                 f"x_end_m = {self.x_end_m!r} (m)")
        for name in ("start_weight", "end_weight"):
            v = check_float(f"DistributedLoad {name}", getattr(self, name))
            object.__setattr__(self, name, v)


def check_load(lengths_m: np.ndarray, load: DistributedLoad, field: str) -> float:
    """Check that ``load`` is a DistributedLoad on the beam of links ``lengths_m`` (m).

    Returns the beam length, m. InputTypeError or BeamInputError naming ``field``.
    """
    if not isinstance(load, DistributedLoad):
        raise InputTypeError(f"{field} = {load!r:.60}: must be a prbdm_pin.DistributedLoad")
    L = float(np.sum(lengths_m))
    tol = 1e-9 * L  # the stations come from sums of link lengths
    for name in ("x_start_m", "x_end_m"):
        v = getattr(load, name)
        if v > L + tol:
            raise BeamInputError(f"{field} {name} = {v!r}: must lie on the beam, in [0, {L:g}] "
                                 "(m)")
    return L


def link_resultants(lengths_m: np.ndarray, load: DistributedLoad | None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Return each link's share of a unit load and its first moment about the link's start.

    The share is N per N/m of input, the moment N m per N/m (the share times the distance of
    its resultant point from the link's start, along the link), both shape (n+1,); a link the
    load misses has zeros. ``None`` is the uniform unit load over the whole beam. The load's
    intensity is linear on each link, so both are exact (a trapezoid's area and first moment),
    and so is the virtual work of the pair, also where a profile changes sign on a link (its
    share may vanish there, not its moment).
    """
    lengths = np.asarray(lengths_m, dtype=float)
    ends = np.cumsum(lengths)
    starts = ends - lengths
    if load is None:
        a, b, wa, wb = 0.0, float(ends[-1]), 1.0, 1.0
    else:
        a, b, wa, wb = load.x_start_m, load.x_end_m, load.start_weight, load.end_weight
    u = np.clip(starts, a, b)
    v = np.clip(ends, a, b)

    def w(x):
        return wa + (wb - wa) * (x - a) / (b - a)

    wu, wv = w(u), w(v)
    share = 0.5 * (wu + wv) * (v - u)
    # first moment of the trapezoid about u, (v - u)^2 (wu + 2 wv) / 6, moved to the start
    moment = (v - u) ** 2 * (wu + 2.0 * wv) / 6.0 + share * (u - starts)
    return share, moment


def _link_frames(model) -> list[int]:
    """Frame ids of each link's start (x along the link), link 0 first (found once)."""
    ids = model._cache.get("link_frames")
    if ids is None:
        pm = model.pin_model
        names = ["link_0"] + [node_links(j, model.axes)[-1]
                              for j in range(1, model.n_joints + 1)]
        ids = model._cache["link_frames"] = [pm.getFrameId(n) for n in names]
    return ids


def distributed_column(model, q: np.ndarray, load: DistributedLoad | None, axis: int,
                       data: pin.Data | None = None) -> np.ndarray:
    """Return the generalized force of a unit distributed load along world ``axis``, (nv,).

    N m per N/m (m^2): sum over the links of J(c_i)^T e_axis F_i (module notes).
    """
    pm = model.pin_model
    d = model.default_data if data is None else data
    share, moment = link_resultants(model.lengths_m, load)
    pin.computeJointJacobians(pm, d, q)
    pin.updateFramePlacements(pm, d)
    out = np.zeros(pm.nv)
    for fid, F, Q in zip(_link_frames(model), share, moment, strict=True):
        if F == 0.0 and Q == 0.0:
            continue
        J = pin.getFrameJacobian(pm, d, fid, pin.LOCAL_WORLD_ALIGNED)
        ex = d.oMf[fid].rotation[:, 0]  # the link's axis, world
        # a point s along the link moves by v_f + omega x (s ex): the load's work is
        # e . v_f F + e . (omega x ex) Q; component `axis` of omega_j x ex for each joint j
        i1, i2 = (axis + 1) % 3, (axis + 2) % 3
        cross = J[3 + i1] * ex[i2] - J[3 + i2] * ex[i1]
        out += F * J[axis] + Q * cross
    return out


def follower_moment_columns(model, q: np.ndarray, data: pin.Data | None = None) -> np.ndarray:
    """Return the columns of unit follower moments about the tip frame's x, y, z, (nv, 3)."""
    d = model.default_data if data is None else data
    J = pin.computeFrameJacobian(model.pin_model, d, q, model.tip_frame_id, pin.LOCAL)
    return J.reshape(6, -1)[3:].T


def base_accel_columns(model, q: np.ndarray) -> np.ndarray:
    """Return the columns of unit base accelerations along world x, y, z, (nv, 3), kg m.

    Each is the generalized gravity of the chain under the unit gravity e_k (module notes).
    """
    pm = model._cache.get("unit_gravity")
    if pm is None:
        pm = model._cache["unit_gravity"] = pin.Model(model.pin_model)
        model._cache["unit_gravity_data"] = pm.createData()
    d = model._cache["unit_gravity_data"]
    out = np.empty((pm.nv, 3))
    for k in range(3):
        pm.gravity = pin.Motion(np.r_[np.eye(3)[k], 0.0, 0.0, 0.0])
        out[:, k] = pin.computeGeneralizedGravity(pm, d, q)
    return out
