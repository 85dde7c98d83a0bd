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
"""

from __future__ import annotations

import numpy as np

from .names import parse_names

__all__ = ["OUTPUT_UNITS", "CORNER_OUTPUTS", "parse_outputs", "output_maps", "output_values",
           "output_unit", "output_samples"]

OUTPUT_UNITS = {"tip_z": "m", "tip_x": "m", "tip_y": "m", "tip_z_rate": "m/s", "tip_twist": "rad",
                "corner_z_left": "m", "corner_z_right": "m", "q": "rad", "q_rate": "rad/s",
                "spring_torque": "N m", "hub_angle": "rad", "hub_rate": "rad/s"}
# the corner outputs and the point each reads (:mod:`prbdm_pin.chain.points`)
CORNER_OUTPUTS = {"corner_z_left": "tip_corner_left", "corner_z_right": "tip_corner_right"}


def parse_outputs(names, n_joints: int, hub: bool):
    """Check output names against a model; returns (name, base, index) per output.

    ``n_joints`` is the number of spring coordinates ``q[j]`` indexes (a spatial chain's
    ``n_springs``).
    """
    plain = ("tip_z", "tip_z_rate", "tip_x", "tip_y", "tip_twist", *CORNER_OUTPUTS) + (
        ("hub_angle", "hub_rate") if hub else ())
    indexed = {"q": n_joints, "q_rate": n_joints, "spring_torque": n_joints}
    return parse_names(names, "outputs", indexed, plain)


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


def output_values(model, q: np.ndarray, names) -> np.ndarray:
    """Return the outputs' values at rest at pose ``q`` (rad), shape (p,).

    Tip and corner coordinates (m), angles (rad), spring torques (N m), rates 0.
    """
    hub = model.hub is not None
    parsed = parse_outputs(names, model.n_springs, hub)
    off = int(hub)
    p = model.tip_position(q)
    out = np.zeros(len(parsed))
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
        elif base == "q":
            out[r] = q[off + idx]
        elif base == "spring_torque":
            out[r] = model.stiffness_Nm_per_rad[idx] * q[off + idx]
        elif base == "hub_angle":
            out[r] = q[0]
    return out


def output_unit(name: str) -> str:
    """Return the unit of the output ``name``."""
    return OUTPUT_UNITS[name.split("[")[0]]


def output_samples(model, Q: np.ndarray, V: np.ndarray, tip_m: np.ndarray, names
                   ) -> np.ndarray:
    """Return the outputs' values along a trajectory (not deviations), shape (s, p).

    From joint angles ``Q`` (rad) and rates ``V`` (rad/s), (s, nv), with the tip positions
    ``tip_m`` (s, 3), m.
    """
    hub = model.hub is not None
    parsed = parse_outputs(names, model.n_springs, hub)
    off = int(hub)
    out = np.zeros((len(Q), len(parsed)))
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
