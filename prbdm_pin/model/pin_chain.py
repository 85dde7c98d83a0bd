"""The Pinocchio side of a link chain.

The ``pinocchio.Model`` built by hand from the links' sections, and the sections read back from
a model (one parsed from a URDF file).

Building through the API rather than rendering and parsing a URDF keeps ``build_model`` cheap
inside optimisation loops; the model equals the one Pinocchio's URDF parser makes.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain.sections import LinkSections
from ..errors import BeamInputError
from ..options.choices import Axes
from .chain_names import joint_names, node_links
from .urdf import JOINT_EFFORT_LIMIT_NM, JOINT_LIMIT_RAD, JOINT_VELOCITY_LIMIT_RAD_S

__all__ = ["TIP_FRAME", "pin_chain", "sections_from_pin", "spatial_lengths"]

TIP_FRAME = "tip"


_JOINT_MODELS = {"x": pin.JointModelRX, "y": pin.JointModelRY, "z": pin.JointModelRZ}


def pin_chain(sections: LinkSections, lengths: np.ndarray, name: str,
              axes: Axes = Axes.Y) -> tuple[pin.Model, int]:
    """Build the chain of links ``sections`` cut at ``lengths`` (m) through the Pinocchio API.

    It is built frame for frame as Pinocchio's URDF parser builds it; returns the model and the
    tip frame id. A spatial chain (``axes`` other than y) has at node j one revolute joint per
    axis, in the order of :attr:`Axes.joint_order`, all at the same point, joined by massless
    links (:func:`node_links`).
    """
    n = lengths.size - 1
    model = pin.Model()
    model.name = name
    eye = np.eye(3)

    def inertia(i: int) -> pin.Inertia:
        c = sections.com_m[i] - np.array([sections.start_m[i], 0.0, 0.0])
        return pin.Inertia(float(sections.mass_kg[i]), c, sections.inertia_com_kg_m2[i])

    ident = pin.SE3.Identity()
    world = model.addBodyFrame("world", 0, ident, 0)
    # a fixed-joint frame carrying an inertia adds it to its joint (here the universe)
    clamp = model.addFrame(pin.Frame("clamp", 0, world, ident, pin.FrameType.FIXED_JOINT,
                                     inertia(0)))
    prev = model.addBodyFrame("link_0", 0, ident, clamp)
    big = np.array([JOINT_EFFORT_LIMIT_NM])
    vel = np.array([JOINT_VELOCITY_LIMIT_RAD_S])
    lim = np.array([JOINT_LIMIT_RAD])
    zero = np.zeros(1)
    names = iter(joint_names(n, axes))
    jid = 0
    for j in range(1, n + 1):
        placement = pin.SE3(eye, np.array([float(lengths[j - 1]), 0.0, 0.0]))
        links = node_links(j, axes)
        for a, link in zip(axes.joint_order, links, strict=True):
            jid = model.addJoint(jid, _JOINT_MODELS[a](), placement, next(names),
                                 -big, big, -vel, vel, -lim, lim, zero, zero, zero)
            jf = model.addJointFrame(jid, prev)
            if link == links[-1]:
                model.appendBodyToJoint(jid, inertia(j), ident)
            prev = model.addBodyFrame(link, jid, ident, jf)
            placement = ident
    tip_place = pin.SE3(eye, np.array([float(lengths[n]), 0.0, 0.0]))
    tf = model.addFrame(pin.Frame("tip_joint", jid, prev, tip_place, pin.FrameType.FIXED_JOINT))
    tip = model.addBodyFrame(TIP_FRAME, jid, tip_place, tf)
    model.gravity = pin.Motion.Zero()
    return model, tip


def sections_from_pin(model: pin.Model, lengths: np.ndarray, hub: bool = False,
                      axes: Axes = Axes.Y) -> LinkSections:
    """Read the links' sections back from a Pinocchio model.

    Mass (kg), COM (m, beam frame) and inertia (kg m^2) as the model holds them, for lengths
    ``lengths`` (m); ``area_moment_m4`` is NaN (a URDF does not carry it).

    On a hub model (``hub``) link 0 is the inertia of the ``clamp`` frame (the parser keeps a
    fixed joint's child there) and link j that of Pinocchio joint j + 1. On a spatial chain
    link j is the inertia of node j's last joint (the others are massless).
    """
    n1 = lengths.size
    ends = np.cumsum(lengths)
    starts = ends - lengths
    if hub:
        links = [model.frames[model.getFrameId("clamp")].inertia,
                 *(model.inertias[i + 1] for i in range(1, n1))]
    else:
        m = len(axes.joint_order)
        links = [model.inertias[0], *(model.inertias[i * m] for i in range(1, n1))]
    mass = np.array([b.mass for b in links])
    com = np.array([b.lever for b in links]) + starts[:, None] * [1, 0, 0]
    inertia = np.array([b.inertia for b in links])
    arrs = [starts, ends, mass, com, inertia, np.full(n1, np.nan)]
    for a in arrs:
        a.setflags(write=False)
    return LinkSections(*arrs)


def spatial_lengths(model: pin.Model, tip_frame_id: int, axes: Axes) -> np.ndarray:
    """Read the link lengths (m, shape (n+1,)) of a spatial chain parsed from a URDF.

    The model must be the chain :func:`pin_chain` builds: a serial chain whose node j is one
    revolute joint per axis of :attr:`Axes.joint_order` (``JointModelRY``, ``RZ``, ``RX``),
    the first placed a pure x offset (link j - 1's length) from the previous node, the others
    at the same point with the same orientation (exactly: the URDF writes ``0 0 0``), the joints
    before a node's last carrying no inertia (the massless links), and the tip frame a pure x
    offset on the last joint.

    Parameters
    ----------
    model : pinocchio.Model
        The chain, as Pinocchio's URDF parser built it (no hub).
    tip_frame_id : int
        The ``tip`` frame.
    axes : Axes
        The joint axes at each node (spatial).

    Returns
    -------
    ndarray, shape (n+1,)
        The link lengths, m: the x offsets of the nodes' first joints, then the tip's.

    Raises
    ------
    BeamInputError
        Naming the joint, link or frame that is not so.
    """
    order = axes.joint_order
    m = len(order)
    nj = model.njoints - 1
    if nj % m:
        raise BeamInputError(f"{nj} revolute joints: a chain of axes {axes.value!r} has "
                             f"{m} per node")
    out = np.empty(nj // m + 1)
    for idx in range(1, nj + 1):
        a, name = order[(idx - 1) % m], model.names[idx]
        if model.parents[idx] != idx - 1 or model.joints[idx].shortname() != \
                _JOINT_MODELS[a]().shortname():
            raise BeamInputError(f"joint {name!r}: must be a serial revolute joint about {a}")
        p = model.jointPlacements[idx]
        first = (idx - 1) % m == 0
        if not (np.array_equal(p.rotation, np.eye(3)) and not np.any(p.translation[1:])
                and (first or p.translation[0] == 0.0)):
            raise BeamInputError(f"joint {name!r} origin = {p.translation.tolist()} m: must be "
                                 + ("a pure x offset" if first else "at its node (0 0 0)"))
        if first:
            out[(idx - 1) // m] = float(p.translation[0])
        body = model.inertias[idx]
        if idx % m and (body.mass != 0.0 or np.any(body.inertia) or np.any(body.lever)):
            raise BeamInputError(f"the link after joint {name!r}: mass = {body.mass!r} kg: a "
                                 "link between two joints of one node must be massless")
    frame = model.frames[tip_frame_id]
    t = frame.placement.translation
    if frame.parentJoint != nj or not (np.array_equal(frame.placement.rotation, np.eye(3))
                                       and not np.any(t[1:])):
        raise BeamInputError(f"frame {frame.name!r}: must sit on the last joint at a pure x "
                             "offset")
    out[-1] = float(t[0])
    return out
