"""Plant outputs chosen by name, as rows of the linear map y = C_q dq + C_v dv.

Every output is a deviation from its value at the equilibrium (:func:`output_values` gives
those values). Beam joints are numbered 0..n-1 from the root (Pinocchio's ``joint_{j+1}``);
on a hub model the hub angle is a coordinate of its own.

- ``tip_z``, ``tip_x``, ``tip_y``: world tip displacement, m; ``tip_z_rate``: its z velocity,
  m/s
- ``tip_twist``: the tip section's rotation about the tip link's own axis, rad (the roll of the
  tip frame, :mod:`prbdm_pin.chain.points`; 0 on a planar chain)
- ``corner_z_left``, ``corner_z_right``: world z displacement of the tip corners, m (at +/- the
  tip half-width along the tip link's y axis; models with their beam only)
- ``q[j]``: joint angle, rad; ``q_rate[j]``: its rate, rad/s
- ``spring_torque[j]``: k_j q_j, N m (the spring's moment; for a 1R PRBDM the root moment)
- ``hub_angle``, rad; ``hub_rate``, rad/s (hub models only)
- ``slope@X``, ``twist@X``: the section's rotations at station X (m from the root) about y and
  about the link's axis, rad; ``point_x@X:Y``, ``point_y@X:Y``, ``point_z@X:Y``: the world
  displacement of the planform point X along, Y across the beam, m
  (:mod:`prbdm_pin.model.stations`)
- ``strain@X``: the surface bending strain at station X, microstrain, positive for a bending
  that makes ``tip_z`` positive (:mod:`prbdm_pin.model.strain`)
- ``root_force_x|y|z``, N, ``root_moment_x|y|z``, N m: the wrench the member exerts on its
  support about the root point, base frame (:mod:`prbdm_pin.model.reaction`)

The strain and the root reaction read the loads (the acceleration and the applied inputs):
:mod:`prbdm_pin.model.load_outputs` gives their rows and values; here they have zero rows.
"""

from __future__ import annotations

import numpy as np

from .load_outputs import is_load_output, load_output_samples, load_output_values
from .names import parse_names
from .reaction import REACTION_OUTPUTS
from .stations import (
    check_point,
    check_station,
    point_displacement,
    point_position,
    slope,
    twist,
)
from .strain import strain_terms

__all__ = ["OUTPUT_UNITS", "CORNER_OUTPUTS", "STATION_OUTPUTS", "parse_outputs",
           "check_output_stations", "output_maps", "output_values", "output_unit",
           "output_samples"]

OUTPUT_UNITS = {"tip_z": "m", "tip_x": "m", "tip_y": "m", "tip_z_rate": "m/s", "tip_twist": "rad",
                "corner_z_left": "m", "corner_z_right": "m", "q": "rad", "q_rate": "rad/s",
                "spring_torque": "N m", "hub_angle": "rad", "hub_rate": "rad/s",
                "slope": "rad", "twist": "rad", "point_x": "m", "point_y": "m", "point_z": "m",
                "strain": "microstrain", **{b: "N" if "force" in b else "N m"
                                            for b in REACTION_OUTPUTS}}
# the station outputs and how many coordinates their station has (X, or X:Y)
STATION_OUTPUTS = {"strain": 1, "slope": 1, "twist": 1, "point_x": 2, "point_y": 2,
                   "point_z": 2}
_POINT_ROW = {"point_x": 0, "point_y": 1, "point_z": 2}
# the corner outputs and the point each reads (:mod:`prbdm_pin.chain.points`)
CORNER_OUTPUTS = {"corner_z_left": "tip_corner_left", "corner_z_right": "tip_corner_right"}


def parse_outputs(names, n_joints: int, hub: bool):
    """Check output names against a model; returns (name, base, index) per output.

    ``n_joints`` is the number of spring coordinates ``q[j]`` indexes (a spatial chain's
    ``n_springs``).
    """
    plain = ("tip_z", "tip_z_rate", "tip_x", "tip_y", "tip_twist", *CORNER_OUTPUTS,
             *REACTION_OUTPUTS) + (("hub_angle", "hub_rate") if hub else ())
    indexed = {"q": n_joints, "q_rate": n_joints, "spring_torque": n_joints}
    return parse_names(names, "outputs", indexed, plain, STATION_OUTPUTS)


