"""``prbdm export``: write a PRBDM as URDF, MJCF (MuJoCo) or JSON."""

from __future__ import annotations

import argparse
import sys

from . import add_common
from .fit_actuators import add_fit_actuators_option, check_fit_actuators, fit_actuators
from .plant_options import (
    actuators_on_beam,
    actuators_option,
    add_plant_options,
    hub_option,
    names_option,
    with_hub,
)

EXAMPLES = """\
examples:
  prbdm export runs/ref/fit.json \\
      --format urdf --out ref.urdf
  prbdm export runs/ref/fit.json \\
      --format mjcf --damping 0.02 --out ref.xml
  prbdm export ref.urdf --format mjcf --out ref.xml
  prbdm export runs/ref/fit.json --format mjcf --hub 0.5:0.05 \\
      --actuator 0.05:0.4 --out ref_plant.xml
  prbdm export runs/ref/fit.json --format mjcf --actuator 0.2:0.3 --fit-actuators \\
      --out ref_patch.xml

Plant: --hub INERTIA:RADIUS puts the beam on a rotating hub (the MJCF hinge and the URDF
revolute joint `hub`, no spring, no damping); --actuator XA:XB adds a strain actuator
(repeatable; strain[i] is the i-th). The MJCF drives --inputs (default hub_torque with a hub,
and strain[i] for every actuator) as MuJoCo actuators named hub_torque, joint_torque_J,
strain_I, tip_force_z, tip_force_x (data.ctrl is the input, N m or N). URDF has no tendons: it
records the actuators in its comment; JSON records hub and actuators as fields. A model JSON
or URDF written with them carries them into the next export unless the options replace them.
A strain tendon's coefficients are the virtual-work map (1 on the joints inside the patch, 1/2
under an end) or, with --fit-actuators, joint weights fitted to the modal gains of the truth the
fit.json was made against (from the truth cache); the file records them.

Damping: URDF <dynamics damping> and MJCF joint damping are diagonal, so they carry the
stiffness-proportional form C = beta K (default): mode 1 gets ZETA, mode k ZETA omega_k/omega_1.
`--damping-form modal` (every mode ZETA) is only recorded in JSON; asked for a URDF or MJCF, the
stiffness form is written instead, with a warning giving the modal ratios it produces.
`prbdm simulate --damping-form stiffness` simulates what the file carries.
A calibrated model JSON (prbdm calibrate: one ratio per mode), or a URDF exported from one,
exports with its ratios unless --damping is given: JSON keeps them (modal form); URDF and MJCF
get `--damping-form modal_fit`, the diagonal joint damping c >= 0 fitted by least squares to
them, and record the ratios it achieves (from the damped model's eigenvalues) and each mode's
error; a mode off by more than 10 % of its ratio is warned about. `prbdm simulate/linearize
--damping-form modal_fit` runs the same damping. With --damping-form stiffness such a model's
mode-1 ratio is used.

Every file records (XML comment; JSON fields) the exported model's natural frequencies at the
straight pose and, when the truth is known (a fit.json, or an export of one), its signed per-mode
errors 100 (omega_model/omega_truth - 1); a worst mode off by more than 1 % is warned about.

Gravity: a model fitted in gravity (prbdm fit --gravity) carries it on: the MJCF's
<option gravity>, the URDF's comment (URDF has no gravity element: set it in the consumer), the
model JSON's gravity_m_s2; any other model has none (MJCF gravity 0 0 0).

Geometry: a URDF or MJCF export also writes each link's solid (the planform slice extruded to
its thickness) as NAME_meshes/link_J.obj beside it, used as URDF <visual>/<collision> and MJCF
mesh geoms (beam links never collide with each other), and the MJCF gets a tip body tip_body
(1e-12 of the member's mass) with the sites tip, tip_corner_left, tip_corner_right: apply a tip
load with data.xfrc_applied[tip_body id, :3]; --sites X,... adds sites station_k at stations
(m from the root) for MuJoCo sensors. --no-geometry writes the bare file as before.
A model read from a URDF has no planform and exports without geometry.

Load them with prbdm_pin.load_urdf (URDF, springs in the gazebo tags, gravity zero),
pinocchio.buildModelFromUrdf (then set model.gravity = pinocchio.Motion.Zero()),
pybullet.loadURDF(..., useFixedBase=True, flags=pybullet.URDF_USE_INERTIA_FROM_FILE),
mujoco.MjModel.from_xml_path (MJCF) or prbdm_pin.files.export.read_model_json (JSON).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``export`` subparser."""
    from ..options.choices import EXPORT_DAMPING_FORMS, FORMATS

    p = subparsers.add_parser(
        "export",
        help="write a PRBDM as URDF, MJCF or JSON",
        description="Export a fitted PRBDM (fit.json with its beam, model JSON or URDF).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json, model JSON or URDF")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--format", choices=FORMATS, required=True)
    p.add_argument("--damping", type=float, default=None, metavar="ZETA",
                   help="damping ratio of mode 1 (stiffness form) or of every mode (modal, "
                        "modal_fit); 0: none (default 0.02, or the per-mode ratios a "
                        "calibrated model JSON records)")
    p.add_argument("--damping-form", choices=EXPORT_DAMPING_FORMS, default=None,
                   help="stiffness (C = beta K; default for urdf and mjcf), modal (default "
                        "for json; urdf/mjcf write the stiffness form instead and warn) or "
                        "modal_fit (the diagonal joint damping fitted to the per-mode ratios; "
                        "the urdf/mjcf default for a calibrated model JSON)")
    add_plant_options(p)
    add_fit_actuators_option(p, cache_dir=True)
    p.add_argument("--inputs", default=None, metavar="NAMES",
                   help="comma-separated inputs the MJCF drives as MuJoCo actuators: "
                        "hub_torque, joint_torque[j], strain[i], tip_force_z, tip_force_x "
                        "(default hub_torque with a hub, and every strain[i])")
    p.add_argument("--out", required=True, metavar="FILE", help="output file")
    p.add_argument("--sites", default=None, metavar="X,...",
                   help="MJCF: a site station_k at each station X (m from the root) on the link "
                        "holding it, for MuJoCo sensors and loads")
    p.add_argument("--no-geometry", dest="geometry", action="store_false",
                   help="URDF/MJCF: no link meshes (NAME_meshes/ beside --out) and no MJCF tip "
                        "body: the bare file")
    add_common(p)
    p.set_defaults(func=run)
    return p


