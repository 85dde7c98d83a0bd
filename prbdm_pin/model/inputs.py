"""Plant inputs and the generalized forces they make.

Tip forces (at the tip centre, world axes), the dead tip moments about world x, y, z, z forces
at the tip corners, joint torques, strain actuators and the hub torque; follower tip moments,
distributed forces and base accelerations (:mod:`prbdm_pin.model.loads`).

The tip corners are the points at +/- w(L) (the tip half-width) along the tip link's y axis
(:mod:`prbdm_pin.chain.points`): a corner force acts through that point's Jacobian, so it bends
and twists; at the straight pose a planar chain feels its bending part only. A spatial chain's
``joint_torque[j]`` indexes every spring coordinate (``PrbdmModel.spring_axes``).

Strain actuator (a full-width piezo patch between stations x_a < x_b of the beam, m from the
root along the undeformed beam): it bends the beam by a moment M (N m) applied as a pair, +M
about y at x_b and -M at x_a. Its virtual work is M (theta(x_b) - theta(x_a)) with theta(x) the
section rotation in the sense of the joint angles; on the chain theta(x) is the sum of the
angles of the joints at stations < x, so each joint strictly inside (x_a, x_b) gets the
generalized torque +M, and the others none. A positive M therefore turns the joints inside the
patch positive (the tip goes to -z).

A patch end exactly on a joint (within ``ON_JOINT_RTOL`` of the beam length) gives that joint
half the moment: the generalized torque jumps from 0 to M as the end moves across the joint,
and the joint's lumped compliance stands for the beam on both sides of it, so the midpoint of
the jump is the consistent value (a patch from one joint to the next gives each 1/2, and two
such patches end to end add up to the one patch that covers both).

Two maps. The virtual-work map above is what the chain's kinematics give: it needs nothing but
the joint stations, and it is exact in the limit of many joints, but a patch shorter than a
link moves no joint (zero gain: ``strain_map`` refuses such a patch, naming the nearest joints,
rather than give a plant it cannot drive) and one across a joint gives that joint the whole
moment, whichever part of the beam the patch bends. A fitted map (``StrainActuator(...,
joint_weights=w)``, made by :func:`prbdm_pin.plant.actuator_fit.fit_strain_actuators`) gives
each joint the weight that makes the chain's n modal input gains the finite-element truth's,
as the springs and links are fitted to its n frequencies: it needs the truth, and it is the
one to use for patches that are short against the links or that sit anywhere but on joints
(co-design sweeps of patch position). The truth's modes above the n-th are not in either map.
``strain_map`` returns the weights when an actuator carries them; the truth side of a plant
uses the stations only.

Which fitted map: matching the modal gains (the default) forces every mode as the truth's patch
does, so each output is as right as the PRBDM's own mode shapes make it (its tip force is
matched no better); where the chain's tip gain of a high mode is off, outputs weighted to high
frequency (tip z rate) keep that error. Matching the strain -> tip z residues (``match="tip_z"``)
makes that FRF exact over the n modes and moves the error to the other outputs (the hub's). The
virtual-work map remains the choice without a truth, and for patches that span several links
on a chain with many joints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..options.validate import check_size
from .loads import (
    BASE_ACCELS,
    DISTRIBUTED_FORCES,
    FOLLOWER_MOMENTS,
    DistributedLoad,
    base_accel_columns,
    check_load,
    distributed_column,
    follower_moment_columns,
)
from .names import parse_names

__all__ = ["StrainActuator", "INPUT_UNITS", "CORNER_INPUTS", "POSE_INPUTS",
           "ON_JOINT_RTOL", "joint_stations", "strain_map", "check_patch", "virtual_work_map",
           "parse_inputs", "check_corner_names", "input_map"]

# a patch end within this fraction of the beam length of a joint is on it (the stations come
# from sums of link lengths, so exact equality would depend on rounding)
ON_JOINT_RTOL = 1e-9

INPUT_UNITS = {"tip_force_z": "N", "tip_force_x": "N", "tip_force_y": "N", "tip_moment_x": "N m",
               "tip_moment_y": "N m", "tip_moment_z": "N m",
               "corner_force_z_left": "N", "corner_force_z_right": "N",
               "joint_torque": "N m", "strain": "N m", "hub_torque": "N m",
               **dict.fromkeys(FOLLOWER_MOMENTS, "N m"),
               **dict.fromkeys(DISTRIBUTED_FORCES, "N/m"),
               **dict.fromkeys(BASE_ACCELS, "m/s^2")}
# the inputs at a tip corner: the point each acts at (:mod:`prbdm_pin.chain.points`)
CORNER_INPUTS = {"corner_force_z_left": "tip_corner_left",
                 "corner_force_z_right": "tip_corner_right"}
# the inputs that act on the tip link beyond a force at its centre, through their own
# pose-dependent columns of the input map (a time response differentiates them for its load
# stiffness; the tip forces' is the tip's)
TIP_MOMENTS = {"tip_moment_x": 3, "tip_moment_y": 4, "tip_moment_z": 5}  # rows of the frame J
POSE_INPUTS = (*TIP_MOMENTS, *CORNER_INPUTS, *FOLLOWER_MOMENTS, *DISTRIBUTED_FORCES,
               *BASE_ACCELS)


@dataclass(frozen=True)
class StrainActuator:
    """A bending-moment actuator over the beam span [x_start_m, x_end_m], m from the root.

    Its input is the moment M (N m) the patch applies (see the module notes for the sign).
    ``joint_weights`` (one finite number per joint, N m per N m of patch moment), when given,
    replaces the virtual-work map (see the module notes); its length is checked against the
    model where the actuator is used.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> patch = pp.StrainActuator(x_start_m=0.1, x_end_m=0.3)
    >>> patch.x_start_m, patch.x_end_m
    (0.1, 0.3)
    >>> pp.StrainActuator(x_start_m=0.2, x_end_m=0.1)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: StrainActuator x_start_m = 0.2: must be < x_end_m = 0.1 (m)
    """

    x_start_m: float
    x_end_m: float
    joint_weights: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        """Check the stations and the weights (BeamInputError naming the field).

        The stations are on a beam: x_start_m >= 0 and x_end_m a size in [1e-5, 1e3] m
        (:func:`prbdm_pin.validate.check_size`); where the beam ends is checked where the
        actuator is used.
        """
        for name in ("x_start_m", "x_end_m"):
            v = check_size(f"StrainActuator {name}", getattr(self, name), low=0.0)
            object.__setattr__(self, name, v)
        if not self.x_start_m < self.x_end_m:
            raise BeamInputError(f"StrainActuator x_start_m = {self.x_start_m!r}: must be < "
                                 f"x_end_m = {self.x_end_m!r} (m)")
        if self.joint_weights is not None:
            object.__setattr__(self, "joint_weights", _weights(self.joint_weights))

    @property
    def fitted(self) -> bool:
        """Whether the actuator carries its own joint weights (else: the virtual-work map)."""
        return self.joint_weights is not None


def _weights(value: object) -> tuple[float, ...]:
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") \
            or np.ndim(value) != 1 or len(value) == 0:
        raise BeamInputError(f"StrainActuator joint_weights = {value!r:.60}: must be a sequence "
                             "of numbers, one per joint")
    out = []
    for j, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.number)) \
                or not math.isfinite(float(v)):
            raise BeamInputError(f"StrainActuator joint_weights[{j}] = {v!r}: must be a finite "
                                 "number (N m per N m)")
        out.append(float(v))
    return tuple(out)


def joint_stations(lengths_m: np.ndarray) -> np.ndarray:
    """Stations of the n joints along the undeformed beam, m from the root, shape (n,)."""
    return np.cumsum(np.asarray(lengths_m, dtype=float))[:-1]


def strain_map(lengths_m: np.ndarray, actuator: StrainActuator, field: str = "actuators[0]"
               ) -> np.ndarray:
    """Return the generalized torque per unit patch moment on each joint, shape (n,).

    The actuator's ``joint_weights`` when it has them, else 1 inside the patch, 1/2 for a joint
    an end sits on, 0 outside (dimensionless, N m per N m).

    Raises BeamInputError naming ``field`` when the patch leaves [0, L], its weights do not
    have one entry per joint, or it has no weights and holds no joint: the virtual-work map
    would give it no input at all (B = 0); the message names the joint stations nearest to
    it, and the fitted map (:func:`prbdm_pin.fit_strain_actuators`, ``--fit-actuators``) is
    the one for patches between joints.
    """
    lengths = check_patch(lengths_m, actuator, field)
    x = joint_stations(lengths)
    if actuator.joint_weights is not None:
        if len(actuator.joint_weights) != x.size:
            raise BeamInputError(f"{field}.joint_weights: has {len(actuator.joint_weights)} "
                                 f"entries, this model has {x.size} joints")
        return np.array(actuator.joint_weights)
    a, b = actuator.x_start_m, actuator.x_end_m
    inside = virtual_work_map(lengths, a, b)
    if not np.any(inside):
        below, above = x[x < a], x[x > b]
        near = ", ".join([f"{v:.6g} m" for v in (*below[-1:], *above[:1])])
        raise BeamInputError(
            f"{field} [{a:g}, {b:g}] m: holds no joint of this {x.size}R model (nearest joints "
            f"at {near}), so the virtual-work map gives it no input (B = 0); extend the patch "
            "over a joint, or fit its joint weights to the truth (fit_strain_actuators, "
            "--fit-actuators)")
    return inside


def virtual_work_map(lengths_m: np.ndarray, x_start_m: float, x_end_m: float) -> np.ndarray:
    """Return the virtual-work map of the patch [x_start_m, x_end_m] (m) on a chain, shape (n,).

    1 on a joint inside, 1/2 on a joint an end sits on (within ``ON_JOINT_RTOL`` L), 0
    outside; all zero for a patch between joints (which :func:`strain_map` refuses). Unchecked:
    for studies that compare the map with others where it gives nothing.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    tol = ON_JOINT_RTOL * float(lengths.sum())
    x = joint_stations(lengths)
    inside = ((x > x_start_m + tol) & (x < x_end_m - tol)).astype(float)
    inside[(np.abs(x - x_start_m) <= tol) | (np.abs(x - x_end_m) <= tol)] = 0.5
    return inside


