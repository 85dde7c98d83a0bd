"""``prbdm simulate``: time response of a PRBDM (from a fit.json or an exported URDF)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import BeamInputError
from ..io.provenance import provenance
from ..plant.truth_comparison import TRUTH_MODELS
from . import add_common
from .fit_actuators import add_fit_actuators_option, fit_actuators
from .plant_options import add_plant_options, add_span_option
from .simulate_plant import check_plant_options, plant_comparison, plant_outputs
from .support_options import (
    add_support_options,
    base_motion_of,
    check_support_options,
    supported_model,
    world_tip_columns,
)

if TYPE_CHECKING:
    import numpy as np

EXAMPLES = """\
examples:
  prbdm simulate runs/ref/fit.json \\
      --duration 1 --tip-force 0,0,-2500 --out runs/ref/sim
  prbdm simulate beam.urdf --duration 0.5 --tip-force 0,0,-100 --damping 0.05 --out sim/
  prbdm simulate runs/ref/fit.json \\
      --duration 1 --tip-force 0,0,-10 --compare-truth --out runs/ref/sim
  prbdm simulate runs/ref/fit.json --duration 0.1 --compare-truth --truth-model beam \\
      --out runs/ref/sim

  prbdm simulate runs/ref/fit.json --duration 2 --hub 5:0.1 --actuator 0:0.3 \
      --input hub_torque=pulse:0.5:0.4 --input "strain[0]=sine:2:3" \
      --outputs hub_angle,tip_z --out runs/ref/slew
  prbdm simulate runs/ref/fit.json --duration 1 --hub 5:0.1 --actuator 0:0.3 \
      --input hub_torque=1 --compare-truth --out runs/ref/slew

