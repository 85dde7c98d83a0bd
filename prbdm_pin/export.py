"""Write a PRBDM as URDF, MJCF (MuJoCo) or JSON; every file is written atomically.

Loading the files
-----------------
URDF (``prbdm export fit.json --format urdf --out beam.urdf``)
    Pinocchio: ``prbdm_pin.load_urdf("beam.urdf")`` (springs included), or plain
    ``pinocchio.buildModelFromUrdf("beam.urdf")`` (set ``model.gravity = pinocchio.Motion.Zero()``;
    the springs are not part of ``pinocchio.Model``: read them from the ``<gazebo>`` tags).
    ROS tooling: the file is a standard URDF (``world`` -> fixed ``clamp`` -> ``link_0`` ->
    revolute ``joint_1`` ... ``joint_n`` about y -> fixed ``tip_joint`` -> ``tip``), so
    ``check_urdf beam.urdf``, ``robot_state_publisher`` (``robot_description`` parameter) and RViz
    display it; Gazebo-classic reads ``<springStiffness>``/``<springReference>`` from the
    ``<gazebo reference="joint_j">`` tags (N m/rad, rad).
MJCF (``--format mjcf --out beam.xml``)
    MuJoCo: ``mujoco.MjModel.from_xml_path("beam.xml")``. A body chain ``link_1`` ... ``link_n``
    with hinge joints about y carrying ``stiffness`` (N m/rad), ``springref="0"`` and ``damping``
    (N m s/rad), each body's ``inertial`` (mass, centre of mass, ``fullinertia`` about the centre
    of mass), a ``tip`` site at the free end, and ``<option gravity="0 0 0">``. MuJoCo's joint
    damping is diagonal: the exported value is the diagonal of the modal damping matrix at the
    straight pose, so mode ratios are only approximately those requested (exactly for 1R).
    Apply a tip force through ``data.xfrc_applied`` on ``link_n`` (force at the body's centre of
    mass plus the moment (tip - com) x F).
JSON (``--format json --out model.json``)
    The model parameters (beam, link lengths, springs, link inertias, natural frequencies):
    ``prbdm_pin.export.read_model_json("model.json")`` rebuilds the model with ``build_model``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from . import __version__
from .damping import damping_ratios, modal_damping
from .errors import BeamInputError
from .geometry import atomic_write_text, beam_from_dict, beam_to_dict

__all__ = [
    "FORMATS",
    "mjcf_text",
    "model_dict",
    "write_urdf",
    "write_mjcf",
    "write_json",
    "export_model",
    "read_model_json",
]

FORMATS = ("urdf", "mjcf", "json")
JSON_FORMAT = "prbdm-model/1"


def _f(v: float) -> str:
    return repr(float(v))


def _vec(v: np.ndarray) -> str:
    return " ".join(_f(x) for x in v)


def mjcf_text(model, damping_ratio: float | np.ndarray = 0.02, timestep_s: float | None = None
              ) -> str:
    """The model as an MJCF string for MuJoCo.

    Parameters
    ----------
    model : PrbdmModel
    damping_ratio : float or ndarray (n,)
        Modal damping ratio(s); each joint's ``damping`` is the diagonal entry of the modal damping
        matrix at the straight pose (N m s/rad). 0 writes undamped joints.
    timestep_s : float, optional
        MuJoCo time step, s (default: a twentieth of the shortest natural period).
    """
    s = model.sections
    lengths = np.asarray(model.lengths_m, dtype=float)
    n = model.n_joints
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    M, K = model.mass_matrix(), model.stiffness_matrix()
    xi = damping_ratios(damping_ratio, n)
    c = np.zeros(n) if not np.any(xi > 0) else np.diag(modal_damping(M, K, xi))
    if timestep_s is None:
        timestep_s = 2.0 * np.pi / float(model.natural_frequencies()[-1]) / 20.0
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
        "       clamped to the world; hinge joints about y carry the torsional springs. -->",
        '  <compiler angle="radian" autolimits="true"/>',
        f'  <option gravity="0 0 0" timestep="{_f(timestep_s)}"/>',
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


def model_dict(model) -> dict[str, Any]:
    """JSON-ready parameters of ``model`` (SI units)."""
    s = model.sections
    return {
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
        "natural_frequencies_rad_s": [float(v) for v in model.natural_frequencies()],
    }


def write_urdf(model, path: str | os.PathLike) -> Path:
    """Write the model's URDF (springs in Gazebo tags) atomically."""
    return atomic_write_text(path, model.urdf)


def write_mjcf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02) -> Path:
    """Write :func:`mjcf_text` atomically."""
    return atomic_write_text(path, mjcf_text(model, damping_ratio))


def write_json(model, path: str | os.PathLike) -> Path:
    """Write :func:`model_dict` as JSON atomically."""
    return atomic_write_text(path, json.dumps(model_dict(model), indent=2) + "\n")


def export_model(model, path: str | os.PathLike, fmt: str,
                 damping_ratio: float | np.ndarray = 0.02) -> Path:
    """Write ``model`` to ``path`` in format ``fmt`` (``"urdf"``, ``"mjcf"`` or ``"json"``)."""
    if fmt == "urdf":
        return write_urdf(model, path)
    if fmt == "mjcf":
        return write_mjcf(model, path, damping_ratio)
    if fmt == "json":
        return write_json(model, path)
    raise BeamInputError(f"format = {fmt!r}: must be one of {', '.join(FORMATS)}")


def read_model_json(path: str | os.PathLike):
    """Rebuild the PrbdmModel from a file written by :func:`write_json` (needs its beam)."""
    from .model import build_model

    p = Path(path)
    try:
        d = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise BeamInputError(f"model file {str(p)!r}: cannot be read ({exc})") from None
    if not isinstance(d, dict) or d.get("format") != JSON_FORMAT:
        raise BeamInputError(f"model file {str(p)!r}: format must be {JSON_FORMAT!r}")
    if d.get("beam") is None:
        raise BeamInputError(f"model file {str(p)!r}: has no beam; load the URDF export instead")
    for key in ("lengths_m", "stiffness_Nm_per_rad"):
        if key not in d:
            raise BeamInputError(f"model file {str(p)!r}: missing {key!r}")
    lengths = np.asarray(d["lengths_m"], dtype=float)
    return build_model(beam_from_dict(d["beam"]), lengths, d["stiffness_Nm_per_rad"],
                       min_fraction=min(0.02, 0.5 * float(lengths.min()) / float(lengths.sum())))