def check_patch(lengths_m: np.ndarray, actuator: StrainActuator, field: str = "actuators[0]"
                ) -> np.ndarray:
    """Check that ``actuator`` lies on the chain of link lengths ``lengths_m`` (m).

    Returns the lengths as floats; a BeamInputError naming ``field`` when the patch leaves
    [0, L]. Holding a joint is not required here (a patch between joints gets fitted weights).
    """
    if not isinstance(actuator, StrainActuator):
        from ..errors import InputTypeError

        raise InputTypeError(f"{field} = {actuator!r:.60}: must be a prbdm_pin.StrainActuator")
    lengths = np.asarray(lengths_m, dtype=float)
    L = float(lengths.sum())
    tol = ON_JOINT_RTOL * L
    for name in ("x_start_m", "x_end_m"):
        v = getattr(actuator, name)
        if v < -tol or v > L + tol:
            raise BeamInputError(f"{field} {name} = {v!r}: must lie on the beam, in [0, {L:g}] "
                                 "(m)")
    return lengths


def parse_inputs(names, n_joints: int, n_actuators: int, hub: bool, n_loads: int = 0):
    """Check input names against a model; returns (name, base, index) per input.

    ``n_joints`` is the number of spring coordinates ``joint_torque[j]`` indexes (a spatial
    chain's ``n_springs``); ``n_loads`` the number of DistributedLoad spans
    ``distributed_force_z[i]`` indexes (the plain name is the whole beam).
    """
    plain = ("tip_force_z", "tip_force_x", "tip_force_y", *TIP_MOMENTS, *CORNER_INPUTS,
             *FOLLOWER_MOMENTS, *DISTRIBUTED_FORCES, *BASE_ACCELS) + (
        ("hub_torque",) if hub else ())
    indexed = {"joint_torque": n_joints, "strain": n_actuators,
               **dict.fromkeys(DISTRIBUTED_FORCES, n_loads)}
    return parse_names(names, "inputs", indexed, plain)


