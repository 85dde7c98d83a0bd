"""The root reaction: the wrench the member exerts on its support at its root.

``root_force_x|y|z`` (N) and ``root_moment_x|y|z`` (N m, about the root point) are the force
and moment the member exerts on its support (the world for a clamped member, the hub for a hub
model: what a load cell under the root reads, what the bus or the robot's flange carries), in
the base frame (the world's axes; the hub's, turning with it, on a hub model). They are -R,
R the wrench the support exerts on the member, which Newton-Euler for the whole member gives:

    R = sum_i (m_i a_ci - m_i g)  (and the moments about the root)  - W_applied

with W_applied the applied loads' resultant (tip forces, tip moments, corner forces, and the
loads of :mod:`prbdm_pin.model.load_wrench`: follower moments, distributed forces, a base
acceleration's d'Alembert load; joint torques, strain actuators and the hub torque are internal
to the member or act on the hub, so they add none). Under a static tip force F at r_tip (from
the root) the member passes on (F, r_tip x F).

The inertial and weight part is Pinocchio's: the chain is rebuilt with a free-flyer joint at
the root (carrying link 0; on a hub model between the hub and link 0) whose motion is held at
zero, and the RNEA's generalized force of that joint is the wrench the support must exert, in
the joint's frame (the base frame at the root point) (:func:`floating_root`). Its derivatives
in the chain's angles, rates and accelerations are Pinocchio's analytic RNEA derivatives, so
the linear model's acceleration path y = H a + ... has H = dR/da exactly.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from .inputs import CORNER_INPUTS
from .load_wrench import WRENCH_INPUTS, wrench_column

__all__ = ["REACTION_OUTPUTS", "LOAD_INPUTS", "INTERNAL_INPUTS", "floating_root",
           "inertial_wrench", "inertial_wrench_derivatives", "applied_wrench",
           "applied_wrench_columns", "check_load_inputs", "input_loads"]

# output base -> row of the 6-vector (force; moment)
REACTION_OUTPUTS = {"root_force_x": 0, "root_force_y": 1, "root_force_z": 2,
                    "root_moment_x": 3, "root_moment_y": 4, "root_moment_z": 5}
# inputs whose load is applied to the member (tip and corner forces, tip moments), and those
# that act inside it or on the hub (no resultant on the member)
LOAD_INPUTS = {"tip_force_x": ("force", 0), "tip_force_y": ("force", 1),
               "tip_force_z": ("force", 2), "tip_moment_x": ("moment", 0),
               "tip_moment_y": ("moment", 1), "tip_moment_z": ("moment", 2),
               **{c: ("corner", 2) for c in CORNER_INPUTS}}
INTERNAL_INPUTS = ("joint_torque", "strain", "hub_torque")
_NEUTRAL = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])  # the free flyer held at the root


def floating_root(model, gravity_m_s2: np.ndarray | None = None
                  ) -> tuple[pin.Model, pin.Data, np.ndarray, np.ndarray]:
    """Return the chain on a free-flyer root joint, its workspace and the index maps.

    The maps are the free flyer's velocity indices (6,) and the chain's coordinates' (nv,) in
    the rebuilt model. Built once per model and gravity (m/s^2, world) and kept in its cache.
    """
    g = np.zeros(3) if gravity_m_s2 is None else np.asarray(gravity_m_s2, dtype=float)
    key = ("floating_root", tuple(g))
    if key in model._cache:
        return model._cache[key]
    pm, s = model.pin_model, model.sections
    hub = model.hub is not None
    link0 = pin.Inertia(float(s.mass_kg[0]), s.com_m[0] - np.array([s.start_m[0], 0.0, 0.0]),
                        s.inertia_com_kg_m2[0])
    fm = pin.Model()
    fm.name = f"{pm.name}_floating_root"
    root = pin.SE3.Identity()
    if hub:
        h = fm.addJoint(0, pm.joints[1], pm.jointPlacements[1], pm.names[1])
        fm.appendBodyToJoint(h, pin.Inertia(0.0, np.zeros(3),
                                            model.hub.inertia_kg_m2 * np.eye(3)),
                             pin.SE3.Identity())
        root = pin.SE3(np.eye(3), np.array([model.hub.radius_m, 0.0, 0.0]))
    ff = fm.addJoint(int(hub), pin.JointModelFreeFlyer(), root, "root")
    fm.appendBodyToJoint(ff, link0, pin.SE3.Identity())
    for i in range(1 + int(hub), pm.njoints):
        parent = pm.parents[i]
        place = pm.jointPlacements[i]
        if parent == int(hub):  # the first beam joint: placed from the root, not the hub axis
            place = root.inverse() * place
        jid = fm.addJoint(ff if parent == int(hub) else parent + 1, pm.joints[i], place,
                          pm.names[i])
        fm.appendBodyToJoint(jid, pm.inertias[i], pin.SE3.Identity())
    fm.gravity = pin.Motion(np.concatenate([g, np.zeros(3)]))
    ff_idx = np.arange(6) + int(hub)
    chain = np.concatenate([[0], np.arange(7, fm.nv)]) if hub else np.arange(6, fm.nv)
    out = (fm, fm.createData(), ff_idx, chain.astype(int))
    model._cache[key] = out
    return out


def _extend(model, x: np.ndarray, held: np.ndarray) -> np.ndarray:
    """Insert the held root joint's coordinates into a chain vector (hub first, then root)."""
    x = np.asarray(x, dtype=float)
    if model.hub is not None:
        return np.concatenate([x[:1], held, x[1:]])
    return np.concatenate([held, x])


