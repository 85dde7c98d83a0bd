"""``prbdm calibrate``: fit E, rho and modal damping of a PRBDM to a measured ring-down."""

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

Data: a CSV with a header, t_s (s, increasing) then one column per measured output named as
`prbdm linearize` names outputs, with or without the unit the trajectory CSV appends (tip_z or
tip_z_m, tip_z_rate or tip_z_rate_m_s, q[0] or q[0]_rad): a free ring-down of the clamped
member. Its initial state (each mode's amplitude and phase) is fitted with the parameters.

Parameters: E and rho (scales of the model's: springs scale with E, link masses and inertias
with rho), damping[k] (the modal damping ratio of mode k + 1), or rayleigh_alpha (1/s) and
rayleigh_beta (s) of C = alpha M + beta K instead, offset[CHANNEL] (a constant sensor offset
of a data channel, its unit). A clamped member's ring-down sees E/rho only: asking
for both is refused, as is any parameter the data cannot determine.

On a hub of known inertia (--hub INERTIA:RADIUS [--hub-axis y], or a model JSON that has one)
the coupled modes depend on the beam's mass against the hub's, so E and rho are fitted apart;
damping[k] is then the ratio of flexible mode k + 1 (the hub's rigid rotation is undamped, its
angle a + b t fitted with the initial state). A hub much heavier than the beam's own inertia
about its axis, or one turning about x or z, holds the beam as a clamp: E with rho is refused.

Writes OUT/calibration.json ("parameters": {NAME: {"value", "std_error"}}, E in Pa, rho in
kg/m^3; the residual RMS per channel), OUT/model.json (the calibrated model JSON, the fitted
ratios in its modal damping record) and OUT/calibration.png (data against model).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``calibrate`` subparser."""
    p = subparsers.add_parser(
        "calibrate",
        help="fit E, rho and modal damping to a measured ring-down",
        description="Calibrate a PRBDM (fit.json or model JSON) to a measured free ring-down.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json or model JSON")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--data", required=True, metavar="FILE", help="ring-down CSV (t_s, outputs)")
    p.add_argument("--parameters", required=True, metavar="NAMES",
                   help="comma-separated: E, rho, damping[k], rayleigh_alpha, rayleigh_beta, "
                        "offset[CHANNEL]")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help="modes in the response (default: those damping[k] names; 2 with both "
                        "Rayleigh coefficients; at least 1)")
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


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm calibrate``."""
    from ..files.calibration_file import write_calibration
    from ..files.model_source import load_model
    from ..fitting.calibrate import calibrate
    from ..fitting.calibration_data import read_ring_down
    from ..io.paths import writable_dir
    from .checks import in_range
    from .plant_options import hub_option, with_hub

    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="the ratio of the modes not fitted")
    if args.modes is not None:
        in_range("--modes", args.modes, 1, None, integer=True, why="modes in the response")
    hub = hub_option(args.hub, args.hub_axis)
    out = writable_dir(args.out, "--out")
    data = read_ring_down(args.data)
    model = load_model(args.model, args.beam).model
    if hub is not None:
        model = with_hub(model, hub)
    result = calibrate(model, data, args.parameters, n_modes=args.modes,
                       damping_ratio=args.damping)
    write_calibration(result, out)
    if not args.quiet:
        for n, v, s in zip(result.parameters, result.values, result.std_errors, strict=True):
            print(f"{n} = {v:.6g} +/- {s:.2g}", file=sys.stderr)
        rms = ", ".join(f"{c} {v:.3g}" for c, v in result.residual_rms.items())
        print(f"residual RMS: {rms}; wrote {out}", file=sys.stderr)
    return 0
