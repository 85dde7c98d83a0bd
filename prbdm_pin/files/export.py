"""Write a PRBDM as URDF, MJCF (MuJoCo) or JSON; every file is written atomically.

Every export records the exported model itself (:class:`ExportRecord`): its natural frequencies at
the straight pose, and, when the truth it was fitted to is known, its signed per-mode errors
100 (omega_model / omega_truth - 1) and the worst of them; and the damping it carries with the
modal ratios that damping gives. URDF and MJCF hold the record as an XML comment
(:func:`read_export_record` reads it back), JSON as fields.

The plant: a model with a hub (``build_model(..., hub=Hub(J_h, r))``) is exported with its hub
(MJCF body and hinge, URDF revolute joint, JSON fields), and strain actuators
(``actuators=(StrainActuator(x_a, x_b), ...)``) go with it: MJCF tendons and motors, the URDF's
record comment (URDF has no tendons), JSON fields. With a hub the record's frequencies and
per-mode errors stay the clamped model's (the model that was fitted, to a clamped truth) and
``hub_frequencies_rad_s`` adds the hub model's flexible frequencies (the rigid mode at 0 left
out); the damping is the hub model's: beta = 2 xi_1 / omega_1 with omega_1 its lowest flexible
frequency (:func:`prbdm_pin.simulation.hub_damping.plant_damping`'s stiffness form, what
``linearize(..., damping="stiffness")`` uses), on the beam joints only: the hub joint is
undamped.

Gravity: a PRBDM fitted without gravity has none, one fitted in gravity (``prbdm fit
--gravity``) has that gravity (``FitResult.gravity_m_s2``, passed as ``gravity_m_s2``). The MJCF
sets it as ``<option gravity>`` (``"0 0 0"`` without); URDF has no gravity element, so its comment
states the fit's gravity vector and that the consumer must set it: ``pinocchio.buildModelFromUrdf``
and MuJoCo's URDF import turn on -9.81 m/s^2 along z (``prbdm_pin.load_urdf`` sets zero).

Damping: a diagonal joint damping (MJCF ``damping``, URDF ``<dynamics damping>``) carries the
stiffness-proportional form C = beta K exactly (K is diagonal), beta = 2 xi_1 / omega_1 at the
straight pose, so mode 1 gets the asked ratio xi_1 and mode k gets xi_1 omega_k / omega_1; it is
the default (``damping_form="stiffness"``) of those two formats. The modal form (every mode xi)
is not diagonal and no joint damping carries it: asked for a URDF or MJCF, the stiffness form with
mode 1's ratio is written instead and the record's ``warnings`` say so, with the modal ratios that
result. ``prbdm_pin.simulate(..., damping="stiffness")`` simulates the damping these files carry.
Per-mode ratios that differ (a calibrated model's, ``prbdm calibrate``) go to URDF and MJCF as
``damping_form="modal_fit"`` (their default for such ratios): the diagonal joint damping c >= 0
fitted by least squares to the ratios (:mod:`prbdm_pin.simulation.modal_fit`); the record
holds the ratios it achieves (from the damped model's complex eigenvalues) and each mode's
error against the asked ratio (``damping_ratio_errors``), and warns about a mode off by more
than ``MODAL_FIT_WARN_PCT`` % of its ratio (:mod:`prbdm_pin.files.export_damping`);
``simulate``/``linearize(..., damping="modal_fit")`` run the same damping.

Spatial chains (``build_model(..., axes="xy" | "yz" | "xyz")``): node j is the revolute joints
``joint_j_y``, ``joint_j_z``, ``joint_j_x`` (those of ``axes``, in that order) at one point, each
with its own spring, and every spring gets the stiffness-proportional damping beta K_ii (beta
from the lowest mode of all the springs' coordinates); the record's frequencies, damping ratios
and joint damping have one entry per spring coordinate. The URDF joins a node's joints by
massless links ``link_j_y``, ``link_j_z`` (explicit zero inertial); the MJCF puts all of a node's
hinges in the body ``link_j`` (MuJoCo composes a body's joints in the order written); the model
JSON adds ``"axes"``. A spatial model has no hub, strain actuators or MJCF inputs (they are
defined on the planar chain) and the exports refuse them. MuJoCo does not compile the spatial
URDF as it is: a body with a joint needs mass and inertia >= mjMINVAL, its own or a jointless
child's, and the massless node links have neither (no URDF compiler option changes that without
giving them mass); use the MJCF, or parse the URDF into ``mujoco.MjSpec.from_string`` and call
``to_frame()`` on each node's later bodies (``link_j_z``, then ``link_j``) before
``spec.compile()``, which gives the MJCF's bodies.

Loading the files
-----------------
URDF (``prbdm export fit.json --format urdf --out beam.urdf``)
    Pinocchio: ``prbdm_pin.load_urdf("beam.urdf")`` (springs included, gravity zero, the hub
    too), or plain ``model = pinocchio.buildModelFromUrdf("beam.urdf")`` followed by
    ``model.gravity = pinocchio.Motion.Zero()``; the springs are not part of ``pinocchio.Model``
    (read them with ``prbdm_pin.model.urdf.read_springs``), the joint damping is ``model.damping``.
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
    With a hub (``--hub J:R``): ``world`` -> revolute ``hub`` about y (no spring, damping 0, a
    limit of 1e6 rad that never binds: a ``continuous`` joint would give Pinocchio a (cos, sin)
    coordinate) -> massless link ``hub_body`` with inertia J_h about every axis -> fixed
    ``clamp`` at x = R -> ``link_0`` ...; the hub is the first coordinate in every consumer
    (Pinocchio, pybullet, yourdfpy, MuJoCo), and ``load_urdf`` returns a hub model. URDF cannot
    carry tendons or actuators: the strain actuators are only recorded in the comment
    (``strain_actuators_m``); apply ``strain[i]``'s moment as joint torques
    ``prbdm_pin.model.inputs.strain_map(lengths, actuator) * M`` and the hub torque on ``hub``.
MJCF (``--format mjcf --out beam.xml``)
    MuJoCo: ``mujoco.MjModel.from_xml_path("beam.xml")``. A body chain ``link_1`` ... ``link_n``
    with hinge joints about y carrying ``stiffness`` (N m/rad), ``springref="0"`` and ``damping``
    (N m s/rad, the stiffness form above), each body's ``inertial`` (mass, centre of mass,
    ``fullinertia`` about the centre of mass), a ``tip`` site at the free end, and
    ``<option gravity="0 0 0" integrator="RK4">`` with a step of a twentieth of the shortest
    period. With a hub, ``link_0`` sits at x = R in body ``hub_body``, which turns on the hinge
    ``hub`` about y (no stiffness, no damping; mass 0, ``diaginertia`` J_h as the Pinocchio hub
    model holds it); ``qpos[0]`` is the hub angle. Inputs are ``<actuator>`` motors with unit
    gear and ``ctrllimited="false"``, so ``data.ctrl[i]`` is the input in the package's units
    (:mod:`prbdm_pin.files.export_mjcf`); the MuJoCo names replace ``[i]`` by ``_i``:
    ``hub_torque`` -> ``hub_torque`` (N m, hinge ``hub``), ``joint_torque[j]`` ->
    ``joint_torque_j`` (N m, hinge ``joint_{j+1}``), ``strain[i]`` -> ``strain_i`` (N m, a motor
    on the fixed tendon ``strain_i`` whose coefficients are the patch's map: 1 on a joint inside
    it, 1/2 on a joint an end sits on), ``tip_force_z``/``tip_force_x`` (N, a site
    transmission at ``tip`` with ``refsite="world_ref"``, a site at the world origin: the force
    is along world z/x, a dead load). Default inputs: ``hub_torque`` with a hub and
    ``strain[i]`` for every actuator; the record's ``inputs`` line lists them in actuator order.
    Without a tip force actuator push on the tip body, ``data.xfrc_applied[m.body("tip_body")
    .id, :3] = F``, at the tip at every RK4 stage (:mod:`~prbdm_pin.files.export_geometry`;
    without geometry: on ``link_n``, F plus (tip - com) x F, refreshed every step). For a
    time-varying input, set ``data.ctrl`` to its value mid-step: RK4 holds it over the step.
JSON (``--format json --out model.json``)
    The model parameters (beam, link lengths, springs, link inertias, natural frequencies), the
    plant (``hub``: null or inertia_kg_m2 and radius_m; ``actuators``: x_start_m and x_end_m
    each) and the record's fields: ``prbdm_pin.files.export.read_model_json("model.json")`` rebuilds
    the model (on its hub) with ``build_model``; ``read_plant_json`` also returns the
    actuators.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import BeamInputError
from ..io.atomic import atomic_write_text
from ..io.paths import check_out_file, writable_dir
from ..io.provenance import provenance
from ..model.checks import check_model
from ..truth.self_weight import check_gravity
from .export_comment import gravity_comment
from .export_geometry import (
    has_geometry,
    link_meshes,
    mesh_folder,
    urdf_geometry,
    write_meshes,
)
from .export_mjcf import mjcf_text
from .export_plant import mujoco_name
from .export_record import (
    EXPORT_DAMPING_FORMS,
    FORMATS,
    MODAL_FIT_WARN_PCT,
    WORST_MODE_WARN_PCT,
    ExportRecord,
    export_record,
    read_export_record,
)
from .model_json import JSON_FORMAT, model_dict, read_model_json, read_plant_json

__all__ = [
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
    "WORST_MODE_WARN_PCT",
    "MODAL_FIT_WARN_PCT",
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


# the URDF header's gravity sentence (urdf_templates/robot.urdf.tmpl) and its form for a model
# fitted in gravity
_NO_GRAVITY = ("No gravity: the model is defined without\n     it, but URDF carries none, so "
               "zero it in the consumer")
_FITTED_GRAVITY = ("Gravity: the model was fitted in the\n     gravity_m_s2 stated below; URDF "
                   "carries none, so set it\n     in the consumer")


def urdf_text(model, damping_ratio: float | np.ndarray = 0.02, *,
              damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
              actuators=(), gravity_m_s2=None, mesh_folder: str | None = None) -> str:
    """Return the model's URDF with ``<dynamics damping>`` (stiffness form) and record comment.

    Parameters as :func:`export_record`; a hub model gets the revolute joint ``hub`` (see the
    module notes). URDF has no tendons: ``actuators`` are recorded in the comment only, and no
    gravity: the comment states ``gravity_m_s2`` (m/s^2, world; the gravity the model was
    fitted in, default none) and that the consumer must set it
    (:func:`~prbdm_pin.files.export_comment.gravity_comment`). ``mesh_folder`` (relative to
    the URDF) gives each link its ``<visual>`` and ``<collision>`` mesh
    (:mod:`~prbdm_pin.files.export_geometry`). With ``damping_ratio=0``, no actuators, no
    comment and no mesh folder this is :attr:`PrbdmModel.urdf`.
    """
    from ..model.urdf import render_urdf

    g = None if gravity_m_s2 is None else check_gravity(gravity_m_s2, planar=False)
    rec = export_record(model, "urdf", damping_ratio, damping_form, omega_truth_rad_s,
                        actuators=actuators)
    name = "prbdm" if model.beam is None else f"prbdm_{model.beam.name}"
    text = render_urdf(model.sections, model.lengths_m, model.stiffness_Nm_per_rad, name,
                       damping_Nms_per_rad=rec.joint_damping_Nms_per_rad,
                       comment=rec.comment_text() + gravity_comment(g), hub=model.hub,
                       axes=model.axes,
                       link_geometry=None if mesh_folder is None else
                       [urdf_geometry(mesh_folder, i) for i in range(model.n_joints + 1)])
    if g is None or not np.any(g):
        return text
    # the header's convention sentence, for a model fitted in gravity
    if _NO_GRAVITY not in text:
        raise AssertionError("urdf_templates/robot.urdf.tmpl: the gravity sentence changed")
    return text.replace(_NO_GRAVITY, _FITTED_GRAVITY)


def write_urdf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               mesh_folder: str | None = None, **kw) -> Path:
    """Write :func:`urdf_text` atomically (keywords as it takes them)."""
    return atomic_write_text(path, urdf_text(model, damping_ratio, mesh_folder=mesh_folder, **kw))


def write_mjcf(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               mesh_folder: str | None = None, **kw) -> Path:
    """Write :func:`mjcf_text` atomically (keywords as it takes them)."""
    return atomic_write_text(path, mjcf_text(model, damping_ratio, mesh_folder=mesh_folder, **kw))


def write_json(model, path: str | os.PathLike, damping_ratio: float | np.ndarray = 0.02, *,
               damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
               actuators=(), gravity_m_s2=None, seed: int | None = None) -> Path:
    """Write :func:`model_dict` as JSON atomically (with ``gravity_m_s2`` when given).

    The file also records the package's ``versions`` and the ``seed`` of the fit the model came
    from (None when not known).
    """
    d = model_dict(model, damping_ratio, damping_form=damping_form,
                   omega_truth_rad_s=omega_truth_rad_s, actuators=actuators)
    d.update(provenance(seed))
    if gravity_m_s2 is not None:
        d["gravity_m_s2"] = check_gravity(gravity_m_s2, planar=False).tolist()
    return atomic_write_text(path, json.dumps(d, indent=2) + "\n")


def export_model(model, path: str | os.PathLike, fmt: str,
                 damping_ratio: float | np.ndarray = 0.02, *, damping_form: str | None = None,
                 omega_truth_rad_s: np.ndarray | None = None, actuators=(), inputs=None,
                 gravity_m_s2=None, geometry: bool = True, sensor_stations_m=(),
                 seed: int | None = None) -> Path:
    """Write ``model`` (with its hub, if any) to ``path`` in format ``fmt``.

    Parameters
    ----------
    model : PrbdmModel
        The model to export.
    path : str or path-like
        The file to write (atomically).
    fmt : {"urdf", "mjcf", "json"}
        The file format.
    damping_ratio : float or ndarray (n,)
        Mode 1's damping ratio (stiffness form) or each mode's (modal form), dimensionless; 0
        writes no damping.
    damping_form, omega_truth_rad_s, actuators, inputs
        As :func:`~prbdm_pin.files.export_record.export_record` (which gives what the file records,
        for a command to print): the damping form, the truth frequencies (rad/s), the strain
        actuators and the inputs (MJCF only).
    gravity_m_s2 : array_like (3,), optional
        The gravity the model was fitted in, m/s^2, world (``FitResult.gravity_m_s2``; default
        none): the MJCF's ``<option gravity>``, stated in the URDF's comment (URDF has no
        gravity element); a model JSON records it as ``gravity_m_s2``.
    seed : int, optional
        The seed of the fit the model came from, recorded in a model JSON beside the package's
        versions (every JSON the package writes says what made it).
    geometry : bool
        URDF and MJCF: write each link's solid as ``NAME_meshes/link_j.obj`` beside ``path``
        and use it as visual and collision geometry, and (MJCF) the tip body with its sites
        (:mod:`~prbdm_pin.files.export_geometry`); default True. False, or a model read from a
        URDF (no planform), writes the bare file as before geometry.
    sensor_stations_m : sequence of float
        MJCF: a site ``station_k`` at each station (m from the root), default none.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputTypeError
        ``model`` not a PrbdmModel, ``path`` not a str or path-like.
    BeamInputError
        A ``path`` that cannot be written as a file (an existing folder, a path under a file,
        in ``/proc``, ``/sys`` or ``/dev``, an unwritable folder), refused before anything is
        written; a bad format, damping or actuator; a mesh folder that cannot be written
        (named ``mesh folder``), refused before anything is written.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> import trimesh
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])  # m, N m/rad
    >>> path = pp.export_model(model, Path(tempfile.mkdtemp()) / "chain.urdf", "urdf")
    >>> sorted(p.name for p in (path.parent / "chain_meshes").iterdir())  # the links' solids
    ['link_0.obj', 'link_1.obj', 'link_2.obj']
    >>> again = pp.load_urdf(path)  # read back: the same springs and frequencies
    >>> again.natural_frequencies().round(1), model.natural_frequencies().round(1)  # rad/s
    (array([ 59. , 320.9]), array([ 59. , 320.9]))
    >>> obj = trimesh.load(path.parent / "chain_meshes" / "link_1.obj")
    >>> # link 1's mesh: its volume times the density is the link's mass, kg
    >>> round(float(obj.volume) * 7850.0, 4), round(float(model.sections.mass_kg[1]), 4)
    (1.9625, 1.9625)
    """
    check_model(model)
    if getattr(model, "bus", None) is not None:  # no file format carries a free bus yet
        raise BeamInputError("model: on a free bus, which no export format carries; export "
                             "model.member (the clamped member)")
    check_out_file("path", path)
    if fmt not in FORMATS:
        raise BeamInputError(f"format = {fmt!r}: must be one of {', '.join(FORMATS)}")
    g = None if gravity_m_s2 is None else check_gravity(gravity_m_s2, planar=False)
    kw = {"damping_form": damping_form, "omega_truth_rad_s": omega_truth_rad_s,
          "actuators": actuators, "gravity_m_s2": g}
    for what, given in (("inputs", () if inputs is None else inputs),
                        ("sensor_stations_m", sensor_stations_m)):
        if len(given) and fmt != "mjcf":  # MuJoCo actuators and sites
            raise BeamInputError(f"{what} = {list(given)!r}: a {fmt} file carries no "
                                 "actuators or sites (only the MJCF does)")
    if fmt == "json":
        return write_json(model, path, damping_ratio, seed=seed, **kw)
    if fmt == "mjcf":
        kw |= {"inputs": inputs, "sensor_stations_m": sensor_stations_m}
    text_of = mjcf_text if fmt == "mjcf" else urdf_text
    if not geometry or not has_geometry(model):  # from a URDF, or a section table: no shape
        return atomic_write_text(path, text_of(model, damping_ratio, **kw))
    folder = writable_dir(mesh_folder(path), "mesh folder")
    link_meshes(model)  # a model that cannot be meshed is refused before any file is written
    text = text_of(model, damping_ratio, mesh_folder=folder.name, **kw)
    write_meshes(model, path)  # the file that names the meshes comes last
    return atomic_write_text(path, text)