def inertial_wrench(model, q: np.ndarray, v: np.ndarray, a: np.ndarray,
                    gravity_m_s2: np.ndarray | None = None) -> np.ndarray:
    """Return sum_i (m_i a_ci - m_i g) and its moment about the root, base frame, (6,).

    From the chain's angles ``q`` (rad), rates ``v`` (rad/s) and accelerations ``a``
    (rad/s^2): N then N m, the part of the root reaction the member's motion and weight make.
    """
    fm, fd, ff, _ = floating_root(model, gravity_m_s2)
    z = np.zeros(6)
    tau = pin.rnea(fm, fd, _extend(model, q, _NEUTRAL), _extend(model, v, z),
                   _extend(model, a, z))
    return tau[ff].copy()


def inertial_wrench_derivatives(model, q: np.ndarray, v: np.ndarray, a: np.ndarray,
                                gravity_m_s2: np.ndarray | None = None
                                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the derivatives of :func:`inertial_wrench` in q, v and a, each (6, nv).

    Pinocchio's analytic RNEA derivatives; the acceleration one is the mass matrix's coupling
    of the root joint to the chain (Pinocchio fills the upper triangle of M: completed here).
    """
    fm, fd, ff, chain = floating_root(model, gravity_m_s2)
    z = np.zeros(6)
    dq, dv, M = pin.computeRNEADerivatives(fm, fd, _extend(model, q, _NEUTRAL),
                                           _extend(model, v, z), _extend(model, a, z))
    M = np.triu(M) + np.triu(M, 1).T
    return (np.asarray(dq)[np.ix_(ff, chain)], np.asarray(dv)[np.ix_(ff, chain)],
            M[np.ix_(ff, chain)])


def _base(model, q: np.ndarray, data) -> tuple[np.ndarray, np.ndarray]:
    """World rotation of the base (the hub's, or I) and the root point's world position, m."""
    if model.hub is None:
        return np.eye(3), np.zeros(3)
    R = pin.exp3(_hub_axis(model) * q[0])  # the hub's turn about its axis
    return R, R @ np.array([model.hub.radius_m, 0.0, 0.0])


def _hub_axis(model) -> np.ndarray:
    return np.eye(3)["xyz".index(getattr(model.hub, "axis", "y"))]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    # numpy's cross costs tens of microseconds on 3-vectors; a time response calls this per sample
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _points(model, q, data, loads: dict[str, np.ndarray], jacobian: bool):
    """(world position, linear Jacobian or None, world force, world moment) of each load."""
    out = []
    f, m = loads.get("tip_force"), loads.get("tip_moment")
    if (f is not None and f.any()) or (m is not None and m.any()):
        p, J = model.tip_kinematics(q, data) if jacobian else (model.tip_position(q, data), None)
        out.append((p, J, np.zeros(3) if f is None else f, np.zeros(3) if m is None else m))
    for base, point in CORNER_INPUTS.items():
        fz = loads.get(base, 0.0)
        if fz:
            p, J = model.point_kinematics(point, q, data)
            out.append((p, J, np.array([0.0, 0.0, fz]), np.zeros(3)))
    return out


def applied_wrench(model, q: np.ndarray, loads: dict[str, np.ndarray],
                   data: pin.Data | None = None, derivative: bool = False):
    """Return the applied loads' resultant about the root, base frame, (6,): N, N m.

    ``loads``: ``tip_force`` (N, world, at the tip centre), ``tip_moment`` (N m, world), the
    corner forces by their input names (N, world z), and ``extra``: (input base name, index,
    value) of the loads of :mod:`prbdm_pin.model.load_wrench` over the DistributedLoad spans
    ``spans``. With ``derivative``, also its derivative
    in the angles (6, nv) (dead loads: the points move, the base turns on a hub model).
    """
    R, p0 = _base(model, q, data)
    W = np.zeros(6)
    dW = np.zeros((6, model.pin_model.nv))
    for p, J, f, m in _points(model, q, data, loads, derivative):
        W[:3] += f
        W[3:] += _cross(p - p0, f) + m
        if derivative:
            dp = J.copy()
            if model.hub is not None:  # the root point turns with the hub
                dp[:, 0] -= _cross(_hub_axis(model), p0)
            dW[3:] += -pin.skew(f) @ dp  # d(r x f) = dr x f = -f x dr
    for base, idx, value in loads.get("extra", ()):
        if value:  # the pose derivative is not needed: these hold no load at an equilibrium
            W += value * wrench_column(model, q, base, idx, loads.get("spans", ()), p0, data)
    Wb = np.concatenate([R.T @ W[:3], R.T @ W[3:]])
    if not derivative:
        return Wb
    dWb = np.vstack([R.T @ dW[:3], R.T @ dW[3:]])
    if model.hub is not None:  # d(R^T w)/d(hub angle) = -e x (R^T w), e the hub's axis
        e = _hub_axis(model)
        dWb[:3, 0] -= _cross(e, Wb[:3])
        dWb[3:, 0] -= _cross(e, Wb[3:])
    return Wb, dWb


def applied_wrench_columns(model, q: np.ndarray, parsed_inputs, field: str = "inputs",
                           data: pin.Data | None = None, spans: tuple = ()) -> np.ndarray:
    """Return the applied resultant per unit input (6, m), base frame, at ``q`` (rad).

    ``parsed_inputs`` as :func:`prbdm_pin.model.inputs.parse_inputs` returns them. An input
    this module does not know the resultant of is refused (BeamInputError naming
    ``field[i]``) rather than taken as none.
    """
    check_load_inputs(parsed_inputs, field)
    cols = np.zeros((6, len(parsed_inputs)))
    for c, (_, base, idx) in enumerate(parsed_inputs):
        if base in INTERNAL_INPUTS:
            continue
        if base in WRENCH_INPUTS:
            cols[:, c] = applied_wrench(model, q, {"extra": [(base, idx, 1.0)], "spans": spans},
                                        data)
            continue
        kind, k = LOAD_INPUTS[base]
        unit = np.zeros(3)
        unit[k] = 1.0
        key = {"force": "tip_force", "moment": "tip_moment", "corner": base}[kind]
        cols[:, c] = applied_wrench(model, q, {key: unit if kind != "corner" else 1.0}, data)
    return cols


def check_load_inputs(parsed_inputs, field: str = "inputs") -> None:
    """Refuse an input whose load on the member this module does not know.

    BeamInputError naming ``field[i]``: the root reaction and the strain would otherwise
    leave its load out.
    """
    for c, (name, base, _) in enumerate(parsed_inputs):
        if base not in INTERNAL_INPUTS and base not in LOAD_INPUTS \
                and base not in WRENCH_INPUTS:
            raise BeamInputError(f"{field}[{c}] = {name!r}: the root reaction and the strain "
                                 "do not know this input's load on the member")


def input_loads(parsed_inputs, u: np.ndarray, tip_force_N: np.ndarray | None = None,
                spans: tuple = ()) -> dict[str, np.ndarray]:
    """Return the applied loads of the input values ``u`` (their units) as a loads dict.

    Plus a tip force ``tip_force_N`` (N, world) from outside the inputs; the keys as
    :func:`applied_wrench` takes them; ``spans`` the DistributedLoad spans the indexed
    distributed forces act over.
    """
    force = np.zeros(3) if tip_force_N is None else np.array(tip_force_N, dtype=float)
    moment = np.zeros(3)
    loads: dict = {"extra": [], "spans": tuple(spans)}
    for (_, base, idx), value in zip(parsed_inputs, u, strict=True):
        if base in WRENCH_INPUTS:
            loads["extra"].append((base, idx, float(value)))
            continue
        if base not in LOAD_INPUTS:
            continue
        kind, k = LOAD_INPUTS[base]
        if kind == "force":
            force[k] += value
        elif kind == "moment":
            moment[k] += value
        else:
            loads[base] = float(value)
    loads["tip_force"], loads["tip_moment"] = force, moment
    return loads
