"""Render the URDF of a PRBDM from ``urdf_templates/`` and read its springs back.

Layout of the URDF: a ``world`` link, a fixed joint ``clamp`` to ``link_0`` (the clamped link;
on a hub model ``world`` -> revolute ``hub`` about its axis x, y or z -> massless link
``hub_body`` carrying the hub inertia -> ``clamp`` at the hub radius along x -> ``link_0``),
revolute joints ``joint_1`` ... ``joint_n`` about y (each with a generous ``<limit>`` tag, which
Pinocchio's parser requires, and ``<dynamics damping>``, N m s/rad, 0 unless given), links
``link_1`` ... ``link_n`` with their inertia about the centre of mass, and a fixed joint
``tip_joint`` to the ``tip`` link at the free end. The ``tip`` link has an explicit zero
``<inertial>`` (a consumer that defaults a link without one to 1 kg and unit inertia, as pybullet
does, then reads it as massless); ``world`` is the root and has none (the URDF convention for a
fixed base; KDL warns about a root link with an inertia). Pinocchio has no joint stiffness, so
springs are written as Gazebo's extension
``<gazebo reference="joint_j"><springStiffness>K</springStiffness>`` (N m/rad).
"""

from __future__ import annotations

import math
import string
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from functools import cache
from importlib import resources
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from ..chain.sections import LinkSections
from ..errors import BeamInputError
from ..options.choices import Axes
from .chain_names import joint_names, node_links

# an attribute's tab, newline and carriage return become spaces when an XML parser normalises
# it; as character references they survive
_ATTRIBUTE = {'"': "&quot;", "\t": "&#9;", "\n": "&#10;", "\r": "&#13;"}

__all__ = [
    "JOINT_LIMIT_RAD",
    "JOINT_EFFORT_LIMIT_NM",
    "JOINT_VELOCITY_LIMIT_RAD_S",
    "HUB_LIMIT_RAD",
    "render_urdf",
    "read_springs",
    "template_text",
]

# Limits that never bind: Pinocchio's parser needs them, the beam does not.
JOINT_LIMIT_RAD = 2.0 * math.pi
JOINT_EFFORT_LIMIT_NM = 1.0e9
JOINT_VELOCITY_LIMIT_RAD_S = 1.0e3
# a hub may turn many times: its limit is far beyond any run (a continuous joint would make
# Pinocchio's coordinate a (cos, sin) pair)
HUB_LIMIT_RAD = 1.0e6


_AXIS = {"x": "1 0 0", "y": "0 1 0", "z": "0 0 1"}


@cache
def template_text(name: str) -> str:
    """Read template ``name`` from the installed package ``prbdm_pin.urdf_templates``.

    A source checkout that was not installed falls back to the repository's ``urdf_templates/``.
    """
    try:
        return resources.files("prbdm_pin.urdf_templates").joinpath(name).read_text("utf-8")
    except (ModuleNotFoundError, FileNotFoundError):
        path = Path(__file__).resolve().parents[2] / "urdf_templates" / name
        return path.read_text("utf-8")


def _t(name: str) -> string.Template:
    return string.Template(template_text(name))


def _f(v: float) -> str:
    # repr is the shortest string that parses back to the same double
    return repr(float(v))


