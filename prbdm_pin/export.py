"""Write a PRBDM as URDF, MJCF (MuJoCo) or JSON; every file is written atomically.

Every export records the exported model itself (:class:`ExportRecord`): its natural frequencies at
the straight pose, and, when the truth it was fitted to is known, its signed per-mode errors
100 (omega_model / omega_truth - 1) and the worst of them; and the damping it carries with the
modal ratios that damping gives. URDF and MJCF hold the record as an XML comment
(:func:`read_export_record` reads it back), JSON as fields.

Gravity: the PRBDM has none. The MJCF sets ``<option gravity="0 0 0">``; URDF has no gravity
element, and ``pinocchio.buildModelFromUrdf`` and MuJoCo's URDF import turn on -9.81 m/s^2 along
z, so zero it there (``prbdm_pin.load_urdf`` does).

Damping: a diagonal joint damping (MJCF ``damping``, URDF ``<dynamics damping>``) carries the
stiffness-proportional form C = beta K exactly (K is diagonal), beta = 2 xi_1 / omega_1 at the
straight pose, so mode 1 gets the asked ratio xi_1 and mode k gets xi_1 omega_k / omega_1; it is
the default (``damping_form="stiffness"``) of those two formats. The modal form (every mode xi)
is not diagonal and no joint damping carries it: asked for a URDF or MJCF, the stiffness form with
mode 1's ratio is written instead and the record's ``warnings`` say so, with the modal ratios that
result. ``prbdm_pin.simulate(..., damping="stiffness")`` simulates the damping these files carry.

Loading the files
-----------------
URDF (``prbdm export fit.json --format urdf --out beam.urdf``)
    Pinocchio: ``prbdm_pin.load_urdf("beam.urdf")`` (springs included, gravity zero), or plain
    ``model = pinocchio.buildModelFromUrdf("beam.urdf")`` followed by
    ``model.gravity = pinocchio.Motion.Zero()``; the springs are not part of ``pinocchio.Model``
    (read them with ``prbdm_pin.urdf.read_springs``), the joint damping is ``model.damping``.
    pybullet: ``p.loadURDF("beam.urdf", useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE)``
    (without the flag pybullet replaces the inertia tensors by its own estimate); its mass matrix
    (``p.calculateMassMatrix``) is ours. It reads ``<dynamics damping>`` as the joint damping
    (``p.getJointInfo``), not the springs (apply -K q as joint torques), and its default
    velocity motors hold the joints until released
    (``p.setJointMotorControlArray(body, joints, p.VELOCITY_CONTROL, forces=[0] * n)``).
    yourdfpy reads the same masses, inertias and joint origins; MuJoCo compiles the URDF
    (``mujoco.MjModel.from_xml_path("beam.urdf")``: same mass matrix and joint damping, gravity
    -9.81 m/s^2, no springs: use the MJCF for MuJoCo). ROS tooling: the file is a standard URDF
    (``world`` -> fixed ``clamp`` -> ``link_0`` -> revolute ``joint_1`` ... ``joint_n`` about y
    -> fixed ``tip_joint`` -> ``tip``), so ``check_urdf beam.urdf``, ``robot_state_publisher``
    and RViz display it; Gazebo-classic reads ``<springStiffness>``/``<springReference>`` from
    the ``<gazebo reference="joint_j">`` tags (N m/rad, rad).
MJCF (``--format mjcf --out beam.xml``)
    MuJoCo: ``mujoco.MjModel.from_xml_path("beam.xml")``. A body chain ``link_1`` ... ``link_n``
    with hinge joints about y carrying ``stiffness`` (N m/rad), ``springref="0"`` and ``damping``
    (N m s/rad, the stiffness form above), each body's ``inertial`` (mass, centre of mass,
    ``fullinertia`` about the centre of mass), a ``tip`` site at the free end, and
    ``<option gravity="0 0 0" integrator="RK4">`` with a step of a twentieth of the shortest
    period. Apply a tip force through ``data.xfrc_applied`` on ``link_n``
    (the force at the body's centre of mass plus the moment (tip - com) x F), refreshed every
    step as the pose changes.
JSON (``--format json --out model.json``)
    The model parameters (beam, link lengths, springs, link inertias, natural frequencies) and the
    record's fields: ``prbdm_pin.export.read_model_json("model.json")`` rebuilds the model with
    ``build_model``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from . import __version__
from .beam_file import beam_from_dict
from .errors import BeamInputError
from .export_record import (
    EXPORT_DAMPING_FORMS,
    FORMATS,
    WORST_MODE_WARN_PCT,
    ExportRecord,
    export_record,
    read_export_record,
)
from .geometry import beam_to_dict
from .io import atomic_write_text

__all__ = [
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
    "WORST_MODE_WARN_PCT",
    "ExportRecord",
    "export_record",
    "read_export_record",
    "mjcf_text",
    "urdf_text",
    "model_dict",
    "write_urdf",
    "write_mjcf",
    "write_json",
    "export_model",
    "read_model_json",
]

JSON_FORMAT = "prbdm-model/1"


def _f(v: float) -> str:
    return repr(float(v))


def _vec(v: np.ndarray) -> str:
    return " ".join(_f(x) for x in v)


def mjcf_text(model, damping_ratio: float | np.ndarray = 0.02, timestep_s: float | None = None,
              *, damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
              ) -> str:
    """The model as an MJCF string for MuJoCo.

    Parameters
    ----------
    model : PrbdmModel
    damping_ratio : float or ndarray (n,)
        Mode 1's damping ratio: joint ``damping`` is beta K_jj (N m s/rad), the stiffness form
        (see :func:`export_record`). 0 writes undamped joints.
    timestep_s : float, optional
        MuJoCo time step, s (default: a twentieth of the shortest natural period; the
        integrator is RK4).
    damping_form, omega_truth_rad_s
        See :func:`export_record`; the record is written as a comment.
    """
    rec = export_record(model, "mjcf", damping_ratio, damping_form, omega_truth_rad_s)
    s = model.sections
    lengths = np.asarray(model.lengths_m, dtype=float)
    n = model.n_joints
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    c = rec.joint_damping_Nms_per_rad
    if timestep_s is None:
        timestep_s = 2.0 * np.pi / float(rec.natural_frequencies_rad_s[-1]) / 20.0
    if not (math.isfinite(timestep_s) and timestep_s > 0.0):
        raise BeamInputError(f"timestep = {timestep_s!r} s: must be finite and > 0")
    name = "prbdm" if model.beam is None else f"prbdm_{model.beam.name}"

    def inertial(i: int) -> str:
        com = s.com_m[i] - np.array([s.start_m[i], 0.0, 0.0])
        J = s.inertia_com_kg_m2[i]
        full = [J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2]]
        return (f'<inertial pos="{_vec(com)}" mass="{_f(s.mass_kg[i])}" '
                f'fullinertia="{_vec(full)}"/>')

    lines = [
        f"<mujoco model={quoteattr(name)}>",
        f"  <!-- Pseudo-rigid-body dynamic model written by prbdm_pin {__version__}: link 0 is",
        "       clamped to the world; hinge joints about y carry the torsional springs and the",
        "       stiffness-proportional damping beta K. -->",
        f"  <!--{rec.comment_text()}  -->",
        '  <compiler angle="radian" autolimits="true"/>',
        # RK4: at T_n/20 its step response is within 0.02 % of the peak of an accurate
        # integration (3R and 5R reference chains), the default Euler 0.1-0.6 % (1st order)
        f'  <option gravity="0 0 0" timestep="{_f(timestep_s)}" integrator="RK4"/>',
        "  <worldbody>",
        '    <body name="link_0" pos="0 0 0">',
        f"      {inertial(0)}",
    ]
    indent = "      "
    for j in range(1, n + 1):
        lines += [
            f'{indent}<body name="link_{j}" pos="{_f(lengths[j - 1])} 0 0">',
            f'{indent}  <joint name="joint_{j}" type="hinge" axis="0 1 0" pos="0 0 0" '
            f'stiffness="{_f(k[j - 1])}" springref="0" damping="{_f(c[j - 1])}"/>',
            f"{indent}  {inertial(j)}",
        ]
        indent += "  "
    lines.append(f'{indent}<site name="tip" pos="{_f(lengths[n])} 0 0" size="0.005"/>')
    for _ in range(n + 1):
        indent = indent[:-2]
        lines.append(f"{indent}</body>")
    lines += ["  </worldbody>", "</mujoco>", ""]
    return "\n".join(lines)


def urdf_text(model, damping_ratio: float | np.ndarray = 0.02, *,
              damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
              ) -> str:
    """The model's URDF with ``<dynamics damping>`` (stiffness form) and the record comment.

    Parameters as :func:`export_record`. With ``damping_ratio=0`` and no comment this is
    :attr:`PrbdmModel.urdf`.
    """
    from .urdf import render_urdf

    rec = export_record(model, "urdf", damping_ratio, damping_form, omega_truth_rad_s)
    name = "prbdm" if model.beam is None else f"prbdm_{model.beam.name}"
    return render_urdf(model.sections, model.lengths_m, model.stiffness_Nm_per_rad, name,
                       damping_Nms_per_rad=rec.joint_damping_Nms_per_rad,
                       comment=rec.comment_text())


def model_dict(model, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
               ) -> dict[str, Any]:
    """JSON-ready parameters of ``model`` (SI units) and its :class:`ExportRecord` fields."""
    rec = export_record(model, "json", damping_ratio, damping_form, omega_truth_rad_s)
    s = model.sections
    out = {
        "format": JSON_FORMAT,
        "version": __version__,
        "beam": None if model.beam is None else beam_to_dict(model.beam),
        "n_joints": model.n_joints,
        "lengths_m": [float(v) for v in model.lengths_m],
        "stiffness_Nm_per_rad": [float(v) for v in model.stiffness_Nm_per_rad],
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


def write_urdf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
               ) -> Path:
    """Write :func:`urdf_text` atomically."""
    return atomic_write_text(path, urdf_text(model, damping_ratio, damping_form=damping_form,
                                             omega_truth_rad_s=omega_truth_rad_s))


def write_mjcf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
               ) -> Path:
    """Write :func:`mjcf_text` atomically."""
    return atomic_write_text(path, mjcf_text(model, damping_ratio, damping_form=damping_form,
                                             omega_truth_rad_s=omega_truth_rad_s))


def write_json(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None
               ) -> Path:
    """Write :func:`model_dict` as JSON atomically."""
    d = model_dict(model, damping_ratio, damping_form=damping_form,
                   omega_truth_rad_s=omega_truth_rad_s)
    return atomic_write_text(path, json.dumps(d, indent=2) + "\n")


def export_model(model, path: str | os.PathLike, fmt: str,
                 damping_ratio: float | np.ndarray = 0.02, *, damping_form: str | None = None,
                 omega_truth_rad_s: np.ndarray | None = None) -> Path:
    """Write ``model`` to ``path`` in format ``fmt`` (``"urdf"``, ``"mjcf"`` or ``"json"``).

    ``damping_ratio``, ``damping_form`` and ``omega_truth_rad_s`` as :func:`export_record`
    (which gives what the file records, for a command to print).
    """
    writers = {"urdf": write_urdf, "mjcf": write_mjcf, "json": write_json}
    if fmt not in writers:
        raise BeamInputError(f"format = {fmt!r}: must be one of {', '.join(FORMATS)}")
    if getattr(model, "hub", None) is not None:
        # the file formats carry the clamped chain only: a hub would be dropped silently
        raise BeamInputError(f"hub = {model.hub!r}: a model with a hub cannot be exported; "
                             "export the model without the hub")
    return writers[fmt](model, path, damping_ratio, damping_form=damping_form,
                        omega_truth_rad_s=omega_truth_rad_s)


def read_model_json(path: str | os.PathLike):
    """Rebuild the PrbdmModel from a file written by :func:`write_json` (needs its beam)."""
    from .jsonfile import read_json
    from .model import build_model
    from .model_files import LINK_FLOOR_FRACTION, check_chain, file_kind

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
    lengths, k = check_chain(what, d["lengths_m"], d["stiffness_Nm_per_rad"], beam.length_m)
    if "n_joints" in d and d["n_joints"] != k.size:
        raise BeamInputError(f"{what}: n_joints = {d['n_joints']!r:.60}: lengths_m and "
                             f"stiffness_Nm_per_rad hold {k.size} joints")
    return build_model(beam, lengths, k, min_fraction=LINK_FLOOR_FRACTION)
