"""``linearize`` of a model on a free bus: six rigid modes and the constrained-free flexible ones.

A free bus has an equilibrium at every bus pose with the member unbent and no load: the bus
drifts under a constant force and gravity accelerates it whole, so neither is taken. About a
pose q_eq (default zero) at rest the linear plant is

    M(q_eq) dv' + C_d dv + K dq = B_q u,   K = diag(0 (six), springs),

(the velocity terms of the dynamics are quadratic in v and vanish at rest) with the damping of
:func:`prbdm_pin.simulation.hub_damping.plant_damping` on the flexible modes only. Inputs act
in the world frame on the whole system (``tip_force_*``, ``tip_moment_*``, ``corner_force_*``)
or on the member's joints (``joint_torque[j]``, ``strain[i]``: coordinates 6 + j); outputs are
:mod:`prbdm_pin.model.bus_outputs`'s. The modal view takes the six rigid modes out exactly
(:func:`prbdm_pin.model.supports.free_modes_of`).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..model.bus_outputs import (
    bus_output_maps,
    bus_output_unit,
    bus_output_values,
    parse_bus_outputs,
)
from ..model.inputs import check_corner_names, input_map, input_unit, parse_inputs
from ..model.supports import BASE_JOINTS, N_BASE
from ..simulation.hub_damping import plant_damping
from .equilibrium import check_vector
from .state_space import LinearModel

__all__ = ["linearize_bus"]


def linearize_bus(model, inputs, outputs, q_eq, load_N, damping_ratio, damping, actuators,
                  gravity_m_s2) -> LinearModel:
    """Linearise ``model`` (a PrbdmModel with a FreeBus) about a pose at rest.

    The arguments are :func:`prbdm_pin.linearize`'s (``actuators`` already checked); ``load_N``
    and ``gravity_m_s2`` must be absent or zero (BeamInputError naming them).
    """
    from .linearize import first_order

    for field, value, unit in (("load_N", load_N, "N"), ("gravity_m_s2", gravity_m_s2,
                                                         "m/s^2")):
        v = check_vector(field, value, unit)
        if v is not None and np.any(v):
            raise BeamInputError(f"{field} = {value!r}: a free bus has no equilibrium under a "
                                 "constant load or gravity (the whole system accelerates)")
    n = model.n_springs
    acts = tuple(actuators)
    in_names = tuple(name for name, _, _ in parse_inputs(inputs, n, len(acts), False))
    out_names = parse_bus_outputs(outputs, n)
    check_corner_names(model, in_names, "inputs")
    check_corner_names(model.member, out_names, "outputs")
    q = _pose(model, q_eq)
    # world forces and moments through the whole system's Jacobians, torques and patch moments
    # on the member's coordinates (after the six base ones)
    Bq = input_map(model, q, in_names, acts)
    Cq, Cv = bus_output_maps(model, q, out_names)
    M = model.mass_matrix(q)
    K = model.stiffness_matrix()
    Cd = plant_damping(model, M, damping_ratio, damping)
    A, B, _ = first_order(M, K, Cd, Bq)
    coords = [name for name, _ in BASE_JOINTS] + [f"q[{j}]" for j in range(n)]
    states = tuple(coords + [c.replace("q[", "q_rate[") if c.startswith("q[") else c + "_rate"
                             for c in coords])
    y_eq = bus_output_values(model, q, out_names)
    u_eq = np.zeros(len(in_names))
    Cfull, D = np.hstack([Cq, Cv]), np.zeros((len(out_names), len(in_names)))
    for a in (A, B, Cq, Cv, M, K, Cd, Bq, q, u_eq, Cfull, D, y_eq):
        a.setflags(write=False)
    return LinearModel(
        A=A, B=B, C=Cfull, D=D, state_names=states, input_names=in_names,
        output_names=out_names, input_units=tuple(input_unit(s) for s in in_names),
        output_units=tuple(bus_output_unit(s) for s in out_names), q_eq=q, u_eq=u_eq,
        y_eq=y_eq, mass_kg_m2=M, stiffness_Nm_per_rad=K, damping_Nms_per_rad=Cd,
        input_map=Bq, output_map_position=Cq, output_map_rate=Cv, hub=False, n_free=N_BASE,
    )


def _pose(model, q_eq) -> np.ndarray:
    """Return the pose (nv,): the bus's six coordinates (m, rad), the member's zero."""
    nv = model.pin_model.nv
    if q_eq is None:
        return np.zeros(nv)
    try:
        q = np.array(q_eq, dtype=float)
    except (TypeError, ValueError):
        q = np.array([np.nan])
    if q.shape != (nv,) or not np.all(np.isfinite(q)):
        raise BeamInputError(f"q_eq = {q_eq!r}: must be {nv} finite numbers (the bus's x, y, z "
                             "m and yaw, pitch, roll rad first, then the member's angles)")
    if np.any(q[N_BASE:]):
        raise BeamInputError(f"q_eq = {q_eq!r}: the member must be unbent (its springs hold no "
                             "bent pose of a free bus at rest)")
    # yaw and roll turn about one axis there: cond(M) grows as 1 / cos(pitch)^2, 1e6 at 1e-3
    if abs(np.cos(q[4])) < 1e-3:
        raise BeamInputError(f"q_eq: pitch = {q[4]:g} rad is at the Euler angles' singularity "
                             "(+/- pi/2)")
    return q
