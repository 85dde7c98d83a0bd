"""``prbdm export``: write a PRBDM as URDF, MJCF (MuJoCo) or JSON."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from . import add_common

if TYPE_CHECKING:
    import numpy as np

EXAMPLES = """\
examples:
  prbdm export runs/ref/fit.json \\
      --format urdf --out ref.urdf
  prbdm export runs/ref/fit.json \\
      --format mjcf --damping 0.02 --out ref.xml
  prbdm export ref.urdf --format mjcf --out ref.xml

Damping: URDF <dynamics damping> and MJCF joint damping are diagonal, so they carry the
stiffness-proportional form C = beta K (default): mode 1 gets ZETA, mode k ZETA omega_k/omega_1.
`--damping-form modal` (every mode ZETA) is only recorded in JSON; asked for a URDF or MJCF, the
stiffness form is written instead, with a warning giving the modal ratios it produces.
`prbdm simulate --damping-form stiffness` simulates what the file carries.

Every file records (XML comment; JSON fields) the exported model's natural frequencies at the
straight pose and, when the truth is known (a fit.json, or an export of one), its signed per-mode
errors 100 (omega_model/omega_truth - 1); a worst mode off by more than 1 % is warned about.

Load them with prbdm_pin.load_urdf (URDF, springs in the gazebo tags, gravity zero),
pinocchio.buildModelFromUrdf (then set model.gravity = pinocchio.Motion.Zero()),
pybullet.loadURDF(..., useFixedBase=True, flags=pybullet.URDF_USE_INERTIA_FROM_FILE),
mujoco.MjModel.from_xml_path (MJCF) or prbdm_pin.export.read_model_json (JSON).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``export`` subparser."""
    from ..choices import EXPORT_DAMPING_FORMS, FORMATS

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
                   help="damping ratio of mode 1 (stiffness form) or of every mode (modal); "
                        "0: none (default 0.02)")
    p.add_argument("--damping-form", choices=EXPORT_DAMPING_FORMS, default=None,
                   help="stiffness (C = beta K; default for urdf and mjcf) or modal (default "
                        "for json; urdf/mjcf write the stiffness form instead and warn)")
    p.add_argument("--out", required=True, metavar="FILE", help="output file")
    add_common(p)
    p.set_defaults(func=run)
    return p


def truth_frequencies(path: str | Path, fitted) -> np.ndarray | None:
    """The truth frequencies (rad/s) a model file knows: a fit.json's ``omega_truth_rad_s``, or
    the record of an earlier export (model JSON fields, URDF comment); None if none."""
    import numpy as np

    from ..export import read_export_record

    if fitted is not None:
        return np.asarray(fitted.omega_truth_rad_s, dtype=float)
    p = Path(path)
    text = p.read_text(encoding="utf-8")
    if p.suffix.lower() == ".urdf":
        rec = read_export_record(text)
        return None if rec is None else rec.omega_truth_rad_s
    w = json.loads(text).get("omega_truth_rad_s")
    return None if w is None else np.asarray(w, dtype=float)


def check_options(args: argparse.Namespace) -> None:
    """Refuse bad ``prbdm export`` options before the model is read."""
    import os

    from ..errors import BeamInputError
    from .checks import in_range, writable_file

    in_range("--damping", args.damping, 0.0, 1.0, hi_open=True,
             why="the damping_ratio of mode 1 (stiffness form) or of every mode (modal); "
                 "0: none")
    out = writable_file(args.out, "--out")
    if os.path.exists(args.model) and out.exists() and os.path.samefile(args.model, out):
        raise BeamInputError(f"--out = {args.out!r}: is the MODEL file itself; give another "
                             "file name")


def run(args: argparse.Namespace) -> int:
    """Run ``prbdm export``."""
    from ..export import export_model, export_record
    from .simulate import load_model_and_fit

    check_options(args)
    model, fitted = load_model_and_fit(args.model, args.beam)
    omega_truth = truth_frequencies(args.model, fitted)
    rec = export_record(model, args.format, args.damping, args.damping_form, omega_truth)
    path = export_model(model, args.out, args.format, damping_ratio=args.damping,
                        damping_form=args.damping_form, omega_truth_rad_s=omega_truth)
    if not args.quiet:
        for note in rec.warnings:
            print(f"export warning: {note}", file=sys.stderr)
        for line in rec.summary_lines():
            print(line)
        print(f"wrote {path} ({args.format}, {model.n_joints} joints)", file=sys.stderr)
    return 0
