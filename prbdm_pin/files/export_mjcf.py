"""The MJCF (MuJoCo) text of a PRBDM.

The text holds the chain, a hub when the model has one, and the plant's inputs as MuJoCo
actuators.

Inputs (names as :func:`prbdm_pin.model.inputs.input_map`'s) become ``<actuator>`` entries
named by :func:`~prbdm_pin.files.export_plant.mujoco_name` (``strain[0]`` -> ``strain_0``), each a
``<motor>`` with unit gear and no control limit, so ``data.ctrl`` is the input itself:

- ``hub_torque`` (N m): on the hub joint;
- ``joint_torque[j]`` (N m): on beam joint ``joint_{j+1}``;
- ``strain[i]`` (N m, the patch moment): on a fixed tendon ``strain_i`` over the joints of the
  patch with the coefficients of :func:`~prbdm_pin.model.inputs.strain_map` (the virtual-work
  map: 1 inside, 1/2 on a joint an end sits on; or the actuator's fitted joint weights, any
  real numbers, over every joint); MuJoCo applies coef * force to each joint of a fixed tendon,
  which is the patch's map;
- ``tip_force_z``, ``tip_force_x`` (N): a site transmission at ``tip`` with ``refsite`` a site
  fixed at the world origin, so the force is along world z (x) at the tip: J^T F, a dead load.
"""

from __future__ import annotations

import math
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import BeamInputError
from ..truth.self_weight import check_gravity
from ..version import __version__
from .export_comment import number_text as _f
from .export_comment import vector_text as _vec
from .export_geometry import mjcf_assets, mjcf_link_geom, mjcf_tip_body, station_sites
from .export_plant import mujoco_name
from .export_record import export_record

__all__ = ["mjcf_text"]

_TIP_GEAR = {"tip_force_z": "0 0 1 0 0 0", "tip_force_x": "1 0 0 0 0 0"}
_AXIS = {"x": "1 0 0", "y": "0 1 0", "z": "0 0 1"}


def _gravity_text(g: np.ndarray) -> str:
    """``0 0 0`` for no gravity (as before gravity was recorded), else the exact doubles."""
    return "0 0 0" if not np.any(g) else _vec(g)


def _fastest_rate(model, k: np.ndarray, c: np.ndarray) -> float:
    """Largest |lambda| (1/s) of the damped linear chain at the straight pose.

    Stiffness-proportional damping overdamps the high modes: their fast real root ~ 2 xi_k
    omega_k can exceed omega_max many times (a spatial chain's torsion), and RK4's real-axis
    stability bound is h |lambda| < 2.79.
    """
    M = np.asarray(model.mass_matrix(), dtype=float)
    nv = M.shape[0]
    K, C = np.zeros((nv, nv)), np.zeros((nv, nv))
    K[nv - k.size:, nv - k.size:] = np.diag(k)  # the hub's coordinate, if any, comes first
    C[nv - k.size:, nv - k.size:] = np.diag(c)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((nv, nv)), np.eye(nv)], [-Minv @ K, -Minv @ C]])
    return float(np.abs(np.linalg.eigvals(A)).max())