def check_output_stations(model, names) -> None:
    """Refuse station outputs off the member or the planform (BeamInputError naming them).

    ``outputs[i] = 'strain@2'`` for a station outside [0, L], a point beyond the half-width,
    or a strain or a point on a model without its beam.
    """
    parsed = parse_outputs(names, model.n_springs, model.hub is not None)
    for i, (name, base, idx) in enumerate(parsed):
        where = f"outputs[{i}] = {name!r}"
        if base == "strain":
            strain_terms(model, idx[0], where)
        elif base in _POINT_ROW:
            check_point(model, idx[0], idx[1], where)
        elif base in STATION_OUTPUTS:
            check_station(model, idx[0], where)


def output_maps(model, q: np.ndarray, names) -> tuple[np.ndarray, np.ndarray]:
    """Return (C_q, C_v), each shape (p, nv): the outputs' derivatives at pose ``q`` (rad).

    The derivatives are with respect to the joint angles (per rad) and rates (per rad/s).
    """
    hub = model.hub is not None
    parsed = parse_outputs(names, model.n_springs, hub)
    nv, off = model.pin_model.nv, int(hub)
    J = model.tip_jacobian(q)
    Cq = np.zeros((len(parsed), nv))
    Cv = np.zeros((len(parsed), nv))
    for r, (_, base, idx) in enumerate(parsed):
        if base == "tip_z":
            Cq[r] = J[2]
        elif base == "tip_x":
            Cq[r] = J[0]
        elif base == "tip_y":
            Cq[r] = J[1]
        elif base == "tip_twist":
            Cq[r] = model.tip_twist(q)[1]
        elif base in CORNER_OUTPUTS:
            Cq[r] = model.point_kinematics(CORNER_OUTPUTS[base], q)[1][2]
        elif base == "slope":
            Cq[r] = slope(model, q, idx[0])[1]
        elif base == "twist":
            Cq[r] = twist(model, q, idx[0])[1]
        elif base in _POINT_ROW:
            Cq[r] = point_displacement(model, q, *idx)[1][_POINT_ROW[base]]
        elif is_load_output(base):
            continue  # rows from load_output_rows
        elif base == "tip_z_rate":
            Cv[r] = J[2]
        elif base == "q":
            Cq[r, off + idx] = 1.0
        elif base == "q_rate":
            Cv[r, off + idx] = 1.0
        elif base == "spring_torque":
            Cq[r, off + idx] = model.stiffness_Nm_per_rad[idx]
        elif base == "hub_angle":
            Cq[r, 0] = 1.0
        else:  # hub_rate
            Cv[r, 0] = 1.0
    return Cq, Cv


def output_values(model, q: np.ndarray, names, load_N: np.ndarray | None = None,
                  gravity_m_s2: np.ndarray | None = None) -> np.ndarray:
    """Return the outputs' values at rest at pose ``q`` (rad), shape (p,).

    Tip and corner coordinates (m), angles (rad), spring torques (N m), rates 0; the strain
    and the root reaction under the dead tip force ``load_N`` (N, world) and gravity
    ``gravity_m_s2`` (m/s^2, world), both default none.
    """
    hub = model.hub is not None
    parsed = parse_outputs(names, model.n_springs, hub)
    off = int(hub)
    p = model.tip_position(q)
    z = np.zeros(model.pin_model.nv)
    loads = {} if load_N is None else {"tip_force": np.asarray(load_N, dtype=float)}
    out = load_output_values(model, q, z, z, parsed, loads, gravity_m_s2)
    for r, (_, base, idx) in enumerate(parsed):
        if base == "tip_z":
            out[r] = p[2]
        elif base == "tip_x":
            out[r] = p[0]
        elif base == "tip_y":
            out[r] = p[1]
        elif base == "tip_twist":
            out[r] = model.tip_twist(q)[0]
        elif base in CORNER_OUTPUTS:
            out[r] = model.point_kinematics(CORNER_OUTPUTS[base], q)[0][2]
        elif base in STATION_OUTPUTS and not is_load_output(base):
            out[r] = _station_value(model, q, base, idx)
        elif base == "q":
            out[r] = q[off + idx]
        elif base == "spring_torque":
            out[r] = model.stiffness_Nm_per_rad[idx] * q[off + idx]
        elif base == "hub_angle":
            out[r] = q[0]
    return out


