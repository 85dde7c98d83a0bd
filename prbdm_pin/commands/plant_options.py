"""Plant options shared by ``prbdm linearize`` and ``prbdm export``.

Input names, strain actuators (``--actuator XA:XB``) and a hub (``--hub INERTIA:RADIUS``,
``--hub-axis {x,y,z}``), each
refused with a message naming the option and the value.
"""

from __future__ import annotations

import argparse
import math

from ..errors import BeamInputError

__all__ = ["add_plant_options", "names_option", "pair_option", "actuators_option",
           "hub_option", "with_hub", "actuators_on_beam", "add_span_option", "spans_option",
           "spans_on_beam"]


def add_plant_options(p: argparse.ArgumentParser) -> None:
    """Add ``--actuator`` (repeatable), ``--hub`` and ``--hub-axis`` to a subparser."""
    p.add_argument("--actuator", action="append", default=[], metavar="XA:XB",
                   help="a strain actuator from XA to XB m along the beam (repeat for more; "
                        "strain[i] is the i-th)")
    p.add_argument("--hub", default=None, metavar="INERTIA:RADIUS",
                   help="a rotating hub at the root: inertia kg m^2, radius m")
    p.add_argument("--hub-axis", default=None, metavar="{x,y,z}",
                   help="the world axis the --hub turns about (default y, in the beam's "
                        "bending plane; z: the beam sweeps the xy-plane and bends out of it; x: "
                        "the beam spins about its own axis)")


def names_option(text: str, option: str) -> tuple[str, ...]:
    """Split a comma-separated list of input or output names (each ``base`` or ``base[i]``)."""
    from ..model.names import split_name

    names = tuple(s.strip() for s in text.split(","))
    for i, name in enumerate(names):
        split_name(name, f"{option}[{i}]" if len(names) > 1 else option)
    return names


def pair_option(text: str, option: str, what: str) -> tuple[float, float]:
    """``A:B`` as two finite numbers."""
    parts = text.split(":")
    try:
        a, b = (float(v) for v in parts)
    except ValueError:
        a = b = math.nan
    if len(parts) != 2 or not (math.isfinite(a) and math.isfinite(b)):
        raise BeamInputError(f"{option} = {text!r}: must be two numbers {what}")
    return a, b


def actuators_option(texts: list[str]) -> list:
    """Return the ``--actuator XA:XB`` values as StrainActuators (XA < XB).

    The beam is checked later by :func:`actuators_on_beam`.
    """
    from ..model.inputs import StrainActuator

    acts = []
    for text in texts:
        a, b = pair_option(text, "--actuator", "XA:XB (m)")
        try:
            acts.append(StrainActuator(a, b))
        except BeamInputError as exc:
            raise BeamInputError(f"--actuator = {text!r}: {exc}") from None
    return acts


def hub_option(text: str | None, axis: str | None = None):
    """Return ``--hub INERTIA:RADIUS`` with ``--hub-axis`` as a Hub (None without ``--hub``)."""
    from ..model.hub import Hub

    if axis is not None and axis not in ("x", "y", "z"):
        raise BeamInputError(f"--hub-axis = {axis!r}: must be x, y or z (the world axis the "
                             "hub turns about)")
    if text is None:
        if axis is not None:
            raise BeamInputError(f"--hub-axis = {axis!r}: needs --hub INERTIA:RADIUS")
        return None
    J, r = pair_option(text, "--hub", "INERTIA:RADIUS (kg m^2, m)")
    try:
        return Hub(J, r, "y" if axis is None else axis)
    except BeamInputError as exc:
        raise BeamInputError(f"--hub = {text!r}: {exc}") from None


def with_hub(model, hub):
    """``model`` rebuilt on ``hub`` (needs the beam: a URDF does not carry it)."""
    from ..io.record_checks import LINK_FLOOR_FRACTION
    from ..model.prbdm_model import build_model

    if model.beam is None:
        raise BeamInputError("--hub: needs the beam (give a fit.json or a model JSON; a "
                             "URDF does not carry it)")
    if model.axes.spatial:
        raise BeamInputError(f"--hub: a hub carries the planar chain only; this model has "
                             f"axes = {model.axes.value!r}")
    return build_model(model.beam, model.lengths_m, model.stiffness_Nm_per_rad,
                       min_fraction=LINK_FLOOR_FRACTION, hub=hub)


def actuators_on_beam(model, actuators, texts: list[str], fitted: bool = False) -> None:
    """Refuse an ``--actuator`` that leaves the beam of ``model``.

    Unless its weights are to be fitted (``fitted``: ``--fit-actuators``), a patch must also
    hold a joint: the virtual-work map gives a patch between joints no input at all.
    """
    from ..model.inputs import check_patch, strain_map

    for a, text in zip(actuators, texts, strict=True):
        (check_patch if fitted else strain_map)(model.lengths_m, a, f"--actuator = {text!r}:")


def add_span_option(p: argparse.ArgumentParser) -> None:
    """Add ``--distributed-span`` (repeatable) to a subparser."""
    p.add_argument("--distributed-span", action="append", default=[], metavar="XA:XB",
                   help="a span XA to XB m along the beam for distributed_force_x/y/z[i] (repeat "
                        "for more; the i-th is [i]); the plain names cover the whole beam")


def spans_option(texts: list[str], option: str = "--distributed-span") -> tuple:
    """Return the ``--distributed-span XA:XB`` values as DistributedLoads (XA < XB).

    The beam is checked later by :func:`spans_on_beam`.
    """
    from ..model.loads import DistributedLoad

    loads = []
    for text in texts:
        a, b = pair_option(text, option, "XA:XB (m)")
        try:
            loads.append(DistributedLoad(a, b))
        except BeamInputError as exc:
            raise BeamInputError(f"{option} = {text!r}: {exc}") from None
    return tuple(loads)


def spans_on_beam(model, loads, texts: list[str], option: str = "--distributed-span") -> None:
    """Refuse a ``--distributed-span`` that leaves the beam of ``model``."""
    from ..model.loads import check_load

    for ld, text in zip(loads, texts, strict=True):
        check_load(model.lengths_m, ld, f"{option} = {text!r}:")
