"""The export record as the text of an XML comment (URDF, MJCF), and read back from it.

The comment holds one ``key: values`` line per field, under a fixed head line.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from ..errors import BeamInputError
from .export_record import FLOAT_FIELDS, ExportRecord

__all__ = ["comment_text", "read_export_record", "number_text", "vector_text",
           "gravity_comment", "read_gravity_comment"]

WEIGHTS_VW = "virtual-work"
RECORD_HEAD = " prbdm_pin export record (prbdm_pin.files.export.read_export_record reads it)"


def number_text(v: float) -> str:
    """Write a float as text that reads back to the same double."""
    return repr(float(v))


def vector_text(v: np.ndarray) -> str:
    """Floats as space-separated :func:`number_text`."""
    return " ".join(number_text(x) for x in v)


def comment_text(record: ExportRecord) -> str:
    """``record`` as the text of an XML comment (one ``key: values`` line each)."""
    def vals(a):
        return "unknown" if a is None else vector_text(a)

    def num(v):
        return "unknown" if v is None else number_text(v)

    lines = [
        RECORD_HEAD,
        "     The exported model at the straight pose (q = 0): its own natural frequencies",
        "     (rad/s), the truth frequencies it was fitted to (rad/s), the signed errors",
        "     100 (omega_model / omega_truth - 1) and the worst absolute error (%); the joint",
        "     damping written (C = beta K for the stiffness form, N m s/rad) and the damping",
        "     ratio it gives each mode, ascending frequency.",
        f"     natural_frequencies_rad_s: {vals(record.natural_frequencies_rad_s)}",
        f"     omega_truth_rad_s: {vals(record.omega_truth_rad_s)}",
        f"     omega_errors_pct: {vals(record.omega_errors_pct)}",
        f"     worst_mode_error_pct: {num(record.worst_mode_error_pct)}",
        f"     worst_mode: {'unknown' if record.worst_mode is None else record.worst_mode}",
        f"     damping_requested: {record.damping_requested}",
        f"     damping_form: {record.damping_form}",
        f"     damping_ratio: {vals(record.damping_ratio)}",
        f"     damping_beta_s: {num(record.damping_beta_s)}",
        f"     joint_damping_Nms_per_rad: {vals(record.joint_damping_Nms_per_rad)}",
        f"     modal_damping_ratios: {vals(record.modal_damping_ratios)}",
    ]
    if record.damping_ratio_errors is not None:
        lines += [
            "     modal_fit: the joint damping is the diagonal c >= 0 fitted by least squares",
            "     to the asked ratios; modal_damping_ratios are the ratios it achieves (from",
            "     the damped model's complex eigenvalues), and each mode's achieved minus",
            "     asked ratio is:",
            f"     damping_ratio_errors: {vals(record.damping_ratio_errors)}",
        ]
    if record.hub_frequencies_rad_s is not None:
        lines += [
            "     The model turns on a hub: the frequencies and errors above are the",
            "     clamped (fitted) model's; the hub model's flexible frequencies (rad/s,",
            "     the rigid mode at 0 left out) follow; the damping and its modal ratios",
            "     are the hub model's.",
            f"     hub_frequencies_rad_s: {vals(record.hub_frequencies_rad_s)}",
        ]
    if record.strain_actuators_m.size:
        lines += [
            "     Strain actuators [x_start_m x_end_m], m from the root, ';' between them:",
            "     strain_actuators_m: "
            + "; ".join(vector_text(a) for a in record.strain_actuators_m),
        ]
    if record.strain_actuator_weights:
        lines += [
            "     Their joint weights, N m per N m of patch moment, one per joint:",
            "     fitted to the truth's modal gains, or virtual-work (1 inside, 1/2 on ends):",
            "     strain_actuator_weights: " + "; ".join(
                WEIGHTS_VW if v is None else vector_text(v)
                for v in record.strain_actuator_weights),
        ]
    if record.inputs:
        lines.append("     inputs: " + " ".join(record.inputs))
    lines += [f"     warning: {w}" for w in record.warnings]
    return "\n".join(lines) + "\n"



def gravity_comment(gravity_m_s2: np.ndarray | None) -> str:
    """Return the URDF's gravity convention as lines of its XML comment.

    URDF has no gravity element: the comment states the gravity the model was fitted in
    (m/s^2, world) and that the consumer must set it; Pinocchio's URDF parser and MuJoCo's
    URDF import default to -9.81 m/s^2 along z.
    """
    g = np.zeros(3) if gravity_m_s2 is None else np.asarray(gravity_m_s2, dtype=float)
    if np.any(g):
        fitted = (f"     This model was fitted in gravity_m_s2: {vector_text(g)} (m/s^2, world;",
                  "     its frequencies and tip in fit.json are about its sag in it): the",
                  "     consumer must set this gravity (Pinocchio: model.gravity; MuJoCo:")
    else:
        fitted = ("     This model was fitted without gravity (gravity_m_s2: 0.0 0.0 0.0,",
                  "     m/s^2, world): the consumer must set gravity to zero (Pinocchio:",
                  "     model.gravity = pinocchio.Motion.Zero(); MuJoCo:")
    return "\n".join((
        "     Gravity: URDF has no gravity element, and Pinocchio's URDF parser and MuJoCo's",
        "     URDF import default to -9.81 m/s^2 along z.", *fitted,
        "     <option gravity>; prbdm_pin.load_urdf sets zero).")) + "\n"


def read_gravity_comment(text: str) -> list[str] | None:
    """Return the gravity a URDF's comment states it was fitted in (3 texts), None without.

    The inverse of :func:`gravity_comment` (a file written before it, or fitted without
    gravity, reads as None); the caller checks the numbers.
    """
    m = re.search(r"fitted in gravity_m_s2: (\S+) (\S+) (\S+) \(", text)
    return None if m is None else list(m.groups())


def read_export_record(text: str) -> ExportRecord | None:
    """Read the :class:`ExportRecord` in the comment of an exported URDF or MJCF text.

    None when the text has none.

    Raises BeamInputError when the record is there but malformed.
    """
    start = text.find("<!--" + RECORD_HEAD)
    if start < 0:
        return None
    end = text.find("-->", start)
    if end < 0:
        raise BeamInputError("export record: comment is not closed")
    fields: dict[str, Any] = {}
    warnings = []
    for line in text[start:end].splitlines()[1:]:
        m = re.match(r"\s*([A-Za-z0-9_]+): (.*)$", line)
        if m is None:
            continue
        key, value = m.group(1), m.group(2).strip()
        if key == "warning":
            warnings.append(value)
        elif key == "strain_actuators_m":
            fields[key] = np.array([p.split() for p in value.split(";")], dtype=float)
        elif key == "strain_actuator_weights":
            fields[key] = tuple(None if p.strip() == WEIGHTS_VW else np.array(p.split(),
                                dtype=float) for p in value.split(";"))
        elif key == "inputs":
            fields[key] = tuple(value.split())
        elif key in FLOAT_FIELDS:
            fields[key] = None if value == "unknown" else np.array(value.split(), dtype=float)
        elif key in ("worst_mode_error_pct", "damping_beta_s"):
            fields[key] = None if value == "unknown" else float(value)
        elif key == "worst_mode":
            fields[key] = None if value == "unknown" else int(value)
        elif key in ("damping_requested", "damping_form"):
            fields[key] = value
    try:
        return ExportRecord(warnings=tuple(warnings), **fields)
    except (TypeError, ValueError) as exc:
        raise BeamInputError(f"export record: malformed ({exc})") from None