Writes OUT/trajectory.csv (t, joint angles, joint rates, tip position; with a hub the hub angle
and rate first; then each input as u:NAME and each output as y:NAME in their units; with
--base-motion the joint angles, tip and outputs relative to the moving base, in its frame, and
the world tip last as tip_world_x_m, tip_world_y_m, tip_world_z_m) and
OUT/response.png. Plant inputs (--input NAME=SIGNAL, repeatable): hub_torque (N m, needs
--hub), joint_torque[j] (N m), strain[i] (N m, the i-th --actuator), tip_force_z, tip_force_x,
tip_force_y (N), tip_moment_x, tip_moment_y, tip_moment_z (N m, about world x, y, z at the
tip), corner_force_z_left, corner_force_z_right (N, world z at the tip corners; dead loads),
tip_moment_follower_x, _y, _z (N m, about the tip link's own axes), distributed_force_x, _y, _z
(N/m, world, uniform over the beam; [i] over the i-th --distributed-span), base_accel_x, _y, _z
(m/s^2, the base's acceleration: the motion is then relative to the base); SIGNAL is A (a step
at t = 0), step:A:T0, pulse:A:T1 (A until T1 s), sine:A:F (F in Hz) or FILE.csv (rows of time s
and value, a header allowed; linear between samples, held outside them; times increasing).
Outputs (--outputs): tip_z, tip_z_rate, tip_x, tip_y, tip_twist, corner_z_left, corner_z_right,
q[j], q_rate[j], spring_torque[j], hub_angle, hub_rate; at a station X m from the root (Y m
across): slope@X, twist@X (rad), point_x@X:Y, point_y@X:Y, point_z@X:Y (m, displacement),
strain@X (microstrain, positive when the bending lifts the tip); root_force_x|y|z (N),
root_moment_x|y|z (N m): the support's wrench on the member about the root, base frame.
--compare-truth adds OUT/truth_comparison.json and OUT/truth_comparison.png: the tip response to
a unit step tip force over the first second and the tip FRF over [0, 1.2 omega_n] (n = joints)
of the model linearised at the straight pose, against the finite-element truth's modal
superposition at the same modal damping ratio. The truth is the one a fit.json was fitted to
(its model, mode selection and mesh level, found in the cache `prbdm fit` filled), else the
Kirchhoff plate (every plate mode up to the n-th selected bending mode, exact finite-element modal
masses); --truth-model beam asks for the 1D Euler-Bernoulli beam (milliseconds). With --hub,
--actuator or --input, --compare-truth compares the plant instead (as `prbdm linearize
--compare-truth`):
the model linearised at the straight pose with the --input names as inputs and the --outputs,
against the truth plant of the same hub and actuators, per input/output pair (FRF, resonance
peaks, step) and per mode: OUT/comparison.json and OUT/comparison.png.
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``simulate`` subparser."""
    p = subparsers.add_parser(
        "simulate",
        help="simulate a PRBDM's response to a tip force or plant inputs (trajectory CSV, "
             "plot)",
        description="Integrate the PRBDM's equations of motion through Pinocchio with its "
        "joint springs, modal damping, a step tip force and plant inputs (hub torque, joint "
        "torques, strain actuators) on a clamped root or a rotating hub.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json, model JSON or URDF")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--duration", type=float, required=True, metavar="S",
                   help="simulated time, s")
    p.add_argument("--tip-force", default="0,0,0", metavar="FX,FY,FZ",
                   help="step tip force in world axes, N (default 0,0,0)")
    p.add_argument("--gravity", default=None, metavar="GX,GY,GZ",
                   help="gravity, m/s^2, world (default: the gravity the model was fitted in, "
                        "none for most models); from the straight pose at rest the member "
                        "falls into its sag")
    p.add_argument("--initial-angle", type=float, default=0.0, metavar="RAD",
                   help="start with every joint at this angle, rad (default 0)")
    p.add_argument("--damping", type=float, default=None, metavar="ZETA",
                   help="damping ratio: of every mode (modal, modal_fit), of mode 1 (stiffness), "
                        "per-joint factor (eq5c) (default 0.02, or the per-mode ratios a "
                        "calibrated model JSON records)")
    p.add_argument("--damping-form", choices=("modal", "eq5c", "stiffness", "modal_fit"),
                   default="modal",
                   help="modal damping (default: every mode gets ZETA), the paper's Eq. 5c, "
                        "stiffness-proportional C = beta K (mode 1 of the straight pose gets "
                        "ZETA, mode k ZETA omega_k/omega_1: what MJCF/URDF exports carry, so a "
                        "run matches MuJoCo's), or modal_fit (the diagonal joint damping fitted "
                        "at the straight pose to the per-mode ratios: what MJCF/URDF exports of "
                        "a calibrated model carry). Modal and eq5c are computed at the initial "
                        "pose")
    p.add_argument("--method", default=None,
                   help="auto (default: picked per problem by the stated rule of "
                        "prbdm_pin.simulation.default_rule, compiled or exponential; the one "
                        "used is printed and recorded in simulation.json), exponential "
                        "(exact linear modes, step T1/10), gauss (symplectic; long undamped "
                        "runs, violent starts), trapezoidal, compiled (scipy's DOP853 "
                        "compiled with the chain's dynamics: constant loads only, no "
                        "--input), or a solve_ivp method: DOP853, Radau, BDF ...")
    p.add_argument("--dt", type=float, default=None, metavar="S",
                   help="trapezoidal step, s (default: lowest period / 100)")
    p.add_argument("--output-dt", type=float, default=None, metavar="S",
                   help="sample interval of the CSV, s (default: duration / 2000)")
    p.add_argument("--compare-truth", action="store_true",
                   help="also compare step response and FRF with the truth (needs the beam: "
                        "a fit.json or a model JSON)")
    p.add_argument("--truth-model", default=None, choices=TRUTH_MODELS,
                   help="truth of --compare-truth: plate (finite elements, cached) or beam (1D "
                        "Euler-Bernoulli, milliseconds); default: the truth a fit.json was "
                        "fitted to (its model, mode selection and mesh level), else plate")
    p.add_argument("--cache-dir", default=None, metavar="DIR",
                   help="truth cache folder, shared with `prbdm fit` (default $PRBDM_CACHE or "
                        "~/.cache/prbdm_pin)")
    add_plant_options(p)
    add_span_option(p)
    add_fit_actuators_option(p)
    p.add_argument("--input", action="append", default=[], metavar="NAME=SIGNAL",
                   help="a plant input and its signal (repeat for more): A, step:A:T0, "
                        "pulse:A:T1, sine:A:F (Hz) or FILE.csv (time s, value; linear "
                        "between samples); e.g. hub_torque=pulse:0.5:0.4")
    add_support_options(p)
    p.add_argument("--spin", type=float, default=None, metavar="RAD_S",
                   help="start the --hub spinning at this rate, rad/s, about --hub-axis (the "
                        "hub free: without a hub_torque it keeps spinning)")
    p.add_argument("--outputs", default=None, metavar="NAMES",
                   help="plant outputs to record, comma-separated (default tip_z, and "
                        "hub_angle with a hub)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_common(p)
    p.set_defaults(func=run)
    return p


def parse_force(text: str) -> np.ndarray:
    """``"FX,FY,FZ"`` -> array (3,) in N; BeamInputError otherwise."""
    import numpy as np

    parts = text.split(",")
    try:
        f = np.array([float(v) for v in parts])
    except ValueError:
        f = np.array([])
    if f.size != 3 or not np.all(np.isfinite(f)):
        raise BeamInputError(f"--tip-force = {text!r}: must be three numbers FX,FY,FZ (N)")
    return f


SIMULATE_FILES = ("trajectory.csv", "simulation.json", "response.png", "truth_comparison.png",
                  "truth_comparison.json", "comparison.png", "comparison.json")


# the CSV's default sampling: duration / DEFAULT_SAMPLES
DEFAULT_SAMPLES = 2000


def check_options(args: argparse.Namespace) -> np.ndarray:
    """Refuse bad ``prbdm simulate`` options before the model is read or ``--out`` created.

    Returns the tip force (N).
    """
    import math

    from ..io.paths import writable_dir
    from ..options.limits import check_cap
    from ..simulation import FIXED_STEP_METHODS, IVP_METHODS
    from .checks import in_range, xyz_option

    force = parse_force(args.tip_force)
    args.gravity_m_s2 = None if args.gravity is None else xyz_option(args.gravity, "--gravity",
                                                                     "m/s^2")
    if args.compare_truth and args.gravity_m_s2 is not None and any(args.gravity_m_s2):
        raise BeamInputError("--compare-truth: compares the unloaded plant; run it without "
                             "--gravity")
    in_range("--duration", args.duration, 0.0, lo_open=True, unit="s")
    in_range("--initial-angle", args.initial_angle, -math.pi, math.pi, unit="rad")
    # the integrators and the truth comparison take underdamped modes (over-damped runs: an
    # equivalent viscous model is out of the PRBDM's scope)
    args.damping_given = args.damping
    args.damping = 0.02 if args.damping is None else args.damping
    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="a damping ratio of an underdamped response" if not args.compare_truth else
             "--compare-truth needs an underdamped step response")
    methods = FIXED_STEP_METHODS + IVP_METHODS
    if args.method is None:  # the rule's pick (it leaves the exponential one off a spin)
        args.method = "auto"
    if args.method not in methods:
        raise BeamInputError(f"--method = {args.method!r}: must be one of {', '.join(methods)}")
    for name, dt in (("--dt", args.dt), ("--output-dt", args.output_dt)):
        in_range(name, dt, 0.0, args.duration, lo_open=True, unit="s",
                 why=f"a step within --duration {args.duration:g} s")
    if args.output_dt is not None:
        ratio = args.duration / args.output_dt  # inf for a subnormal step: over any cap
        samples = math.floor(ratio + 1e-9) + 1 if math.isfinite(ratio) else math.inf
        check_cap(f"output samples (--duration {args.duration:g} / --output-dt "
                  f"{args.output_dt:g} + 1)", samples, "max_output_samples")
    check_support_options(args)
    writable_dir(args.out, "--out")
    if args.compare_truth:
        from .fit_checks import check_cache_dir

        check_cache_dir(args)
    return force


def simulation_options(args, output_dt_s: float, damping_ratio=None):
    """Return the SimulationOptions of a ``prbdm simulate`` command line.

    ``output_dt_s`` is the sample interval, s: ``--output-dt`` or its default;
    ``damping_ratio`` the ratios to run with (default ``--damping``).
    """
    from ..options.objects import SimulationOptions

    zeta = args.damping if damping_ratio is None else damping_ratio
    return SimulationOptions(method=args.method, dt_s=args.dt, output_dt_s=output_dt_s,
                             damping_ratio=zeta, damping=args.damping_form)


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm simulate``."""
    import numpy as np

    from ..files.model_source import load_model
    from ..files.simulation_record import simulation_record
    from ..files.trajectory_csv import trajectory_csv
    from ..io.atomic import atomic_write_text
    from ..io.output_folder import output_folder
    from ..simulation import simulate
    from ..views.response_plot import plot_response
    from .checks import gravity_option, modal_damping_option
    from .plant_options import actuators_on_beam, spans_on_beam, with_hub

    force = check_options(args)
    plant = check_plant_options(args)
    source = load_model(args.model, args.beam)
    model, fitted = source.model, source.fit
    args.gravity_m_s2 = gravity_option(args.gravity, source,
                                       getattr(args, "bus_spec", None) is not None)
    ratio = modal_damping_option(args.damping_given, source, args.damping_form,
                                 plant["hub"] is not None
                                 or getattr(args, "bus_spec", None) is not None)
    if args.compare_truth and model.beam is None:
        raise BeamInputError("--compare-truth: needs the beam (give a fit.json or a model JSON; "
                             "a URDF does not carry it)")
    if plant["hub"] is not None:
        model = with_hub(model, plant["hub"])
    model = supported_model(model, args)
    if args.actuator:
        actuators_on_beam(model, plant["actuators"], args.actuator, args.fit_actuators)
    else:  # those a model JSON or URDF export records
        plant["actuators"] = source.actuators
    plant["actuators"] = fit_actuators(args, model, fitted, plant["actuators"])
    spans_on_beam(model, plant["loads"], args.distributed_span)
    if args.fit_actuators and not args.quiet:
        for i, a in enumerate(plant["actuators"]):
            print(f"strain[{i}] joint weights fitted to the truth: "
                  + " ".join(f"{v:.6g}" for v in a.joint_weights), file=sys.stderr)
    hub = model.hub is not None
    motion = base_motion_of(args)
    outputs = plant_outputs(plant, hub)
    out = Path(args.out)
    output_dt = args.output_dt or args.duration / DEFAULT_SAMPLES
    nv = model.pin_model.nv
    q0 = np.full(nv, args.initial_angle)
    q0[:model.n_free] = 0.0  # a hub or bus starts at 0; --initial-angle bends the beam joints
    # the stiffness form's beta and the fitted diagonal damping from the straight pose, as the
    # MJCF/URDF exports set them; the other forms are exact about the initial pose
    diagonal = args.damping_form in ("stiffness", "modal_fit")
    damping_pose = np.zeros(nv) if diagonal else None
    tr = simulate(model, args.duration, q0=q0, tip_force=force if np.any(force) else None,
                  options=simulation_options(args, output_dt, ratio), damping_pose=damping_pose,
                  inputs=plant["inputs"], u=plant["u"], actuators=tuple(plant["actuators"]),
                  loads=plant["loads"], outputs=outputs, base_motion=motion,
                  gravity_m_s2=args.gravity_m_s2 if any(args.gravity_m_s2) else None,
                  spin_rad_s=args.spin)
    world = world_tip_columns(model, motion, tr)  # the run's tip is in the base frame
    plant_cmp = None
    if args.compare_truth and plant["plant"]:  # before any file: a refusal leaves OUT as it was
        plant_cmp = plant_comparison(model, fitted, plant, outputs, args)
    # every file replaces an earlier simulation's as one set (output_folder)
    with output_folder(out, SIMULATE_FILES, marker="trajectory.csv") as stage:
        atomic_write_text(stage / "trajectory.csv",
                          trajectory_csv(tr, hub, world, bus=model.bus is not None))
        # the integrator used (the rule's pick under the default "auto") and its counts
        atomic_write_text(stage / "simulation.json", json.dumps(
            {**provenance(None), **simulation_record(tr, args.method)}, indent=2) + "\n")
        plot_response(model, tr, force, args.damping, stage / "response.png")
        if not args.quiet:
            print(f"{tr.steps} steps ({tr.method}) in {tr.wall_time_s:.3f} s for "
                  f"{args.duration} s simulated; wrote {out / 'trajectory.csv'}", file=sys.stderr)
        if plant_cmp is not None:
            from ..plant.comparison_plot import plot_plant_comparison
            from ..plant.comparison_record import comparison_summary

            plot_plant_comparison(plant_cmp.comparison, stage / "comparison.png")
            atomic_write_text(stage / "comparison.json", json.dumps(
                {**provenance(getattr(fitted, "seed", None)),
                 **plant_cmp.to_dict(Path(args.model).name)}, indent=2) + "\n")
            if not args.quiet:
                for line in comparison_summary(plant_cmp.comparison):
                    print(line, file=sys.stderr)
        elif args.compare_truth:
            from ..plant.truth_comparison import compare_truth
            from ..plant.truth_comparison_plot import plot_truth_comparison
            from .compare_truth import comparison_request, print_truth_warnings
            from .fit_checks import cache_dir

            request = comparison_request(model, fitted, args.truth_model, quiet=args.quiet)
            cmp = compare_truth(model, request, args.damping, cache_dir(args))
            print_truth_warnings(cmp.truth, args.quiet)
            plot_truth_comparison(cmp, stage / "truth_comparison.png")
            # the JSON last: its presence marks a complete comparison
            atomic_write_text(stage / "truth_comparison.json", json.dumps(
                {**provenance(getattr(fitted, "seed", None)),
                 **cmp.to_dict(Path(args.model).name)}, indent=2) + "\n")
            if not args.quiet:
                print(f"against the {request.model} truth: step error "
                      f"{100 * cmp.accuracy.step_error:.3g} %, FRF error "
                      f"{100 * cmp.accuracy.frf_error:.3g} %; "
                      f"wrote {out / 'truth_comparison.json'}", file=sys.stderr)
    return 0