def check_options(args: argparse.Namespace) -> dict:
    """Refuse bad ``prbdm export`` options before the model is read.

    Returns the parsed plant options (hub, actuators, inputs).
    """
    import os

    from ..errors import BeamInputError
    from ..io.paths import writable_file
    from .checks import in_range

    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="the damping_ratio of mode 1 (stiffness form) or of every mode (modal); "
                 "0: none")
    opts = {"hub": hub_option(args.hub, args.hub_axis),
            "actuators": actuators_option(args.actuator),
            "inputs": None if args.inputs is None else names_option(args.inputs, "--inputs")}
    if opts["inputs"] is not None and args.format != "mjcf":
        raise BeamInputError(f"--inputs = {args.inputs!r}: only the MJCF carries actuators; "
                             f"drop it for --format {args.format}")
    opts["sites"] = ()
    if args.sites is not None:
        if args.format != "mjcf":
            raise BeamInputError(f"--sites = {args.sites!r}: only the MJCF carries sites; drop "
                                 f"it for --format {args.format}")
        try:
            opts["sites"] = tuple(float(v) for v in args.sites.split(","))
        except ValueError:
            raise BeamInputError(f"--sites = {args.sites!r}: must be stations in m separated "
                                 "by commas (0.2,0.5)") from None
    check_fit_actuators(args, len(opts["actuators"]) or -1)
    out = writable_file(args.out, "--out")
    if args.format != "json" and args.geometry:
        from ..files.export_geometry import mesh_folder
        from ..io.paths import writable_dir

        writable_dir(mesh_folder(out), "mesh folder of --out")
    if os.path.exists(args.model) and out.exists() and os.path.samefile(args.model, out):
        raise BeamInputError(f"--out = {args.out!r}: is the MODEL file itself; give another "
                             "file name")
    return opts


def damping_option(args: argparse.Namespace, source, hub: bool):
    """Return the damping ratio(s) to export with: ``--damping``, or the model file's.

    A calibrated model JSON's per-mode ratios (``ModelFile.modal_damping_ratio``) when
    ``--damping`` is not given and no hub is added (a hub changes the modes): all of them for
    the modal and fitted forms, mode 1's for the stiffness form; else ``--damping`` (0.02).
    """
    recorded = getattr(source, "modal_damping_ratio", None)
    if args.damping is not None or recorded is None or hub:
        return 0.02 if args.damping is None else args.damping
    return float(recorded[0]) if args.damping_form == "stiffness" else recorded


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm export``."""
    from ..files.export import export_model, export_record
    from ..files.model_source import load_model

    opts = check_options(args)
    source = load_model(args.model, args.beam)
    model, fitted = source.model, source.fit
    omega_truth = source.omega_truth_rad_s
    if opts["hub"] is not None:
        model = with_hub(model, opts["hub"])
    actuators = opts["actuators"]
    if args.actuator:
        actuators_on_beam(model, actuators, args.actuator, args.fit_actuators)
    else:
        actuators = source.actuators
    actuators = fit_actuators(args, model, fitted, actuators)
    plant = {"actuators": actuators}
    sites = {"sensor_stations_m": opts["sites"]} if opts["sites"] else {}
    if args.format == "mjcf":
        plant["inputs"] = opts["inputs"]
    ratio = damping_option(args, source, opts["hub"] is not None)
    rec = export_record(model, args.format, ratio, args.damping_form, omega_truth, **plant)
    # a model fitted in gravity carries it on (MJCF option, URDF comment, JSON field)
    path = export_model(model, args.out, args.format, damping_ratio=ratio,
                        damping_form=args.damping_form, omega_truth_rad_s=omega_truth,
                        gravity_m_s2=source.gravity_m_s2, geometry=args.geometry, **sites,
                        seed=getattr(fitted, "seed", None),
                        **plant)
    if not args.quiet:
        for note in rec.warnings:
            print(f"export warning: {note}", file=sys.stderr)
        for line in rec.summary_lines():
            print(line)
        hub = "" if model.hub is None else ", on a hub"
        fit = " (joint weights fitted to the truth)" if args.fit_actuators else ""
        acts = f", {len(actuators)} strain actuators{fit}" if len(actuators) else ""
        inputs = f", inputs {', '.join(rec.inputs)}" if rec.inputs else ""
        geom = ""
        if args.format != "json" and args.geometry and model.beam is not None:
            from ..files.export_geometry import mesh_folder

            geom = f", link meshes in {mesh_folder(path)}"
        print(f"wrote {path} ({args.format}, {model.n_joints} joints{hub}{acts}{inputs}{geom})",
              file=sys.stderr)
    return 0