def check_corner_names(model, names, field: str) -> None:
    """Refuse names of tip-corner signals (``field[i]``) on a model without its beam.

    A model read from a URDF carries no width, so it has no corners; BeamInputError.
    """
    if model.beam is not None:
        return
    for i, name in enumerate(names):
        if isinstance(name, str) and name.startswith("corner_"):
            raise BeamInputError(f"{field}[{i}] = {name!r}: this model carries no beam (read "
                                 "from a URDF), so no tip width and no corners")


def input_map(model, q: np.ndarray, names, actuators: tuple[StrainActuator, ...] = (),
              loads: tuple[DistributedLoad, ...] = ()) -> np.ndarray:
    """Return the generalized force per unit input at pose ``q`` (rad), shape (nv, m).

    Tip forces act through the tip Jacobian's transpose (m/rad), the tip moments about world
    x, y, z through the tip's angular Jacobian (its rows), corner forces through the corner points'
    Jacobians (:meth:`PrbdmModel.point_kinematics`), torques and patch moments directly; the
    follower moments, distributed forces (over ``loads[i]`` or the whole beam) and base
    accelerations as :mod:`prbdm_pin.model.loads` maps them.

    ``q`` has ``pin_model.nq`` entries (the hub angle first on a hub model).
    """
    hub = model.hub is not None
    for i, ld in enumerate(loads):
        check_load(model.lengths_m, ld, f"loads[{i}]")
    parsed = parse_inputs(names, model.n_springs, len(actuators), hub, len(loads))
    off = getattr(model, "n_free", int(hub))  # the coordinates without springs come first
    # Pinocchio's Jacobians only for the columns that need them (a time response calls this
    # for its pose-dependent columns at every evaluation)
    tip = {"tip_force_x", "tip_force_y", "tip_force_z"}
    J = model.tip_jacobian(q) if any(b in tip for _, b, _ in parsed) else None
    Jw = model.tip_frame_jacobian(q) if any(b in TIP_MOMENTS for _, b, _ in parsed) else None
    maps = [strain_map(model.lengths_m, a, f"actuators[{i}]") for i, a in enumerate(actuators)]
    Jf = follower_moment_columns(model, q) if any(b in FOLLOWER_MOMENTS for _, b, _ in parsed) \
        else None
    Ga = base_accel_columns(model, q) if any(b in BASE_ACCELS for _, b, _ in parsed) else None
    B = np.zeros((model.pin_model.nv, len(parsed)))
    for c, (_, base, idx) in enumerate(parsed):
        if base == "tip_force_z":
            B[:, c] = J[2]
        elif base == "tip_force_x":
            B[:, c] = J[0]
        elif base == "tip_force_y":
            B[:, c] = J[1]
        elif base in TIP_MOMENTS:
            B[:, c] = Jw[TIP_MOMENTS[base]]
        elif base in CORNER_INPUTS:
            B[:, c] = model.point_kinematics(CORNER_INPUTS[base], q)[1][2]
        elif base in FOLLOWER_MOMENTS:
            B[:, c] = Jf[:, FOLLOWER_MOMENTS[base] - 3]
        elif base in DISTRIBUTED_FORCES:
            B[:, c] = distributed_column(model, q, None if idx is None else loads[idx],
                                         DISTRIBUTED_FORCES[base])
        elif base in BASE_ACCELS:
            B[:, c] = Ga[:, BASE_ACCELS[base]]
        elif base == "hub_torque":
            B[0, c] = 1.0
        elif base == "joint_torque":
            B[off + idx, c] = 1.0
        else:
            B[off:, c] = maps[idx]
    return B


def input_unit(name: str) -> str:
    """Return the unit of the input ``name``."""
    return INPUT_UNITS[name.split("[")[0]]
