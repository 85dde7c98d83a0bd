"""The model JSON file: a PRBDM's parameters, its plant (hub, strain actuators), its record.

The file is written by :func:`model_dict` and read back, validated, by :func:`read_model_json`
and :func:`read_plant_json`.

Plant fields: ``hub`` is null or ``{"inertia_kg_m2": J, "radius_m": r, "axis": a}`` (``a`` the
world axis "x", "y" or "z" it turns about; a file without ``axis`` has a hub about y);
``actuators`` is a list of ``{"x_start_m": a, "x_end_m": b}`` (m from the root, on the beam, a < b),
with ``"joint_weights": [w_1, ..., w_n]`` (one finite number per joint) for an actuator whose map
was fitted to the truth. A file written before they existed has neither and reads as the
clamped beam without actuators.

Spatial chain: ``"axes"`` (``"xy"``, ``"yz"`` or ``"xyz"``: the joint axes at each node) is
written for a spatial model only, and ``stiffness_Nm_per_rad`` holds ``n_joints`` times its
length springs, node-major in the order y, z, x (:attr:`PrbdmModel.spring_axes`); a file
without ``"axes"`` is the planar chain (``"y"``), so a planar model's file is as before. A
spatial model has no hub and no actuators.
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import Any

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import beam_to_dict
from ..options.choices import Axes
from ..version import __version__
from .beam_file import beam_from_dict
from .export_record import export_record

__all__ = ["JSON_FORMAT", "model_dict", "read_model_json", "read_plant_json"]

JSON_FORMAT = "prbdm-model/1"


def model_dict(model, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
               actuators=()) -> dict[str, Any]:
    """Return the JSON-ready parameters of ``model`` (SI units) with its plant and record.

    The mapping holds the model's hub and strain ``actuators``, and its
    :class:`~prbdm_pin.files.export_record.ExportRecord` fields; a spatial model's also its
    ``axes`` (module notes).
    """
    rec = export_record(model, "json", damping_ratio, damping_form, omega_truth_rad_s,
                        actuators=actuators)
    s = model.sections
    hub = model.hub
    out = {
        "format": JSON_FORMAT,
        "version": __version__,
        "beam": None if model.beam is None else beam_to_dict(model.beam),
        "n_joints": model.n_joints,
        **({"axes": model.axes.value} if model.axes.spatial else {}),
        "lengths_m": [float(v) for v in model.lengths_m],
        "stiffness_Nm_per_rad": [float(v) for v in model.stiffness_Nm_per_rad],
        "hub": None if hub is None else {"inertia_kg_m2": hub.inertia_kg_m2,
                                         "radius_m": hub.radius_m, "axis": hub.axis},
        "actuators": [_actuator_dict(a) for a in rec.actuators()],
        "links": [
            {
                "start_m": float(s.start_m[i]),
                "end_m": float(s.end_m[i]),
                "mass_kg": float(s.mass_kg[i]),
                "com_m": [float(v) for v in s.com_m[i]],
                "inertia_com_kg_m2": [[float(v) for v in row] for row in s.inertia_com_kg_m2[i]],
            }
            for i in range(s.mass_kg.size)
        ],
    }
    out.update(rec.to_dict())
    return out


def _actuator_dict(a) -> dict[str, Any]:
    out: dict[str, Any] = {"x_start_m": a.x_start_m, "x_end_m": a.x_end_m}
    if a.joint_weights is not None:
        out["joint_weights"] = list(a.joint_weights)
    return out


def _number(what: str, field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(float(value)):
        raise BeamInputError(f"{what}: {field} = {value!r:.60}: must be a finite number")
    return float(value)


def _fields(what: str, field: str, value: Any, keys: tuple[str, ...]) -> list[float]:
    if not isinstance(value, dict):
        raise BeamInputError(f"{what}: {field} = {value!r:.60}: must be an object with "
                             + ", ".join(keys))
    for key in keys:
        if key not in value:
            raise BeamInputError(f"{what}: {field}.{key}: missing")
    return [_number(what, f"{field}.{key}", value[key]) for key in keys]


def _hub(what: str, value: Any):
    from ..model.hub import HUB_AXES, Hub

    if value is None:
        return None
    J, r = _fields(what, "hub", value, ("inertia_kg_m2", "radius_m"))
    if not J > 0.0:
        raise BeamInputError(f"{what}: hub.inertia_kg_m2 = {J!r}: must be > 0 (kg m^2)")
    if r < 0.0:
        raise BeamInputError(f"{what}: hub.radius_m = {r!r}: must be >= 0 (m)")
    # files written before the hub had an axis turn it about y
    axis = value.get("axis", "y")
    if axis not in HUB_AXES:
        raise BeamInputError(f"{what}: hub.axis = {axis!r:.60}: must be 'x', 'y' or 'z'")
    return Hub(J, r, axis)


def _axes(what: str, value: Any) -> Axes:
    if not (isinstance(value, str) and value in Axes.values()):
        raise BeamInputError(f"{what}: axes = {value!r:.60}: must be one of "
                             f"{', '.join(repr(a) for a in Axes.values())} (the joint axes at "
                             "each node; 'y' when absent)")
    return Axes(value)


def _joint_weights(what: str, field: str, value: Any, n_joints: int) -> tuple | None:
    if value is None:
        return None
    if not isinstance(value, list):
        raise BeamInputError(f"{what}: {field}.joint_weights = {value!r:.60}: must be a list "
                             "of numbers, one per joint")
    w = tuple(_number(what, f"{field}.joint_weights[{j}]", v) for j, v in enumerate(value))
    if len(w) != n_joints:
        raise BeamInputError(f"{what}: {field}.joint_weights: has {len(w)} entries, this model "
                             f"has {n_joints} joints")
    return w


def _actuators(what: str, value: Any, length_m: float, n_joints: int) -> tuple:
    from ..model.inputs import ON_JOINT_RTOL, StrainActuator

    if value is None:
        return ()
    if not isinstance(value, list):
        raise BeamInputError(f"{what}: actuators = {value!r:.60}: must be a list")
    tol = ON_JOINT_RTOL * length_m
    out = []
    for i, item in enumerate(value):
        field = f"actuators[{i}]"
        a, b = _fields(what, field, item, ("x_start_m", "x_end_m"))
        for key, v in (("x_start_m", a), ("x_end_m", b)):
            if v < -tol or v > length_m + tol:
                raise BeamInputError(f"{what}: {field}.{key} = {v!r}: must lie on the beam, in "
                                     f"[0, {length_m:g}] (m)")
        if not a < b:
            raise BeamInputError(f"{what}: {field}.x_end_m = {b!r}: must be > x_start_m = "
                                 f"{a!r} (m)")
        w = _joint_weights(what, field, item.get("joint_weights"), n_joints)
        out.append(StrainActuator(a, b, joint_weights=w))
    return tuple(out)


def read_plant_json(path: str | os.PathLike):
    """Read the model and the strain actuators of a model JSON file.

    Parameters
    ----------
    path : str or path-like
        A model JSON file (``prbdm-model/1``, as the JSON export writes it).

    Returns
    -------
    model : PrbdmModel
        The model, with its hub if the file records one, and its actuators
        (``model.actuators``, as :func:`prbdm_pin.load_urdf` reads a URDF's).
    actuators : tuple of StrainActuator
        The plant's strain actuators (:class:`~prbdm_pin.model.inputs.StrainActuator`; spans
        in m).

    Raises
    ------
    BeamInputError
        Naming the file and the field (``hub.inertia_kg_m2``, ``actuators[1].x_end_m``,
        ``actuators[0].joint_weights``, ...).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> patch = pp.StrainActuator(0.1, 0.3)  # over the joint at 0.2 m
    >>> path = pp.export_model(model, folder / "model.json", "json", actuators=(patch,))
    >>> again, actuators = pp.read_plant_json(path)
    >>> again.n_joints, actuators[0].x_start_m, actuators[0].x_end_m
    (2, 0.1, 0.3)
    """
    from ..io.jsonfile import read_json
    from ..io.record_checks import LINK_FLOOR_FRACTION, check_chain, file_kind
    from ..model.prbdm_model import build_model

    what = f"model file {str(path)!r}"
    d = read_json(path, "model file")
    if not isinstance(d, dict) or d.get("format") != JSON_FORMAT:
        kind = file_kind(d)
        got = f"a {kind} file" if kind != "unknown" else (
            f"format = {d.get('format')!r:.60}" if isinstance(d, dict)
            else f"a JSON {type(d).__name__}")
        raise BeamInputError(f"{what}: {got}; format must be {JSON_FORMAT!r}")
    if d.get("beam") is None:
        raise BeamInputError(f"{what}: has no beam; load the URDF export instead")
    for key in ("lengths_m", "stiffness_Nm_per_rad"):
        if key not in d:
            raise BeamInputError(f"{what}: missing {key!r}")
    try:
        beam = beam_from_dict(d["beam"], check_caps=True)
    except BeamInputError as exc:
        raise BeamInputError(f"{what}: beam: {exc}") from None
    axes = _axes(what, d.get("axes", Axes.Y.value))
    per_node = len(axes.joint_order)
    lengths, k = check_chain(what, d["lengths_m"], d["stiffness_Nm_per_rad"], beam.length_m,
                             springs_per_joint=per_node)
    n = lengths.size - 1
    if "n_joints" in d and d["n_joints"] != n:
        raise BeamInputError(f"{what}: n_joints = {d['n_joints']!r:.60}: lengths_m and "
                             f"stiffness_Nm_per_rad hold {n} joints")
    hub = _hub(what, d.get("hub"))
    actuators = _actuators(what, d.get("actuators"), beam.length_m, n)
    if axes.spatial and (hub is not None or actuators):
        field = "hub" if hub is not None else "actuators"
        raise BeamInputError(f"{what}: {field}: a hub and strain actuators go with the planar "
                             f"chain only (axes = 'y'); this file has axes = {axes.value!r}")
    model = build_model(beam, lengths, k, min_fraction=LINK_FLOOR_FRACTION, hub=hub, axes=axes)
    return dataclasses.replace(model, actuators=tuple(actuators)), actuators


def read_model_json(path: str | os.PathLike):
    """Rebuild the PrbdmModel from a file written by :func:`write_json` (needs its beam).

    The model is on its hub if the file records one, and carries the actuators it records
    (``model.actuators``; :func:`read_plant_json` also returns them).

    Parameters
    ----------
    path : str or path-like
        A model JSON file (``prbdm-model/1``).

    Returns
    -------
    PrbdmModel
        The model: link lengths in m, springs in N m/rad.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = pp.export_model(model, folder / "model.json", "json")
    >>> again = pp.read_model_json(path)
    >>> bool(np.allclose(again.natural_frequencies(), model.natural_frequencies()))
    True
    """
    return read_plant_json(path)[0]