def mjcf_text(model, damping_ratio: float | np.ndarray = 0.02, timestep_s: float | None = None,
              *, damping_form: str | None = None, omega_truth_rad_s: np.ndarray | None = None,
              actuators=(), inputs=None, gravity_m_s2=None,
              mesh_folder: str | None = None, sensor_stations_m=()) -> str:
    """Write the model as an MJCF string for MuJoCo.

    Parameters
    ----------
    model : PrbdmModel
        With a hub, the hub is a body turning on a hinge ``hub`` about ``hub.axis`` (no
        spring, no damping, inertia J_h about its axis) and the beam root sits on it at
        ``radius_m`` along x. A spatial chain's body ``link_j`` has one hinge per axis,
        ``joint_j_y``, ``joint_j_z``, ``joint_j_x`` (those of ``model.axes``, in that order, at the
        body's origin), each with its own spring.
    damping_ratio : float or ndarray (n,)
        Mode 1's damping ratio (the lowest flexible mode with a hub): every hinge's
        ``damping`` is beta K_ii (N m s/rad), the stiffness form (see :func:`export_record`);
        or each mode's, and the hinges get the diagonal damping fitted to them (``modal_fit``,
        the default for ratios that differ). n is the number of springs. 0 writes undamped
        joints.
    timestep_s : float, optional
        MuJoCo time step, s (default: a twentieth of the shortest natural period, of the
        clamped and the hub model, or 2 / |lambda|_max of the damped chain if shorter, which
        keeps RK4 stable where stiffness-proportional damping overdamps the high modes, as on
        a spatial chain's torsion; the integrator is RK4).
    damping_form, omega_truth_rad_s
        See :func:`export_record`; the record is written as a comment.
    actuators : sequence of StrainActuator
        The plant's strain actuators (``strain[i]`` is the i-th).
    inputs : sequence of str, optional
        The inputs written as MuJoCo actuators (module notes); default ``hub_torque`` with a
        hub, and ``strain[i]`` for every actuator. A spatial chain takes neither actuators nor
        inputs.
    gravity_m_s2 : array_like (3,), optional
        The gravity the model was fitted in, m/s^2, world (``FitResult.gravity_m_s2``):
        ``<option gravity>``; default none, ``0 0 0`` (a model fitted without gravity).
    mesh_folder : str, optional
        The links' OBJ folder relative to the MJCF file (:mod:`prbdm_pin.files.export_geometry`
        writes it): a mesh asset and geom per link, and the tip body ``tip_body`` with the
        sites ``tip``, ``tip_corner_left``, ``tip_corner_right``. Default none: no geometry,
        the ``tip`` site in ``link_n`` (the files as they were before geometry).
    sensor_stations_m : sequence of float
        Stations (m from the root) that get a site ``station_k`` on the link holding them
        (:func:`~prbdm_pin.files.export_geometry.station_sites`), where a MuJoCo sensor or load
        can be attached; default none.

    Returns
    -------
    str
        The MJCF text.
    """
    from ..model.chain_names import joint_names
    from ..model.inputs import strain_map

    gravity = np.zeros(3) if gravity_m_s2 is None else check_gravity(gravity_m_s2,
                                                                    planar=False)
    rec = export_record(model, "mjcf", damping_ratio, damping_form, omega_truth_rad_s,
                        actuators=actuators, inputs=inputs)
    s = model.sections
    lengths = np.asarray(model.lengths_m, dtype=float)
    n = model.n_joints
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    c = rec.joint_damping_Nms_per_rad
    hub = model.hub
    if timestep_s is None:
        w_max = float(rec.natural_frequencies_rad_s[-1])
        if rec.hub_frequencies_rad_s is not None:
            w_max = max(w_max, float(rec.hub_frequencies_rad_s[-1]))
        timestep_s = 2.0 * np.pi / w_max / 20.0
        # and inside RK4's stability region with margin (h |lambda| <= 2 < 2.79) when the
        # damping's fastest root is faster than omega_max (overdamped high modes)
        if np.any(c):
            timestep_s = min(timestep_s, 2.0 / _fastest_rate(model, k, c))
    if not (math.isfinite(timestep_s) and timestep_s > 0.0):
        raise BeamInputError(f"timestep = {timestep_s!r} s: must be finite and > 0")
    name = "prbdm" if model.beam is None else f"prbdm_{model.beam.name}"

    def inertial(i: int) -> str:
        com = s.com_m[i] - np.array([s.start_m[i], 0.0, 0.0])
        J = s.inertia_com_kg_m2[i]
        full = [J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2]]
        return (f'<inertial pos="{_vec(com)}" mass="{_f(s.mass_kg[i])}" '
                f'fullinertia="{_vec(full)}"/>')

    root = ["link 0 is", "       clamped to the world;"] if hub is None else [
        "link 0 is",
        f"       clamped to the hub, which turns on the hinge 'hub' about {hub.axis} (no "
        "spring, no",
        "       damping); the actuators carry the plant's inputs (see the record's inputs);"]
    hinges = ["       hinge joints about y carry the torsional springs and the"] \
        if not model.axes.spatial else [
        "       each link's body turns on hinges about "
        + ", ".join(model.axes.joint_order) + " in that order (joint_j_y, ...), at one",
        "       point; each hinge carries its own torsional spring and the"]
    sites = station_sites(model, sensor_stations_m)
    if mesh_folder is not None and model.beam is None:
        raise BeamInputError("model: read from a URDF, it carries no beam, so no geometry")
    lines = [
        f"<mujoco model={quoteattr(name)}>",
        f"  <!-- Pseudo-rigid-body dynamic model written by prbdm_pin {__version__}: {root[0]}",
        *root[1:],
        *hinges,
        "       stiffness-proportional damping beta K. -->" if rec.damping_form != "modal_fit"
        else "       diagonal joint damping fitted to per-mode ratios (modal_fit). -->",
        f"  <!--{rec.comment_text()}  -->",
        '  <compiler angle="radian" autolimits="true"/>',
        # RK4: at T_n/20 its step response is within 0.02 % of the peak of an accurate
        # integration (3R and 5R reference chains), the default Euler 0.1-0.6 % (1st order)
        f'  <option gravity="{_gravity_text(gravity)}" timestep="{_f(timestep_s)}" '
        'integrator="RK4"/>',
        *([] if mesh_folder is None else mjcf_assets(mesh_folder, n + 1)),
        "  <worldbody>",
    ]
    indent = "    "
    if any(u in _TIP_GEAR for u in rec.inputs):
        lines.append(f'{indent}<site name="world_ref" pos="0 0 0" size="0.005"/>')
    if hub is not None:
        # the hub's inertia as the Pinocchio hub model holds it: J_h about every axis, no mass
        J = _f(hub.inertia_kg_m2)
        lines += [
            f'{indent}<body name="hub_body" pos="0 0 0">',
            f'{indent}  <joint name="hub" type="hinge" axis="{_AXIS[hub.axis]}" pos="0 0 0" '
            'damping="0"/>',
            f'{indent}  <inertial pos="0 0 0" mass="0" diaginertia="{J} {J} {J}"/>',
        ]
        indent += "  "
    lines += [f'{indent}<body name="link_0" pos="{"0" if hub is None else _f(hub.radius_m)} 0 0">',
              f"{indent}  {inertial(0)}"]
    if mesh_folder is not None:
        lines.append(f"{indent}  {mjcf_link_geom(0)}")
    lines += [f"{indent}  {t}" for t in sites.get(0, ())]
    indent += "  "
    names = iter(joint_names(n, model.axes))
    springs = iter(range(k.size))
    for j in range(1, n + 1):
        lines.append(f'{indent}<body name="link_{j}" pos="{_f(lengths[j - 1])} 0 0">')
        # MuJoCo composes a body's joints in the order written: y, then z, then x, as the
        # Pinocchio chain's successive joints (massless links between them add nothing)
        for a in model.axes.joint_order:
            i = next(springs)
            lines.append(f'{indent}  <joint name="{next(names)}" type="hinge" axis="{_AXIS[a]}" '
                         f'pos="0 0 0" stiffness="{_f(k[i])}" springref="0" '
                         f'damping="{_f(c[i])}"/>')
        lines.append(f"{indent}  {inertial(j)}")
        if mesh_folder is not None:
            lines.append(f"{indent}  {mjcf_link_geom(j)}")
        lines += [f"{indent}  {t}" for t in sites.get(j, ())]
        indent += "  "
    if mesh_folder is None:
        lines.append(f'{indent}<site name="tip" pos="{_f(lengths[n])} 0 0" size="0.005"/>')
    else:
        lines += mjcf_tip_body(model, indent)
    for _ in range(n + 1 + (hub is not None)):
        indent = indent[:-2]
        lines.append(f"{indent}</body>")
    lines.append("  </worldbody>")
    spans = rec.actuators()
    tendons, motors = [], []
    for u in rec.inputs:
        label = f'name="{mujoco_name(u)}"'
        if u in _TIP_GEAR:
            target = f'site="tip" refsite="world_ref" gear="{_TIP_GEAR[u]}"'
        elif u == "hub_torque":
            target = 'joint="hub"'
        elif u.startswith("joint_torque["):
            target = f'joint="joint_{int(u[13:-1]) + 1}"'
        else:
            i = int(u[7:-1])
            coef = strain_map(lengths, spans[i], f"actuators[{i}]")
            # a patch inside one link moves no joint: a zero coefficient keeps the tendon valid
            on = np.flatnonzero(coef) if np.any(coef) else np.array([0])
            tendons.append(f"    <fixed {label}>")
            tendons += [f'      <joint joint="joint_{j + 1}" coef="{_f(coef[j])}"/>' for j in on]
            tendons.append("    </fixed>")
            target = f'tendon="{mujoco_name(u)}"'
        motors.append(f'    <motor {label} {target} ctrllimited="false"/>')
    if tendons:
        lines += ["  <tendon>", *tendons, "  </tendon>"]
    if motors:
        lines += ["  <actuator>", *motors, "  </actuator>"]
    lines += ["</mujoco>", ""]
    return "\n".join(lines)