def render_urdf(
    sections: LinkSections,
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    robot_name: str = "prbdm",
    damping_Nms_per_rad: np.ndarray | None = None,
    comment: str = "",
    hub=None,
    axes: Axes | str = Axes.Y,
    link_geometry: Sequence[str] | None = None,
) -> str:
    """Render the URDF string of the chain.

    Parameters
    ----------
    sections : LinkSections
        Link masses (kg), centres of mass (m, beam frame) and inertia about the COM (kg m^2).
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m (joint j sits at the end of link j - 1).
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint spring stiffness, N m/rad.
    robot_name : str
    damping_Nms_per_rad : ndarray, shape (n,), optional
        Joint damping written to ``<dynamics damping>``, N m s/rad (default 0).
    comment : str
        Text of an XML comment placed before ``<robot>`` (must not contain ``--``).
    hub : Hub, optional
        A rotating hub: the revolute joint ``hub`` about ``hub.axis`` from ``world`` to the
        massless link ``hub_body`` (inertia ``inertia_kg_m2`` about every axis, as the Pinocchio hub
        model holds it), and ``clamp`` from ``hub_body`` to ``link_0`` at ``radius_m`` along x.
    axes : Axes or str
        The joint axes per node (default ``"y"``). A spatial node j is revolute joints
        ``joint_j_y``, ``joint_j_z``, ``joint_j_x`` (those in ``axes``, in that order) at one
        point, joined by massless links ``link_j_y``, ``link_j_z`` (explicit zero inertial), the
        last one's child ``link_j``; springs and damping are node-major in that order.
    link_geometry : sequence of str, optional
        XML placed in ``link_0`` ... ``link_n`` after the inertial (their ``<visual>`` and
        ``<collision>``: :func:`prbdm_pin.files.export_geometry.urdf_geometry`); the massless
        node links get none. Default none.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    n = lengths.size - 1
    axes = Axes(axes)
    nk = n * len(axes.joint_order)
    damp = np.zeros(nk) if damping_Nms_per_rad is None else np.asarray(damping_Nms_per_rad, float)
    if damp.shape != (nk,) or not np.all(np.isfinite(damp) & (damp >= 0.0)):
        raise BeamInputError(
            f"damping = {damp.tolist()} N m s/rad: needs {nk} finite values >= 0"
        )
    geometry = [""] * (n + 1) if link_geometry is None else list(link_geometry)
    if len(geometry) != n + 1:
        raise BeamInputError(f"link_geometry: {len(geometry)} entries, needs one per link "
                             f"({n + 1})")
    if "--" in comment:
        raise BeamInputError("urdf comment: must not contain '--' (XML comments cannot)")
    link_t, joint_t, spring_t = _t("link.urdf.tmpl"), _t("joint.urdf.tmpl"), _t("spring.urdf.tmpl")
    names = joint_names(n, axes)
    body = []
    zero = dict(com_x="0", com_y="0", com_z="0", mass="0", ixx="0", ixy="0", ixz="0", iyy="0",
                iyz="0", izz="0")
    for i in range(n + 1):
        I = sections.inertia_com_kg_m2[i]
        c = sections.com_m[i] - np.array([sections.start_m[i], 0.0, 0.0])
        parent, x = f"link_{i - 1}", _f(lengths[i - 1]) if i > 0 else "0"
        links = node_links(i, axes) if i > 0 else ["link_0"]
        for a, child in zip(axes.joint_order if i > 0 else (), links, strict=False):
            body.append(joint_t.substitute(
                name=names[(i - 1) * len(axes.joint_order) + axes.joint_order.index(a)],
                parent=parent, child=child, x=x, axis=_AXIS[a], lower=_f(-JOINT_LIMIT_RAD),
                upper=_f(JOINT_LIMIT_RAD), effort=_f(JOINT_EFFORT_LIMIT_NM),
                velocity=_f(JOINT_VELOCITY_LIMIT_RAD_S),
                damping=_f(damp[(i - 1) * len(axes.joint_order) + axes.joint_order.index(a)]),
            ))
            if child != links[-1]:  # a massless link between two joints of one node
                body.append(link_t.substitute(name=child, geometry="", **zero))
            parent, x = child, "0"
        body.append(link_t.substitute(
            name=f"link_{i}", com_x=_f(c[0]), com_y=_f(c[1]), com_z=_f(c[2]),
            mass=_f(sections.mass_kg[i]),
            ixx=_f(I[0, 0]), ixy=_f(I[0, 1]), ixz=_f(I[0, 2]),
            iyy=_f(I[1, 1]), iyz=_f(I[1, 2]), izz=_f(I[2, 2]), geometry=geometry[i],
        ))
    springs = [spring_t.substitute(name=names[j], stiffness=_f(k[j])) for j in range(len(names))]
    hub_text, clamp_parent, clamp_x = "", "world", "0"
    if hub is not None:
        hub_text = _t("hub.urdf.tmpl").substitute(
            lower=_f(-HUB_LIMIT_RAD), upper=_f(HUB_LIMIT_RAD), effort=_f(JOINT_EFFORT_LIMIT_NM),
            velocity=_f(JOINT_VELOCITY_LIMIT_RAD_S), inertia=_f(hub.inertia_kg_m2),
            axis=_AXIS[hub.axis])
        clamp_parent, clamp_x = "hub_body", _f(hub.radius_m)
    return _t("robot.urdf.tmpl").substitute(
        hub=hub_text, clamp_parent=clamp_parent, clamp_x=clamp_x,
        robot_name=escape(robot_name, _ATTRIBUTE), body="".join(body).rstrip("\n"),
        n=n, tip_x=_f(lengths[n]), springs="".join(springs).rstrip("\n"),
        record=f"<!--{comment}-->\n" if comment else "",
    )


def read_springs(urdf_text: str, joint_names: list[str]) -> np.ndarray:
    """Spring stiffness of the named joints from the Gazebo ``<springStiffness>`` tags, N m/rad.

    Raises
    ------
    BeamInputError
        If the XML is malformed, a joint has no spring, or a stiffness is not a positive number.
    """
    try:
        root = ET.fromstring(urdf_text)
    except ET.ParseError as exc:
        raise BeamInputError(f"urdf: not valid XML ({exc})") from None
    found: dict[str, float] = {}
    for g in root.iter("gazebo"):
        ref = g.get("reference")
        el = g.find("springStiffness")
        if ref is None or el is None:
            continue
        try:
            v = float((el.text or "").strip())
        except ValueError:
            raise BeamInputError(
                f"springStiffness of {ref} = {el.text!r}: must be a number (N m/rad)"
            ) from None
        if not (math.isfinite(v) and v > 0.0):
            raise BeamInputError(f"springStiffness of {ref} = {v}: must be finite and > 0")
        found[ref] = v
    missing = [name for name in joint_names if name not in found]
    if missing:
        raise BeamInputError(
            f"joint {missing[0]!r}: no <gazebo reference=...><springStiffness> in the URDF"
        )
    return np.array([found[name] for name in joint_names])
