"""``prbdm export``: write a PRBDM as URDF, MJCF (MuJoCo) or JSON."""

from __future__ import annotations

import argparse
import sys

from . import add_common

EXAMPLES = """\
examples:
  prbdm export runs/ref/fit.json \\
      --format urdf --out ref.urdf
  prbdm export runs/ref/fit.json \\
      --format mjcf --damping 0.02 --out ref.xml
  prbdm export ref.urdf --format mjcf --out ref.xml

Load them with prbdm_pin.load_urdf / pinocchio.buildModelFromUrdf (URDF; springs in the gazebo
tags), mujoco.MjModel.from_xml_path (MJCF) or prbdm_pin.export.read_model_json (JSON).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``export`` subparser."""
    from ..export import FORMATS

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
    p.add_argument("--damping", type=float, default=0.02, metavar="ZETA",
                   help="MJCF joint damping from this modal ratio (default 0.02)")
    p.add_argument("--out", required=True, metavar="FILE", help="output file")
    add_common(p)
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm export``."""
    from ..export import export_model
    from .simulate import load_model

    model = load_model(args.model, args.beam)
    path = export_model(model, args.out, args.format, damping_ratio=args.damping)
    if not args.quiet:
        print(f"wrote {path} ({args.format}, {model.n_joints} joints)", file=sys.stderr)
    return 0
