"""A PRBDM read back from a URDF file (the package's export, or ``PrbdmModel.urdf``).

The URDF carries the chain, its springs and the hub; the export record in its XML comment
carries the strain actuators with their fitted weights.
"""

from __future__ import annotations

import os

import numpy as np
import pinocchio as pin

from ..chain import pin_dynamics as dyn
from ..chain.stiffness import validate_stiffness
from ..errors import BeamInputError
from ..model.chain_names import joint_names
from ..model.hub import HUB_JOINT, Hub
from ..model.inputs import strain_map
from ..model.pin_chain import TIP_FRAME, sections_from_pin, spatial_lengths
from ..model.prbdm_model import PrbdmModel
from ..model.urdf import read_springs
from ..model.urdf_checks import check_sections, check_urdf, hub_inertia, read_urdf_text
from ..options.choices import Axes
from .export_comment import read_export_record

__all__ = ["load_urdf", "chain_axes"]

# the hub's axis from the joint type Pinocchio's parser gives a revolute joint about x, y or z
_HUB_AXIS = {"JointModelRX": "x", "JointModelRY": "y", "JointModelRZ": "z"}


def chain_axes(names: list[str], what: str = "urdf") -> Axes:
    """Tell the joint axes of a chain from its joints' names, in Pinocchio's order.

    ``joint_1`` ... ``joint_n`` (after a ``hub``, if any) is the planar chain (``"y"``);
    ``joint_j_a`` the spatial one whose axes are node 1's suffixes, in the order y, z, x
    (:func:`~prbdm_pin.model.chain_names.joint_names`); every node must have the same.

    Parameters
    ----------
    names : list of str
        The joints' names, the universe left out.
    what : str
        The file, for the messages.

    Returns
    -------
    Axes
        The chain's axes.

    Raises
    ------
    BeamInputError
        Naming the first joint that does not fit.
    """
    beam = names[1:] if names[:1] == [HUB_JOINT] else names
    if not beam or not beam[0].startswith("joint_1_"):
        return Axes.Y  # the planar names are checked where the springs are read
    order = tuple(name[len("joint_1_"):] for name in beam if name.startswith("joint_1_"))
    found = [a for a in Axes if a.spatial and a.joint_order == order]
    if not found:
        raise BeamInputError(f"{what}: joints {', '.join(beam[:len(order)])}: a spatial node "
                             "has the joints joint_j_y, joint_j_z, joint_j_x of its axes, in "
                             "that order (xy, yz or xyz)")
    axes = found[0]
    if len(beam) != len(names):
        raise BeamInputError(f"{what}: joint {HUB_JOINT!r}: a hub carries the planar chain only "
                             f"(joint_1, ...), this chain has axes {axes.value!r}")
    want = joint_names(-(-len(beam) // len(order)), axes)
    for got, expect in zip(beam, want, strict=False):
        if got != expect:
            raise BeamInputError(f"{what}: joint {got!r}: expected {expect!r} (a chain of axes "
                                 f"{axes.value!r} has the joints {', '.join(want[:len(order)])}"
                                 " at node 1, and so on)")
    if len(beam) != len(want):
        raise BeamInputError(f"{what}: joint {want[len(beam)]!r}: missing (every node of a "
                             f"chain of axes {axes.value!r} has {len(order)} joints)")
    return axes


def load_urdf(path: str | os.PathLike) -> PrbdmModel:
    """Read a PRBDM URDF file, springs included.

    The file is one written by :attr:`PrbdmModel.urdf` or the URDF export; ``path`` is a str or
    path-like. A file with the revolute joint ``hub`` reads as a hub model (``hub`` set: the
    inertia of link ``hub_body``, the radius of the ``clamp`` offset, the axis of ``hub``). A
    spatial chain (joints ``joint_j_y``, ``joint_j_z``, ``joint_j_x`` at node j joined by massless
    links) reads with its ``axes`` (:func:`chain_axes`), its springs node-major in that order.

    The springs come from the Gazebo ``<springStiffness>`` tags; the strain actuators the
    file's export record lists (``strain_actuators_m``, with their fitted joint weights) become
    ``actuators``, as :func:`prbdm_pin.read_plant_json` returns them; ``beam`` is None and
    ``sections.area_moment_m4`` is NaN; ``pin_model.damping`` holds the joints'
    ``<dynamics damping>`` (N m s/rad; :func:`prbdm_pin.simulate` takes its damping from its own
    arguments, not from there).

    Gravity: URDF carries none and Pinocchio's parser gives every model its default gravity,
    -9.81 m/s^2 along z (so does ``pinocchio.buildModelFromUrdf``). The PRBDM has no gravity, so
    this loader sets ``pin_model.gravity`` to zero, as :func:`build_model` does; set it back
    (``pin_model.gravity = pinocchio.Motion(np.array([0, 0, -9.81, 0, 0, 0]))``) to simulate
    with gravity. A plain ``pinocchio.buildModelFromUrdf`` model needs
    ``model.gravity = pinocchio.Motion.Zero()`` to be this model. A model fitted in gravity
    (``prbdm fit --gravity``) states that gravity in its comment
    (``prbdm_pin.load_model(path).gravity_m_s2`` reads it): simulate it with that gravity
    (``simulate(..., gravity_m_s2=...)``), as it was fitted.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = model.write_urdf(folder / "model.urdf")
    >>> again = pp.load_urdf(path)
    >>> bool(np.allclose(again.natural_frequencies(), model.natural_frequencies()))
    True
    """
    text = read_urdf_text(path)
    what = f"urdf file {str(path)!r}"
    n = check_urdf(text, what)
    try:
        model = pin.buildModelFromXML(text)
    except (RuntimeError, ValueError) as exc:
        raise BeamInputError(f"{what}: Pinocchio cannot parse it ({exc})") from None
    model.gravity = pin.Motion.Zero()
    if not model.existFrame(TIP_FRAME):
        raise BeamInputError(f"{what}: has no {TIP_FRAME!r} link")
    if model.nv != n:
        raise BeamInputError(f"{what}: {n} revolute joints but a chain of {model.nv} "
                             "(every revolute joint must be on the chain to the tip)")
    tip = model.getFrameId(TIP_FRAME)
    axes = chain_axes(list(model.names)[1:], what)
    if axes.spatial:
        try:
            lengths = spatial_lengths(model, tip, axes)
        except BeamInputError as exc:
            raise BeamInputError(f"{what}: {exc}") from None
    else:
        lengths = dyn.planar_lengths(model, tip, hub_any_axis=True)
    hub = None
    if model.njoints > 2 and model.names[1] == HUB_JOINT:
        # the first offset is the hub's (0); the second is the radius plus link 0
        if not model.existFrame("clamp"):
            raise BeamInputError(f"{what}: a joint 'hub' but no fixed joint 'clamp' to link_0")
        radius = float(model.frames[model.getFrameId("clamp")].placement.translation[0])
        axis = _HUB_AXIS.get(model.joints[1].shortname())
        if axis is None:  # Pinocchio names a revolute joint about a tilted axis otherwise
            raise BeamInputError(f"{what}: joint {HUB_JOINT!r}: its <axis> must be world x, y "
                                 "or z (1 0 0, 0 1 0 or 0 0 1)")
        hub = Hub(hub_inertia(text, what), radius, axis)
        lengths = np.concatenate([[lengths[1] - hub.radius_m], lengths[2:]])
    lengths.setflags(write=False)
    names = [model.names[j] for j in range(1 + (hub is not None), model.njoints)]
    try:
        k = validate_stiffness(read_springs(text, names), len(names))
    except BeamInputError as exc:
        raise BeamInputError(f"{what}: {exc}") from None
    sections = sections_from_pin(model, lengths, hub is not None, axes)
    check_sections(what, lengths, sections.mass_kg)
    try:
        record = read_export_record(text)
        actuators = () if record is None else record.actuators()
    except ValueError as exc:  # a hand-edited record: numbers that are not numbers
        raise BeamInputError(f"{what}: {exc}") from None
    for i, a in enumerate(actuators):  # the record's patches lie on this chain
        strain_map(lengths, a, f"{what}: actuators[{i}]")
    if axes.spatial and actuators:
        raise BeamInputError(f"{what}: its record lists strain actuators: they go with the "
                             f"planar chain only, and this one has axes = {axes.value!r}")
    out = PrbdmModel(None, lengths, k, sections, model, tip, hub, tuple(actuators), axes)
    out._cache["urdf"] = text
    return out
