"""``prbdm statics``: a PRBDM's equilibrium under tip loads, a distributed load and gravity.

Writes ``statics.json`` (``tip_position_m`` world, m; ``q_rad``; and the rest of
:class:`prbdm_pin.plant.statics.StaticEquilibrium`).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..io.provenance import provenance
from . import add_common

EXAMPLES = """\
examples:
  prbdm statics runs/ref/fit.json --tip-force 0,0,-10 --out runs/ref/statics
  prbdm statics model.urdf --tip-moment 0,-2.5,0 --out runs/roll
  prbdm statics runs/ref/fit.json --gravity 0,0,-9.81 --tip-force 0,0,-1 --out runs/sag
  prbdm statics runs/ref/fit.json --tip-moment-follower 0,-2.5,0 --out runs/roll
  prbdm statics runs/ref/fit.json --distributed-load 0,0,-20 --distributed-span 0.3:0.6 \
      --out runs/patch

The loads are dead (fixed in the world) but --tip-moment-follower, which is about the tip
link's own axes and turns with it: a moment about -y rolls a planar chain up (x towards +z).
--distributed-load is a force per unit length (N/m, world) over --distributed-span (m from
the root; default the whole beam), mapped on the links by virtual work. A fit.json, a model
JSON or a URDF is read as its model. A hub model is refused (the hub
would turn; `prbdm linearize --hub` holds it with a trim torque).
"""

STATICS_FILES = ("statics.json",)


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``statics`` subparser."""
    p = subparsers.add_parser(
        "statics",
        help="the static equilibrium of a PRBDM under tip loads, a distributed load and "
        "gravity",
        description="Solve K q + g(q) = J^T F + J_w^T M + J_l^T M_f + B_q q_d for the joint "
        "angles and the tip position under tip loads (dead or follower), a distributed load "
        "and gravity.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", metavar="MODEL", help="fit.json, model JSON or URDF")
    p.add_argument("--beam", metavar="BEAM.json",
                   help="the beam a fit.json was fitted to (default: the one it carries)")
    p.add_argument("--tip-force", default="0,0,0", metavar="FX,FY,FZ",
                   help="dead tip force, N, world (default 0,0,0)")
    p.add_argument("--tip-moment", default="0,0,0", metavar="MX,MY,MZ",
                   help="dead tip moment, N m, world (default 0,0,0)")
    p.add_argument("--tip-moment-follower", default="0,0,0", metavar="MX,MY,MZ",
                   help="follower tip moment, N m, about the tip link's own axes (default "
                        "0,0,0)")
    p.add_argument("--distributed-load", default="0,0,0", metavar="QX,QY,QZ",
                   help="force per unit length, N/m, world, over --distributed-span (default "
                        "0,0,0)")
    p.add_argument("--distributed-span", default=None, metavar="XA:XB",
                   help="span of --distributed-load, m from the root (default the whole beam)")
    p.add_argument("--gravity", default=None, metavar="GX,GY,GZ",
                   help="gravity, m/s^2, world (default: the gravity the model was fitted in, "
                        "none for most models)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    add_common(p)
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm statics``."""
    from ..files.model_source import load_model
    from ..io.atomic import atomic_write_text
    from ..io.output_folder import output_folder
    from ..io.paths import writable_dir
    from ..plant.statics import statics
    from .checks import gravity_option, xyz_option
    from .plant_options import spans_on_beam, spans_option

    loads = {"tip_force_N": xyz_option(args.tip_force, "--tip-force", "N"),
             "tip_moment_Nm": xyz_option(args.tip_moment, "--tip-moment", "N m"),
             "tip_moment_follower_Nm": xyz_option(args.tip_moment_follower,
                                                  "--tip-moment-follower", "N m"),
             "distributed_N_m": xyz_option(args.distributed_load, "--distributed-load", "N/m")}
    texts = [] if args.distributed_span is None else [args.distributed_span]
    spans = spans_option(texts)
    writable_dir(args.out, "--out")
    source = load_model(args.model, args.beam)
    model = source.model
    loads["gravity_m_s2"] = gravity_option(args.gravity, source)
    spans_on_beam(model, spans, texts)
    span = spans[0] if spans else None
    eq = statics(model, **loads, distributed_load=span)
    record = {**provenance(getattr(source.fit, "seed", None)), "model": Path(args.model).name,
              "n_joints": model.n_joints, "axes": model.axes.value, **eq.to_dict()}
    out = Path(args.out)
    with output_folder(out, STATICS_FILES) as stage:
        atomic_write_text(stage / "statics.json", json.dumps(record, indent=2) + "\n")
    if not args.quiet:
        p = ", ".join(f"{v:.6g}" for v in eq.tip_position_m)
        print(f"tip at ({p}) m, largest joint angle {abs(eq.q_rad).max():.4g} rad; wrote "
              f"{out / 'statics.json'}", file=sys.stderr)
    return 0