def _station_value(model, q, base, idx, data=None) -> float:
    if base == "slope":
        return slope(model, q, idx[0], data)[0]
    if base == "twist":
        return twist(model, q, idx[0], data)[0]
    return float(point_displacement(model, q, *idx, data)[0][_POINT_ROW[base]])


def output_unit(name: str) -> str:
    """Return the unit of the output ``name``."""
    return OUTPUT_UNITS[name.split("[")[0].split("@")[0]]


def output_samples(model, Q: np.ndarray, V: np.ndarray, tip_m: np.ndarray, names,
                   A: np.ndarray | None = None, loads=None,
                   gravity_m_s2: np.ndarray | None = None) -> np.ndarray:
    """Return the outputs' values along a trajectory (not deviations), shape (s, p).

    From joint angles ``Q`` (rad) and rates ``V`` (rad/s), (s, nv), with the tip positions
    ``tip_m`` (s, 3), m. The strain and the root reaction need the accelerations ``A``
    (rad/s^2, (s, nv)), the applied loads at each sample ``loads`` (a sequence of the dicts
    :func:`prbdm_pin.model.load_outputs.load_output_values` takes) and the gravity
    ``gravity_m_s2`` (m/s^2, world).
    """
    hub = model.hub is not None
    parsed = parse_outputs(names, model.n_springs, hub)
    off = int(hub)
    out = np.zeros((len(Q), len(parsed)))
    if any(is_load_output(b) for _, b, _ in parsed):
        if A is None or loads is None:
            raise ValueError("output_samples: the strain and the root reaction need the "
                             "accelerations and the loads")
        out += load_output_samples(model, Q, V, A, parsed, loads, gravity_m_s2)
    tip_rate = None
    for r, (_, base, idx) in enumerate(parsed):
        if base == "tip_z":
            out[:, r] = tip_m[:, 2]
        elif base == "tip_x":
            out[:, r] = tip_m[:, 0]
        elif base == "tip_y":
            out[:, r] = tip_m[:, 1]
        elif base == "tip_twist" or base in CORNER_OUTPUTS:
            data = model.new_data()
            out[:, r] = [model.tip_twist(q, data)[0] if base == "tip_twist" else
                         model.point_kinematics(CORNER_OUTPUTS[base], q, data)[0][2] for q in Q]
        elif is_load_output(base):
            continue
        elif base in _POINT_ROW:  # the straight member's position once, not per sample
            data, k = model.new_data(), _POINT_ROW[base]
            p0 = point_position(model, np.zeros(model.pin_model.nq), *idx, data)[0][k]
            out[:, r] = [point_position(model, q, *idx, data)[0][k] - p0 for q in Q]
        elif base in STATION_OUTPUTS:
            data = model.new_data()
            out[:, r] = [_station_value(model, q, base, idx, data) for q in Q]
        elif base == "tip_z_rate":
            if tip_rate is None:
                data = model.new_data()
                tip_rate = np.array([model.tip_jacobian(q, data)[2] @ v
                                     for q, v in zip(Q, V, strict=True)])
            out[:, r] = tip_rate
        elif base == "q":
            out[:, r] = Q[:, off + idx]
        elif base == "q_rate":
            out[:, r] = V[:, off + idx]
        elif base == "spring_torque":
            out[:, r] = model.stiffness_Nm_per_rad[idx] * Q[:, off + idx]
        elif base == "hub_angle":
            out[:, r] = Q[:, 0]
        else:  # hub_rate
            out[:, r] = V[:, 0]
    return out
