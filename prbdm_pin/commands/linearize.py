"""``prbdm linearize``: a fitted PRBDM as a linear state-space plant.

Writes the matrices, names, modes and a Bode plot.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..errors import BeamInputError
from ..io.provenance import provenance
from . import add_common
from .bus_option import add_bus_option, bus_option, bus_record, state_units, with_bus
from .fit_actuators import add_fit_actuators_option, check_fit_actuators, fit_actuators
from .plant_options import (
    actuators_on_beam,
    actuators_option,
    add_plant_options,
    add_span_option,
    hub_option,
    names_option,
    spans_on_beam,
    spans_option,
    with_hub,
)
from .spin_options import check_spin_option, spin_record

EXAMPLES = """\
examples:
  prbdm linearize runs/ref/fit.json --inputs tip_force_z --outputs tip_z --out runs/ref/plant
  prbdm linearize runs/ref/fit.json --inputs tip_force_z,strain[0] --outputs tip_z,q[0] \\
      --actuator 0.05:0.4 --load 0,0,-10 --out runs/ref/plant
  prbdm linearize runs/ref/fit.json --inputs hub_torque --outputs hub_angle,tip_z \\
      --hub 0.5:0.05 --damping-ratio 0.01 --out runs/ref/hub
  prbdm linearize runs/ref/fit.json --inputs hub_torque,strain[0] --outputs hub_angle,tip_z \\
      --hub 5:0.1 --actuator 0:0.1 --compare-truth --out runs/ref/hub
  prbdm linearize runs/ref/fit.json --inputs hub_torque --outputs hub_angle,tip_z \\
      --hub 50:0.1 --hub-axis z --spin 20 --out runs/ref/spin
  prbdm linearize runs/ref/fit.json --inputs strain[0] --outputs tip_z --actuator 0.2:0.3 \\
      --fit-actuators --out runs/ref/patch

Inputs: tip_force_z, tip_force_x, tip_force_y (N), tip_moment_y, tip_moment_z (N m, about world
y, z at the tip), tip_moment_x (N m, about world x at the tip: twists it), corner_force_z_left,
corner_force_z_right (N, z forces at the tip corners, +-w(L) across the tip), joint_torque[j]
(N m, spring coordinate j from the root, 0-based: every axis of a spatial chain), strain[i]
(N m, the moment of the i-th --actuator; planar chains), hub_torque (N m, with --hub),
tip_moment_follower_x, _y, _z (N m, about the tip link's own axes), distributed_force_x, _y, _z
(N/m, world, uniform over the beam; distributed_force_z[i] over the i-th --distributed-span;
mapped on the links by virtual work), base_accel_x, _y, _z
(m/s^2, a translating base's acceleration: the states and outputs are then relative to the
base).
Outputs: tip_z, tip_x, tip_y (m), tip_z_rate (m/s), tip_twist (rad, the tip's rotation about its
own axis), corner_z_left, corner_z_right (m, z of the tip corners), q[j] (rad), q_rate[j]
(rad/s), spring_torque[j] (N m), hub_angle (rad), hub_rate (rad/s, with --hub); sensors at a
station X m from the root (Y m across): slope@X, twist@X (rad, the section's rotation about y
and about its own axis), point_x@X:Y, point_y@X:Y, point_z@X:Y (m, the world displacement of a
planform point), strain@X (microstrain, the bending strain of the faces, positive when the
bending lifts the tip), root_force_x|y|z (N) and root_moment_x|y|z (N m, about the root point):
the support's wrench on the member, base frame. The strain and the root reaction read the
acceleration: their C and D carry it (the modal table's output gains do not: C_q and C_v
only). All are deviations from the equilibrium under --load and --gravity; a hub is held there
by a trim torque. A spatial fit (axes xy, yz, xyz) is linearised through its general
kinematics.

Hub and spin: --hub-axis y (the default) turns the beam in its own bending plane, z sweeps it
through the xy-plane with the bending out of that plane, x spins it about its own axis.
--spin RAD_S linearises about the hub's steady spin (straight, or coned under a --load or
--gravity along the hub axis; off the axis they are refused): the centrifugal stiffness and the
gyroscopic terms from Pinocchio's RNEA derivatives; the states are deviations from the spinning
motion; linear_model.json's spin_frequencies_rad_s (and the omega printed) are the spinning
plant's undamped flexible frequencies with its gyroscopic coupling.

