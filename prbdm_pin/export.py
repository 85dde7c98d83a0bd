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
import os
from pathlib import Path

import numpy as np

from .errors import BeamInputError
from .export_mjcf import mjcf_text
from .export_plant import mujoco_name
from .export_record import (
    EXPORT_DAMPING_FORMS,
    FORMATS,
    WORST_MODE_WARN_PCT,
    ExportRecord,
    export_record,
    read_export_record,
)
from .io import atomic_write_text
from .model_json import JSON_FORMAT, model_dict, read_model_json, read_plant_json

__all__ = [
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
    "WORST_MODE_WARN_PCT",
    "JSON_FORMAT",
    "ExportRecord",
    "export_record",
    "read_export_record",
    "mjcf_text",
    "mujoco_name",
    "urdf_text",
    "model_dict",
    "write_urdf",
    "write_mjcf",
    "write_json",
    "export_model",
    "read_model_json",
    "read_plant_json",
]


def urdf_text(model, damping_ratio: float | np.ndarray = 0.02, *,
              damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
              actuators=()) -> str:
    """The model's URDF with ``<dynamics damping>`` (stiffness form) and the record comment.

    Parameters as :func:`export_record`; a hub model gets the revolute joint ``hub`` (see the
    module notes). URDF has no tendons: ``actuators`` are recorded in the comment only. With
    ``damping_ratio=0``, no actuators and no comment this is :attr:`PrbdmModel.urdf`.
    """
    from .urdf import render_urdf

    rec = export_record(model, "urdf", damping_ratio, damping_form, omega_truth_rad_s,
                        actuators=actuators)
    name = "prbdm" if model.beam is None else f"prbdm_{model.beam.name}"
    return render_urdf(model.sections, model.lengths_m, model.stiffness_Nm_per_rad, name,
                       damping_Nms_per_rad=rec.joint_damping_Nms_per_rad,
                       comment=rec.comment_text(), hub=model.hub)


def write_urdf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
               actuators=()) -> Path:
    """Write :func:`urdf_text` atomically."""
    return atomic_write_text(path, urdf_text(model, damping_ratio, damping_form=damping_form,
                                             omega_truth_rad_s=omega_truth_rad_s,
                                             actuators=actuators))


def write_mjcf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
               actuators=(), inputs=None) -> Path:
    """Write :func:`mjcf_text` atomically."""
    return atomic_write_text(path, mjcf_text(model, damping_ratio, damping_form=damping_form,
                                             omega_truth_rad_s=omega_truth_rad_s,
                                             actuators=actuators, inputs=inputs))


def write_json(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
               actuators=()) -> Path:
    """Write :func:`model_dict` as JSON atomically."""
    d = model_dict(model, damping_ratio, damping_form=damping_form,
                   omega_truth_rad_s=omega_truth_rad_s, actuators=actuators)
    return atomic_write_text(path, json.dumps(d, indent=2) + "\n")


def export_model(model, path: str | os.PathLike, fmt: str,
                 damping_ratio: float | np.ndarray = 0.02, *, damping_form: str | None = None,
                 omega_truth_rad_s: np.ndarray | None = None, actuators=(), inputs=None
                 ) -> Path:
    """Write ``model`` (with its hub, if any) to ``path`` in format ``fmt`` (``"urdf"``,
    ``"mjcf"`` or ``"json"``).

    ``damping_ratio``, ``damping_form``, ``omega_truth_rad_s``, ``actuators`` (strain actuators)
    and ``inputs`` (MJCF only) as :func:`export_record` (which gives what the file records, for
    a command to print).
    """
    if fmt not in FORMATS:
        raise BeamInputError(f"format = {fmt!r}: must be one of {', '.join(FORMATS)}")
    kw = {"damping_form": damping_form, "omega_truth_rad_s": omega_truth_rad_s,
          "actuators": actuators}
    if fmt == "mjcf":
        return write_mjcf(model, path, damping_ratio, inputs=inputs, **kw)
    if inputs is not None and len(inputs):
        raise BeamInputError(f"inputs = {list(inputs)!r}: a {fmt} file carries no actuators "
                             "(only the MJCF does)")
    writer = write_urdf if fmt == "urdf" else write_json
    return writer(model, path, damping_ratio, **kw)
