"""``prbdm calibrate``: fit E, rho and damping of a PRBDM to a ring-down, a driven run or an FRF."""

from __future__ import annotations

import argparse
import sys

from . import add_common

EXAMPLES = """\
examples:
  prbdm calibrate runs/ref/fit.json --data ringdown.csv \\
      --parameters E,damping[0],damping[1] --out runs/cal
  prbdm calibrate model.json --data ringdown.csv \\
      --parameters rho,damping[0],offset[tip_z_m] --modes 2 --out runs/cal
  prbdm calibrate runs/ref/fit.json --data hub_ringdown.csv --hub 0.5:0.05 \
      --parameters E,rho,damping[0],damping[1] --out runs/cal_hub

  prbdm calibrate model.json --data driven.csv --parameters E,rho,damping[0] --out runs/cal
  prbdm calibrate model.json --data frf.csv --parameters E,rho,damping[0],damping[1] \
      --out runs/cal

Data: a CSV with a header; its kind is told by the header.
- Free ring-down: t_s (s, increasing) then one column per measured output named as
  `prbdm linearize` names outputs, with or without the unit the trajectory CSV appends (tip_z
  or tip_z_m, tip_z_rate or tip_z_rate_m_s, q[0] or q[0]_rad). Its initial state (each
  mode's amplitude and phase) is fitted with the parameters.
- Driven trajectory: t_s (s, uniform steps), the measured inputs named as `prbdm linearize`
  names inputs, with or without their unit or the trajectory CSV's u: prefix (tip_force_z,
  tip_force_z_N, u:tip_force_z, base_accel_z_m_s2, joint_torque[0]_N_m), and the measured
  outputs. Each input sample is held over the next step (a zero-order hold); the member
  starts at rest, or with --initial-state from a fitted state of its lowest --modes modes.
- FRF: f_hz (Hz, increasing, > 0), then per transfer function OUTPUT/INPUT_re and
  OUTPUT/INPUT_im, its real and imaginary parts (tip_z/tip_force_z_re in m/N, or with units
  tip_z_m/tip_force_z_N_re), for y = H u with u = exp(i 2 pi f t).

Parameters: E and rho (scales of the model's: springs scale with E, link masses and inertias
with rho), damping[k] (the modal damping ratio of mode k + 1), or rayleigh_alpha (1/s) and
rayleigh_beta (s) of C = alpha M + beta K instead, offset[CHANNEL] (a constant sensor offset
of a data channel, its unit; not for an FRF). A ring-down's frequencies see E/rho only, and
so does a response to a base acceleration: asking for both is refused, as is any parameter
the data cannot determine. A response to a force or a moment sees E and rho apart.

On a hub of known inertia (--hub INERTIA:RADIUS [--hub-axis y], or a model JSON that has one)
the coupled modes depend on the beam's mass against the hub's, so E and rho are fitted apart;
damping[k] is then the ratio of flexible mode k + 1 (the hub's rigid rotation is undamped, its
angle a + b t fitted with the initial state). A hub much heavier than the beam's own inertia
about its axis, or one turning about x or z, holds the beam as a clamp: E with rho is refused.

Writes OUT/calibration.json ("parameters": {NAME: {"value", "std_error"}}, E in Pa, rho in
kg/m^3; the residual RMS per channel), OUT/model.json (the calibrated model JSON, the fitted
ratios in its modal damping record) and OUT/calibration.png (data against model; for an FRF
magnitude and phase against frequency).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``calibrate`` subparser."""
    p = subparsers.add_parser(
        "calibrate",
        help="fit E, rho and damping to a measured ring-down, driven trajectory or FRF",
        description="Calibrate a PRBDM (fit.json or model JSON) to a measured free ring-down, "
                    "a trajectory driven by measured inputs or an FRF.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json or model JSON")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--data", required=True, metavar="FILE",
                   help="CSV: ring-down (t_s, outputs), driven (t_s, inputs, outputs) or FRF "
                        "(f_hz, OUTPUT/INPUT_re, _im)")
    p.add_argument("--parameters", required=True, metavar="NAMES",
                   help="comma-separated: E, rho, damping[k], rayleigh_alpha, rayleigh_beta, "
                        "offset[CHANNEL]")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help="modes whose initial state is fitted: a ring-down's, a driven "
                        "trajectory's with --initial-state (default: those damping[k] names; 2 "
                        "with both Rayleigh coefficients; at least 1)")
    p.add_argument("--initial-state", action="store_true",
                   help="driven trajectory: fit the initial state of its lowest --modes modes "
                        "(default: it starts at rest)")
    p.add_argument("--damping", type=float, default=0.02, metavar="ZETA",
                   help="ratio of the modes not fitted, and the fitted ones' start "
                        "(default 0.02)")
    p.add_argument("--hub", default=None, metavar="INERTIA:RADIUS",
                   help="the member on a free hub of known inertia (kg m^2) at radius (m): E "
                        "and rho apart (default: the model's own hub, if any)")
    p.add_argument("--hub-axis", default=None, metavar="{x,y,z}",
                   help="the world axis the --hub turns about (default y, the bending plane)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_common(p)
    p.set_defaults(func=run)
    return p


def _check_kind(args: argparse.Namespace, data) -> None:
    """Refuse --modes and --initial-state where the data has no initial state, by option."""
    from ..errors import BeamInputError
    from ..fitting.calibration_measured import DrivenTrajectory, FrequencyResponse

    if args.initial_state and isinstance(data, FrequencyResponse):
        raise BeamInputError("--initial-state: an FRF has no initial state")
    if args.modes is not None and (isinstance(data, FrequencyResponse) or isinstance(
            data, DrivenTrajectory) and not args.initial_state):
        raise BeamInputError(f"--modes = {args.modes}: the modes whose initial state is "
                             "fitted; this data has none (an FRF, or a driven trajectory "
                             "without --initial-state)")


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm calibrate``."""
    from ..files.calibration_file import write_calibration
    from ..files.model_source import load_model
    from ..fitting.calibrate import calibrate
    from ..fitting.calibration_measured import read_calibration_data
    from ..io.paths import writable_dir
    from .checks import in_range
    from .plant_options import hub_option, with_hub

    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="the ratio of the modes not fitted")
    if args.modes is not None:
        in_range("--modes", args.modes, 1, None, integer=True, why="modes in the response")
    hub = hub_option(args.hub, args.hub_axis)
    out = writable_dir(args.out, "--out")
    data = read_calibration_data(args.data)
    _check_kind(args, data)
    model = load_model(args.model, args.beam).model
    if hub is not None:
        model = with_hub(model, hub)
    result = calibrate(model, data, args.parameters, n_modes=args.modes,
                       damping_ratio=args.damping,
                       initial_state=True if args.initial_state else None)
    write_calibration(result, out)
    if not args.quiet:
        for n, v, s in zip(result.parameters, result.values, result.std_errors, strict=True):
            print(f"{n} = {v:.6g} +/- {s:.2g}", file=sys.stderr)
        rms = ", ".join(f"{c} {v:.3g}" for c, v in result.residual_rms.items())
        print(f"residual RMS: {rms}; wrote {out}", file=sys.stderr)
    return 0
