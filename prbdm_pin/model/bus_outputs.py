"""Plant outputs of a model on a free bus: the bus's pose and rate, and the member's outputs.

- ``bus_position_x``, ``bus_position_y``, ``bus_position_z``: the bus frame's origin in the
  world, m
- ``bus_attitude_x``, ``bus_attitude_y``, ``bus_attitude_z``: roll, pitch and yaw of the bus
  (R = Rz(yaw) Ry(pitch) Rx(roll)), rad
- ``bus_rate_x``, ``bus_rate_y``, ``bus_rate_z``: the bus's angular velocity in the bus frame
  (what a gyro on the bus reads), rad/s
- every output of the clamped member (:mod:`prbdm_pin.model.outputs`: ``tip_z``, ``q[j]``...),
  measured relative to the bus: in the clamp frame (the bus frame moved to the root,
  ``FreeBus.root_m``), from the member's own coordinates, as the clamped model measures them
  (the model's :attr:`~prbdm_pin.PrbdmModel.member`): ``tip_z`` is 0 on the unbent member.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from .outputs import output_maps, output_samples, output_unit, output_values, parse_outputs
from .supports import N_BASE, euler_rate_matrix

__all__ = ["BUS_OUTPUT_UNITS", "parse_bus_outputs", "bus_output_unit", "bus_output_maps",
           "bus_output_values", "bus_output_samples"]

_AXES = {"x": 0, "y": 1, "z": 2}
BUS_OUTPUT_UNITS = {**{f"bus_position_{a}": "m" for a in _AXES},
                    **{f"bus_attitude_{a}": "rad" for a in _AXES},
                    **{f"bus_rate_{a}": "rad/s" for a in _AXES}}
# the base coordinate of each attitude angle: q = [x, y, z, yaw, pitch, roll, ...]
_ANGLE_INDEX = {"x": 5, "y": 4, "z": 3}


def parse_bus_outputs(names, n_springs: int) -> tuple[str, ...]:
    """Check output names against a bus model (``n_springs`` member springs); return them.

    Raises BeamInputError naming ``outputs[i]`` for a name neither the bus's nor the member's.
    """
    if isinstance(names, str) or not isinstance(names, (list, tuple)) or not names:
        raise BeamInputError(f"outputs = {names!r}: must be a non-empty sequence of names")
    for i, name in enumerate(names):
        if name in BUS_OUTPUT_UNITS:
            continue
        try:
            parse_outputs([name], n_springs, False)
        except BeamInputError as exc:
            bus = ", ".join(BUS_OUTPUT_UNITS)
            raise BeamInputError(f"outputs[{i}] = {name!r}: not an output of a bus model "
                                 f"({str(exc).split(': ', 1)[-1]}; or one of {bus})") from None
    if len(set(names)) != len(names):
        raise BeamInputError(f"outputs = {list(names)!r}: a name appears twice")
    return tuple(names)


def bus_output_unit(name: str) -> str:
    """Return the unit of output ``name`` of a bus model."""
    return BUS_OUTPUT_UNITS.get(name) or output_unit(name)


def _rpy(q: np.ndarray) -> np.ndarray:
    return np.asarray(q, dtype=float)[[5, 4, 3]]


def bus_output_maps(model, q: np.ndarray, names) -> tuple[np.ndarray, np.ndarray]:
    """Return (C_q, C_v), each (p, nv): the outputs' derivatives at pose ``q`` at rest.

    The bus rate is E(q) [roll', pitch', yaw'] (:func:`~prbdm_pin.model.supports.
    euler_rate_matrix`): linear in the rates, so its C_q vanishes at rest.
    """
    names = parse_bus_outputs(names, model.n_springs)
    nv = model.pin_model.nv
    Cq, Cv = np.zeros((len(names), nv)), np.zeros((len(names), nv))
    E = euler_rate_matrix(_rpy(q))
    for r, name in enumerate(names):
        kind, _, axis = name.rpartition("_")
        if kind == "bus_position":
            Cq[r, _AXES[axis]] = 1.0
        elif kind == "bus_attitude":
            Cq[r, _ANGLE_INDEX[axis]] = 1.0
        elif kind == "bus_rate":
            Cv[r, [5, 4, 3]] = E[_AXES[axis]]
        else:
            cq, cv = output_maps(model.member, q[N_BASE:], [name])
            Cq[r, N_BASE:], Cv[r, N_BASE:] = cq[0], cv[0]
    return Cq, Cv


def bus_output_values(model, q: np.ndarray, names) -> np.ndarray:
    """Return the outputs' values at rest at pose ``q`` (m, rad, N m; rates 0), shape (p,)."""
    names = parse_bus_outputs(names, model.n_springs)
    out = np.zeros(len(names))
    for r, name in enumerate(names):
        kind, _, axis = name.rpartition("_")
        if kind == "bus_position":
            out[r] = q[_AXES[axis]]
        elif kind == "bus_attitude":
            out[r] = q[_ANGLE_INDEX[axis]]
        elif kind != "bus_rate":
            out[r] = output_values(model.member, q[N_BASE:], [name])[0]
    return out


def bus_output_samples(model, Q: np.ndarray, V: np.ndarray, tip_m: np.ndarray, names
                       ) -> np.ndarray:
    """Return the outputs along a trajectory, shape (s, p).

    From the coordinates ``Q`` (m, rad) and rates ``V`` (m/s, rad/s), (s, nv), with the
    member's tip positions in the clamp frame ``tip_m`` (s, 3), m.
    """
    names = parse_bus_outputs(names, model.n_springs)
    out = np.zeros((len(Q), len(names)))
    for r, name in enumerate(names):
        kind, _, axis = name.rpartition("_")
        if kind == "bus_position":
            out[:, r] = Q[:, _AXES[axis]]
        elif kind == "bus_attitude":
            out[:, r] = Q[:, _ANGLE_INDEX[axis]]
        elif kind == "bus_rate":
            out[:, r] = [euler_rate_matrix(_rpy(q))[_AXES[axis]] @ v[[5, 4, 3]]
                         for q, v in zip(Q, V, strict=True)]
        else:
            out[:, r] = output_samples(model.member, Q[:, N_BASE:], V[:, N_BASE:], tip_m,
                                       [name])[:, 0]
    return out
