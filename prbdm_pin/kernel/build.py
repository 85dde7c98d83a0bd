"""The compiled kernel's description of a chain: ``ChainKernel``, read from a ``pin.Model``.

A serial chain of one-degree-of-freedom joints, each a revolute or a prismatic joint about one
of its frame's axes (x, y, z): the planar and spatial chains, a hub and a free bus the package
builds (``prbdm_pin.model``) are all of that kind. The kernel keeps per joint what Pinocchio's
model keeps (joint placement in its parent, body inertia), the tip frame and gravity, as plain
arrays the compiled functions (:mod:`.dynamics`) read; nothing here imports numba.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError, InputTypeError

__all__ = ["ChainKernel", "KernelData", "chain_kernel", "REVOLUTE", "PRISMATIC"]

REVOLUTE, PRISMATIC = 0, 1
# Pinocchio's joint models the kernel takes: (kind, axis index)
_JOINTS = {"JointModelRX": (REVOLUTE, 0), "JointModelRY": (REVOLUTE, 1),
           "JointModelRZ": (REVOLUTE, 2), "JointModelPX": (PRISMATIC, 0),
           "JointModelPY": (PRISMATIC, 1), "JointModelPZ": (PRISMATIC, 2)}


@dataclass(frozen=True, eq=False)
class ChainKernel:
    """A serial chain as the compiled kernel evaluates it (arrays only, read-only).

    Attributes
    ----------
    joint_type : ndarray (n,) of int
        0: revolute, 1: prismatic.
    joint_axis : ndarray (n,) of int
        The joint's axis in its own frame: 0 x, 1 y, 2 z.
    parent_rotation : ndarray (n, 3, 3)
        Joint i's placement in its parent joint's frame (the world for the first): rotation.
    parent_translation_m : ndarray (n, 3)
        The placement's translation, m.
    mass_kg : ndarray (n,)
        Mass of the body carried by joint i, kg.
    com_m : ndarray (n, 3)
        Its centre of mass in joint i's frame, m.
    inertia_kg_m2 : ndarray (n, 3, 3)
        Its rotational inertia about the centre of mass, in joint i's frame, kg m^2.
    tip_joint : int
        Index (0-based, in velocity order) of the joint the tip frame sits on.
    tip_rotation : ndarray (3, 3)
        The tip frame's placement in that joint's frame: rotation.
    tip_translation_m : ndarray (3,)
        Its translation, m.
    gravity_m_s2 : ndarray (3,)
        Gravity, world, m/s^2 (zeros: none).
    model_name : str
        The Pinocchio model's name.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> kernel.n, kernel.joint_axis.tolist(), kernel.tip_joint
    (2, [1, 1], 1)
    """

    joint_type: np.ndarray
    joint_axis: np.ndarray
    parent_rotation: np.ndarray
    parent_translation_m: np.ndarray
    mass_kg: np.ndarray
    com_m: np.ndarray
    inertia_kg_m2: np.ndarray
    tip_joint: int
    tip_rotation: np.ndarray
    tip_translation_m: np.ndarray
    gravity_m_s2: np.ndarray
    model_name: str = ""

    @property
    def n(self) -> int:
        """Number of joints (= degrees of freedom)."""
        return int(self.joint_type.size)

    def arrays(self) -> tuple:
        """Return the arrays as the compiled functions take them (one fixed tuple layout)."""
        return (self.joint_type, self.joint_axis, self.parent_rotation,
                self.parent_translation_m, self.mass_kg, self.com_m, self.inertia_kg_m2,
                np.array([self.tip_joint], dtype=np.int64), self.tip_rotation,
                self.tip_translation_m, self.gravity_m_s2)

    def new_data(self) -> KernelData:
        """Return a fresh workspace for this chain (as ``pin.Model.createData``)."""
        return KernelData.for_size(self.n)


@dataclass(frozen=True, eq=False)
class KernelData:
    """The workspace of the compiled functions: every array they write, preallocated.

    Attributes
    ----------
    rotation : ndarray (n, 3, 3)
        World rotation of each joint frame.
    origin_m : ndarray (n, 3)
        World position of each joint frame, m.
    motion_subspace : ndarray (n, 6)
        Each joint's unit motion, world, at the world origin (linear m/s, then angular rad/s).
    first_moment_kg_m : ndarray (n, 3)
        Each body's mass times its world centre of mass, kg m.
    inertia_origin_kg_m2 : ndarray (n, 3, 3)
        Each body's rotational inertia about the world origin, world axes, kg m^2.
    composite_mass_kg, composite_first_moment_kg_m, composite_inertia_kg_m2 : ndarray
        The same summed over a body and the bodies after it (CRBA's composite bodies).
    velocity, acceleration, force : ndarray (n, 6)
        Spatial velocity, acceleration (m/s, rad/s; /s) and force (N, N m) of each body, world.
    mass_matrix : ndarray (n, n)
        M(q), kg m^2 (SI of the joints).
    cholesky : ndarray (n, n)
        Its lower Cholesky factor.
    bias : ndarray (n,)
        h(q, v), N m.
    torque : ndarray (n,)
        Scratch generalised force, N m.
    acceleration_joint : ndarray (n,)
        The joint accelerations of the last forward dynamics.
    """

    rotation: np.ndarray
    origin_m: np.ndarray
    motion_subspace: np.ndarray
    first_moment_kg_m: np.ndarray
    inertia_origin_kg_m2: np.ndarray
    composite_mass_kg: np.ndarray
    composite_first_moment_kg_m: np.ndarray
    composite_inertia_kg_m2: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    force: np.ndarray
    mass_matrix: np.ndarray
    cholesky: np.ndarray
    bias: np.ndarray
    torque: np.ndarray
    acceleration_joint: np.ndarray

    @classmethod
    def for_size(cls, n: int) -> KernelData:
        """Return a zeroed workspace for a chain of ``n`` joints."""
        z = np.zeros
        return cls(z((n, 3, 3)), z((n, 3)), z((n, 6)), z((n, 3)), z((n, 3, 3)), z(n),
                   z((n, 3)), z((n, 3, 3)), z((n, 6)), z((n, 6)), z((n, 6)), z((n, n)),
                   z((n, n)), z(n), z(n), z(n))

    def arrays(self) -> tuple:
        """Return the arrays as the compiled functions take them (one fixed tuple layout)."""
        return (self.rotation, self.origin_m, self.motion_subspace, self.first_moment_kg_m,
                self.inertia_origin_kg_m2, self.composite_mass_kg,
                self.composite_first_moment_kg_m, self.composite_inertia_kg_m2, self.velocity,
                self.acceleration, self.force, self.mass_matrix, self.cholesky, self.bias,
                self.torque, self.acceleration_joint)


def chain_kernel(pin_model: pin.Model, tip_frame_id: int) -> ChainKernel:
    """Read the compiled kernel's description of the serial chain ``pin_model``.

    Parameters
    ----------
    pin_model : pinocchio.Model
        A serial chain of revolute or prismatic joints about their frames' x, y or z axes
        (planar and spatial chains, a hub, a free bus); its gravity is kept.
    tip_frame_id : int
        The frame whose position and force Jacobian the kernel evaluates (``model.tip_frame_id``).

    Returns
    -------
    ChainKernel

    Raises
    ------
    InputTypeError
        ``pin_model`` is not a ``pinocchio.Model`` or ``tip_frame_id`` not an int.
    BeamInputError
        Naming the model and the joint that is not a serial one-axis joint, or a frame id
        out of range.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> round(float(kernel.tip_translation_m[0]), 3)  # the last link's length, m
    0.3
    """
    if not isinstance(pin_model, pin.Model):
        raise InputTypeError(f"pin_model = {pin_model!r:.60}: must be a pinocchio.Model")
    if isinstance(tip_frame_id, bool) or not isinstance(tip_frame_id, (int, np.integer)):
        raise InputTypeError(f"tip_frame_id = {tip_frame_id!r:.60}: must be an int")
    name = pin_model.name or "pin_model"
    n = pin_model.njoints - 1
    if n < 1 or pin_model.nq != n or pin_model.nv != n:
        raise BeamInputError(f"pin_model {name!r}: {n} joints, nq = {pin_model.nq}, nv = "
                             f"{pin_model.nv}: the kernel takes a chain of one-axis joints")
    if not 0 <= int(tip_frame_id) < pin_model.nframes:
        raise BeamInputError(f"tip_frame_id = {tip_frame_id}: pin_model {name!r} has "
                             f"{pin_model.nframes} frames")
    kind, axis = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    R, p = np.empty((n, 3, 3)), np.empty((n, 3))
    mass, com, inertia = np.empty(n), np.empty((n, 3)), np.empty((n, 3, 3))
    for i in range(1, n + 1):
        short = pin_model.joints[i].shortname()
        if pin_model.parents[i] != i - 1 or short not in _JOINTS:
            raise BeamInputError(f"pin_model {name!r} joint {pin_model.names[i]!r} "
                                 f"({short}): the kernel takes a serial chain of revolute or "
                                 "prismatic joints about x, y or z")
        kind[i - 1], axis[i - 1] = _JOINTS[short]
        placement, body = pin_model.jointPlacements[i], pin_model.inertias[i]
        R[i - 1], p[i - 1] = placement.rotation, placement.translation
        mass[i - 1], com[i - 1], inertia[i - 1] = body.mass, body.lever, body.inertia
    frame = pin_model.frames[int(tip_frame_id)]
    if frame.parentJoint < 1:
        raise BeamInputError(f"tip_frame_id = {tip_frame_id}: frame {frame.name!r} of "
                             f"pin_model {name!r} sits on the world, not on a joint")
    arrays = (kind, axis, R, p, mass, com, inertia, frame.placement.rotation.copy(),
              frame.placement.translation.copy(), pin_model.gravity.linear.copy())
    for a in arrays:
        a.setflags(write=False)
    return ChainKernel(kind, axis, R, p, mass, com, inertia, int(frame.parentJoint) - 1,
                       *arrays[7:], model_name=name)