Strain actuators: by default a patch's moment goes to the joints inside it (1) and under its
ends (1/2), the virtual-work map of the chain; a patch shorter than a link then moves no joint.
--fit-actuators fits each joint's weight so that the PRBDM's n modes get the truth's modal input
gains (the truth the fit.json was made against, from the cache).

Writes OUT/linear_model.npz (A, B, C, D; x = [q; v]; with --dt also the zero-order-hold Ad,
Bd), OUT/linear_model.mat (the same matrices with state_names, input_names, output_names and
units as cell arrays, for MATLAB), OUT/linear_model.json (names, units, equilibrium, modal
table, the actuators' stations and joint weights, dt_s) and OUT/bode.png.

--compare-truth adds OUT/comparison.json and OUT/comparison.png: the plant against the truth of
the same plant (the finite-element truth the fit.json was fitted to, from the cache, on the same
hub or bus and with the same actuators: its clamped modes, in hybrid coordinates on a hub or a
free bus), both damped
alike (every flexible mode at --damping-ratio), unloaded at the straight pose. Per flexible
mode: the signed frequency error; per input/output pair both plants have: the FRF error over
[0, 1.2 omega_n] (a hub's from 0.1 omega_1, its rigid-body mode being singular at 0; and its
flexible part from 0), the peak error at each resonance, and the unit-step response error (a
hub's flexible part: the rigid rotation's response subtracted). Signals the truth plant lacks
(tip_x, q[j], q_rate[j], spring_torque[j], tip_force_x, joint_torque[j], the corner and twist
signals) are listed as not compared.
"""

LINEARIZE_FILES = ("linear_model.npz", "linear_model.mat", "linear_model.json", "bode.png",
                   "comparison.json", "comparison.png")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``linearize`` subparser."""
    p = subparsers.add_parser(
        "linearize",
        help="linearise a PRBDM into a state-space plant (inputs, outputs, hub, actuators)",
        description="Linearise a fitted PRBDM about its equilibrium into A, B, C, D with named "
        "inputs and outputs, for control design.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="FIT_JSON", help="fit.json (or a model JSON or URDF)")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--inputs", default="tip_force_z", metavar="NAMES",
                   help="comma-separated input names (default tip_force_z)")
    p.add_argument("--outputs", default="tip_z", metavar="NAMES",
                   help="comma-separated output names (default tip_z)")
    add_plant_options(p)
    add_span_option(p)
    add_bus_option(p)
    p.add_argument("--load", default="0,0,0", metavar="FX,FY,FZ",
                   help="dead tip load of the equilibrium, N, world (default 0,0,0)")
    p.add_argument("--gravity", default=None, metavar="GX,GY,GZ",
                   help="gravity, m/s^2, world (default: the gravity the model was fitted in, "
                        "none for most models)")
    p.add_argument("--spin", type=float, default=None, metavar="RAD_S",
                   help="linearise about the --hub spinning steadily at this rate, rad/s, about "
                        "--hub-axis (--load and --gravity only along that axis; writes the "
                        "spinning plant's frequencies)")
    p.add_argument("--damping-ratio", type=float, default=None, metavar="ZETA",
                   help="damping ratio of every flexible mode (modal, modal_fit) or the lowest "
                        "(stiffness) (default 0.02, or the per-mode ratios a calibrated model "
                        "JSON records)")
    p.add_argument("--damping-form", choices=("modal", "stiffness", "eq5c", "modal_fit"),
                   default="modal",
                   help="damping form (default modal; modal_fit: the diagonal joint damping "
                        "fitted to the per-mode ratios, what an MJCF/URDF export of a "
                        "calibrated model carries; a hub's rigid mode is never damped)")
    p.add_argument("--dt", type=float, default=None, metavar="S",
                   help="also the zero-order-hold discrete-time plant at this sample time, s "
                        "(Ad, Bd in linear_model.npz and .mat; C, D unchanged)")
    p.add_argument("--compare-truth", action="store_true",
                   help="also compare the plant with the truth the fit was made against, on "
                        "the same hub and actuators (comparison.json, comparison.png)")
    p.add_argument("--cache-dir", default=None, metavar="DIR",
                   help="truth cache folder, shared with `prbdm fit` (default $PRBDM_CACHE or "
                        "~/.cache/prbdm_pin)")
    add_fit_actuators_option(p)
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_common(p)
    p.set_defaults(func=run)
    return p


def check_options(args: argparse.Namespace) -> dict:
    """Refuse bad ``prbdm linearize`` options before the model is read.

    Returns the parsed values (names, actuators, hub, load, gravity).
    """
    from ..io.paths import writable_dir
    from .checks import in_range, xyz_option

    out = {"inputs": names_option(args.inputs, "--inputs"),
           "outputs": names_option(args.outputs, "--outputs"),
           "actuators": actuators_option(args.actuator),
           "hub": hub_option(args.hub, args.hub_axis),
           "loads": spans_option(args.distributed_span), "bus": bus_option(args.bus)}
    if out["bus"] is not None and args.hub:
        raise BeamInputError("--bus: not with --hub (one support at a time)")
    out["load"] = xyz_option(args.load, "--load", "N")
    out["gravity"] = None if args.gravity is None else xyz_option(args.gravity, "--gravity",
                                                                  "m/s^2")
    args.damping_given = args.damping_ratio
    args.damping_ratio = 0.02 if args.damping_ratio is None else args.damping_ratio
    in_range("--damping-ratio", args.damping_ratio, 0.0, 1.0, hi_open=True,
             why="a damping ratio of underdamped modes")
    if args.dt is not None:
        in_range("--dt", args.dt, 0.0, lo_open=True, unit="s")
    check_spin_option(args.spin, out)
    writable_dir(args.out, "--out")
    from .compare_truth import check_compare_options

    check_compare_options(args, out)
    check_fit_actuators(args, len(out["actuators"]))
    return out


def _bode(lin, path: Path) -> None:
    from ..views.bode import plot_bode

    plot_bode(lin, path=path)


def actuator_weights_record(model, actuators) -> dict:
    """Return the record fields ``actuator_weights`` and ``actuator_maps``.

    ``actuator_weights``: each actuator's joint weights, N m per N m, as used;
    ``actuator_maps``: ``"fitted"`` or ``"virtual-work"`` each.
    """
    from ..model.inputs import strain_map

    return {"actuator_weights": [[float(v) for v in strain_map(model.lengths_m, a,
                                                                f"actuators[{i}]")]
                                 for i, a in enumerate(actuators)],
            "actuator_maps": ["fitted" if a.fitted else "virtual-work" for a in actuators]}


def _mat_file(mats: dict, lin, dt_s: float | None) -> bytes:
    """Return the plant as a MATLAB .mat file: matrices, signal names (cells) and units."""
    import io

    import numpy as np
    import scipy.io

    def cells(names):
        return np.array(list(names), dtype=object)

    content = {**mats, "state_names": cells(lin.state_names),
               "input_names": cells(lin.input_names), "output_names": cells(lin.output_names),
               "input_units": cells(lin.input_units), "output_units": cells(lin.output_units)}
    if dt_s is not None:
        content["dt_s"] = float(dt_s)
    buf = io.BytesIO()
    scipy.io.savemat(buf, content, oned_as="column")
    return buf.getvalue()


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm linearize``."""
    import io

    import numpy as np

    from ..files.model_source import load_model
    from ..io.atomic import atomic_write_bytes, atomic_write_text
    from ..io.output_folder import output_folder
    from ..plant.linearize import linearize
    from .checks import gravity_option, modal_damping_option

    opts = check_options(args)
    source = load_model(args.model, args.beam)
    model, fitted = source.model, source.fit
    if args.compare_truth:
        from .compare_truth import truth_request_of

        request = truth_request_of(fitted, args.model)
    if opts["hub"] is not None:
        model = with_hub(model, opts["hub"])
    if opts["bus"] is not None:
        model = with_bus(model, opts["bus"])
    if args.actuator:
        actuators_on_beam(model, opts["actuators"], args.actuator, args.fit_actuators)
    else:  # those a model JSON or URDF export records
        opts["actuators"] = source.actuators
    opts["actuators"] = fit_actuators(args, model, fitted, opts["actuators"])
    spans_on_beam(model, opts["loads"], args.distributed_span)
    opts["gravity"] = gravity_option(args.gravity, source, opts["bus"] is not None)
    gravity = opts["gravity"] if any(opts["gravity"]) else None
    ratio = modal_damping_option(args.damping_given, source, args.damping_form,
                                 opts["hub"] is not None or opts["bus"] is not None)
    lin = linearize(model, inputs=opts["inputs"], outputs=opts["outputs"],
                    load_N=opts["load"], damping_ratio=ratio,
                    damping=args.damping_form, actuators=opts["actuators"],
                    gravity_m_s2=gravity, loads=opts["loads"], spin_rad_s=args.spin,
                    compiled=False)  # one plant a command: numba's load would cost more
    record_provenance = provenance(getattr(fitted, "seed", None))
    record = {
        **record_provenance,
        **lin.to_dict(),
        "model": Path(args.model).name,
        "n_joints": model.n_joints,
        "hub": None if opts["hub"] is None else {
            "inertia_kg_m2": opts["hub"].inertia_kg_m2, "radius_m": opts["hub"].radius_m,
            "axis": opts["hub"].axis},
        **spin_record(args.spin, lin),
        "actuators_m": [[a.x_start_m, a.x_end_m] for a in opts["actuators"]],
        **actuator_weights_record(model, opts["actuators"]),
        "distributed_spans_m": [[ld.x_start_m, ld.x_end_m] for ld in opts["loads"]],
        "load_N": opts["load"], "gravity_m_s2": opts["gravity"],
        "damping_ratio": np.asarray(ratio).tolist(), "damping_form": args.damping_form,
        "bus": bus_record(model),
        "state_units": state_units(model),
    }
    cmp = None
    if args.compare_truth:  # before any file is written: a refusal leaves OUT as it was
        from ..plant.comparison_truth import compare_truth_plant
        from .compare_truth import print_truth_warnings
        from .fit_checks import cache_dir

        cmp = compare_truth_plant(lin, model, request, opts["actuators"], args.damping_ratio,
                                  cache_dir(args))
        print_truth_warnings(cmp.truth, args.quiet)
    mats = {"A": lin.A, "B": lin.B, "C": lin.C, "D": lin.D}
    if args.dt is not None:
        mats["Ad"], mats["Bd"] = lin.discretize(args.dt)
        record["dt_s"] = args.dt
    buf = io.BytesIO()
    np.savez(buf, **mats)
    mat = _mat_file(mats, lin, args.dt)
    out = Path(args.out)
    with output_folder(out, LINEARIZE_FILES, marker="linear_model.json") as stage:
        atomic_write_bytes(stage / "linear_model.npz", buf.getvalue())
        atomic_write_bytes(stage / "linear_model.mat", mat)
        _bode(lin, stage / "bode.png")
        if cmp is not None:
            from ..plant.comparison_plot import plot_plant_comparison

            plot_plant_comparison(cmp.comparison, stage / "comparison.png")
            atomic_write_text(stage / "comparison.json", json.dumps(
                {**record_provenance, **cmp.to_dict(Path(args.model).name)}, indent=2) + "\n")
        atomic_write_text(stage / "linear_model.json", json.dumps(record, indent=2) + "\n")
    if not args.quiet:
        w = ", ".join(f"{x:.4g}" for x in (record["spin_frequencies_rad_s"] if args.spin
                                             else lin.modal().omega_rad_s))
        print(f"{lin.A.shape[0]} states, {len(lin.input_names)} inputs, "
              f"{len(lin.output_names)} outputs; omega = [{w}] rad/s; wrote "
              f"{out / 'linear_model.json'}", file=sys.stderr)
    if cmp is not None and not args.quiet:
        from ..plant.comparison_record import comparison_summary

        print(f"against the {cmp.truth.model} truth plant (wrote {out / 'comparison.json'}):",
              file=sys.stderr)
        for line in comparison_summary(cmp.comparison):
            print(f"  {line}", file=sys.stderr)
    return 0
