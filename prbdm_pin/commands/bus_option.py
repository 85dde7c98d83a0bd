"""``--bus MASS:IXX,IYY,IZZ[:X,Y,Z]`` of ``prbdm simulate`` and ``prbdm linearize``.

A free-floating bus (:class:`prbdm_pin.FreeBus`): its mass (kg), its principal moments of
inertia about its centre of mass (kg m^2, along the bus frame's axes; the centre of mass at the
bus frame's origin) and where the beam's root is clamped in the bus frame (m, default the
origin). The option is parsed numpy-free (refused before any import), the bus built with the
model.
"""

from __future__ import annotations

import argparse
import math

from ..errors import BeamInputError

__all__ = ["add_bus_option", "bus_option", "with_bus", "bus_record", "state_units"]

_SPELLING = "MASS:IXX,IYY,IZZ[:X,Y,Z] (kg, kg m^2, m)"


def add_bus_option(p: argparse.ArgumentParser) -> None:
    """Add ``--bus`` to a subparser."""
    p.add_argument("--bus", default=None, metavar="MASS:IXX,IYY,IZZ[:X,Y,Z]",
                   help="a free-floating bus the root is clamped to: mass kg, principal moments "
                        "of inertia about its centre of mass kg m^2 (the bus frame's origin), "
                        "and the root's place on it m (default 0,0,0); its six coordinates "
                        "(bus_x, bus_y, bus_z m, bus_yaw, bus_pitch, bus_roll rad) come first, "
                        "the member's outputs are relative to it; outputs bus_position_x|y|z, "
                        "bus_attitude_x|y|z, bus_rate_x|y|z")


def _numbers(text: str, count: int, option: str) -> list[float]:
    parts = text.split(",")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise BeamInputError(f"{option}: must be {_SPELLING}")
    return values


def bus_option(text: str | None) -> tuple | None:
    """Return ``--bus`` as (mass, (Ixx, Iyy, Izz), root) or None; BeamInputError naming it."""
    if text is None:
        return None
    where = f"--bus = {text!r}"
    parts = text.split(":")
    if len(parts) not in (2, 3):
        raise BeamInputError(f"{where}: must be {_SPELLING}")
    mass = _numbers(parts[0], 1, where)[0]
    moments = tuple(_numbers(parts[1], 3, where))
    root = tuple(_numbers(parts[2], 3, where)) if len(parts) == 3 else (0.0, 0.0, 0.0)
    return mass, moments, root


def with_bus(model, spec: tuple):
    """``model`` rebuilt on the bus ``spec`` (needs the beam: a URDF does not carry it)."""
    from ..io.record_checks import LINK_FLOOR_FRACTION
    from ..model.prbdm_model import build_model
    from ..model.supports import FreeBus

    if model.beam is None:
        raise BeamInputError("--bus: needs the beam (give a fit.json or a model JSON; a URDF "
                             "does not carry it)")
    mass, moments, root = spec
    try:
        bus = FreeBus(mass, moments, root_m=root)
    except BeamInputError as exc:
        raise BeamInputError(f"--bus: {exc}") from None
    return build_model(model.beam, model.lengths_m, model.stiffness_Nm_per_rad,
                       min_fraction=LINK_FLOOR_FRACTION, axes=model.axes, support=bus)


def bus_record(model) -> dict | None:
    """Return the model's bus as a JSON-ready dict (None without one)."""
    bus = getattr(model, "bus", None)
    if bus is None:
        return None
    return {"mass_kg": bus.mass_kg, "inertia_kg_m2": [list(r) for r in bus.inertia_kg_m2],
            "com_m": list(bus.com_m), "root_m": list(bus.root_m)}


def state_units(model) -> list[str]:
    """Return the units of the linear plant's states: coordinates, then rates."""
    n = model.pin_model.nv
    if getattr(model, "bus", None) is None:
        return ["rad"] * n + ["rad/s"] * n
    k = n - 6  # the bus's x, y, z (m) and yaw, pitch, roll (rad) first
    return ["m"] * 3 + ["rad"] * (3 + k) + ["m/s"] * 3 + ["rad/s"] * (3 + k)
