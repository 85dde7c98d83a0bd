"""Validation of a URDF file before Pinocchio reads it, and of the chain read from it.

A file on disk may be truncated, edited, of another kind or hostile: the text is size-capped
and decoded, the XML checked for a PRBDM's joints, finite numbers and positive lengths, masses
and inertias, and every failure raises :class:`~prbdm_pin.errors.BeamInputError` naming the
file, the joint or link, and the value.
"""

from __future__ import annotations

import math
import os
import re
import xml.etree.ElementTree as ET

import numpy as np

from ..errors import BeamInputError
from ..options.limits import check_cap

__all__ = ["HUB_LINK", "read_urdf_text", "check_urdf", "check_sections", "hub_inertia"]

HUB_LINK = "hub_body"
# a spatial chain's massless link between two joints of one node (link_j_y, link_j_z)
_NODE_LINK = re.compile(r"link_[0-9]+_[xyz]")
_NODE_JOINT = re.compile(r"joint_([0-9]+)_[xyz]")


def read_urdf_text(path: str | os.PathLike) -> str:
    """Read the text of a URDF file: size capped by ``max_file_bytes``, UTF-8, named on error."""
    from ..options.validate import check_path

    p = check_path("path", path, "URDF file")
    label = f"urdf file {str(p)!r}"
    try:
        if not p.is_file():
            raise BeamInputError(f"{label}: not found or not a regular file")
        size = p.stat().st_size
        check_cap(f"{label}: size (bytes)", size, "max_file_bytes")
        raw = p.read_bytes()
    except OSError as exc:
        raise BeamInputError(f"{label}: cannot be read ({exc.strerror or exc})") from None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BeamInputError(
            f"{label}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None


def _numbers(label: str, text: str | None, count: int) -> list[float]:
    parts = (text or "").split()
    try:
        vals = [float(v) for v in parts]
    except ValueError:
        vals = []
    if len(vals) != count or not all(math.isfinite(v) for v in vals):
        raise BeamInputError(f"{label} = {text!r:.60}: must be {count} finite number"
                             + ("s" if count > 1 else ""))
    return vals


def check_urdf(text: str, what: str = "urdf") -> int:
    """Check a PRBDM URDF before Pinocchio reads it; returns the number of revolute joints.

    Every joint is revolute or fixed, 1 <= revolute joints <= ``max_joints``, every number is
    finite, joint offsets (link lengths, m) are > 0, link masses (kg) and principal inertias
    (kg m^2) are > 0 (the massless ``tip`` frame and the ``world`` root excepted; the hub link
    ``hub_body`` is massless with inertias > 0, and the hub radius, ``clamp``'s x, may be 0).
    A spatial chain's node links ``link_j_a`` may be massless and the joints after them at
    x = 0 (:func:`~prbdm_pin.model.pin_chain.spatial_lengths` checks the rest); the cap is on
    the nodes.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise BeamInputError(f"{what}: not valid XML ({exc})") from None
    if root.tag != "robot":
        raise BeamInputError(f"{what}: root element <{root.tag}>: must be <robot>")
    joints = root.findall("joint")
    revolute = 0
    plain, nodes = 0, set()  # revolute joints; a spatial node's joint_j_a count once per j
    for j in joints:
        name = j.get("name", "?")
        kind = j.get("type")
        if kind not in ("revolute", "fixed"):
            raise BeamInputError(f"{what}: joint {name!r} type = {kind!r}: a PRBDM has only "
                                 "revolute joints (and fixed ones at the clamp and the tip)")
        revolute += kind == "revolute"
        node = _NODE_JOINT.fullmatch(name) if kind == "revolute" else None
        if node:
            nodes.add(node.group(1))
        else:
            plain += kind == "revolute"
        origin = j.find("origin")
        xyz = _numbers(f"{what}: joint {name!r} origin xyz", None if origin is None
                       else origin.get("xyz", "0 0 0"), 3)
        parent = j.find("parent")
        parent_link = None if parent is None else parent.get("link")
        if parent_link == HUB_LINK:
            if not xyz[0] >= 0.0:
                raise BeamInputError(f"{what}: joint {name!r} origin x = {xyz[0]!r} m: the hub "
                                     "radius must be >= 0")
        elif parent_link not in (None, "world") and not _NODE_LINK.fullmatch(parent_link) \
                and not xyz[0] > 0.0:
            raise BeamInputError(f"{what}: joint {name!r} origin x = {xyz[0]!r} m: the length "
                                 f"of link {parent_link!r} must be > 0")
    # the cap is on the nodes (a spatial node's joints count once), as build_model's
    check_cap(f"{what}: revolute joints", plain + len(nodes), "max_joints")
    if revolute < 1:
        raise BeamInputError(f"{what}: has {revolute} revolute joints: a PRBDM needs n >= 1")
    for link in root.findall("link"):
        name = link.get("name", "?")
        inertial = link.find("inertial")
        if inertial is None:
            continue
        massless = name == "tip" or _NODE_LINK.fullmatch(name) is not None
        m_el = inertial.find("mass")
        (mass,) = _numbers(f"{what}: link {name!r} mass", None if m_el is None
                           else m_el.get("value"), 1)
        # the hub is massless (its axis is fixed) but has a rotational inertia
        if not (mass >= 0.0 if massless or name == HUB_LINK else mass > 0.0):
            raise BeamInputError(f"{what}: link {name!r} mass = {mass!r} kg: must be > 0")
        origin = inertial.find("origin")
        if origin is not None:
            _numbers(f"{what}: link {name!r} inertial origin xyz", origin.get("xyz", "0 0 0"), 3)
        el = inertial.find("inertia")
        if el is None:
            raise BeamInputError(f"{what}: link {name!r}: <inertial> has no <inertia>")
        for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
            (v,) = _numbers(f"{what}: link {name!r} inertia {key}", el.get(key), 1)
            if key in ("ixx", "iyy", "izz") and not (v >= 0.0 if massless else v > 0.0):
                raise BeamInputError(f"{what}: link {name!r} inertia {key} = {v!r} kg m^2: "
                                     "must be > 0")
    return revolute


def check_sections(what: str, lengths_m: np.ndarray, mass_kg: np.ndarray) -> None:
    """After parsing: every link length (m) and mass (kg) of the chain finite and > 0."""
    for i, v in enumerate(lengths_m):
        if not (math.isfinite(v) and v > 0.0):
            raise BeamInputError(f"{what}: link_{i} length = {float(v)!r} m: must be > 0")
    for i, v in enumerate(mass_kg):
        if not (math.isfinite(v) and v > 0.0):
            raise BeamInputError(f"{what}: link_{i} mass = {float(v)!r} kg: must be > 0 "
                                 "(a link without <inertial> has none)")


def hub_inertia(text: str, what: str = "urdf") -> float:
    """Read the hub's inertia about its axis (``iyy`` of link ``hub_body``), kg m^2.

    From a URDF text that :func:`check_urdf` accepted.
    """
    root = ET.fromstring(text)
    for link in root.findall("link"):
        el = None if link.get("name") != HUB_LINK else link.find("inertial/inertia")
        if el is not None:
            return float(el.get("iyy"))
    raise BeamInputError(f"{what}: joint 'hub' without a link {HUB_LINK!r} with an <inertia>")
