"""``prbdm truth``: finite-element truth of a beam file (frequencies, tip response, mode shapes)."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from ..io.provenance import provenance
from . import add_common

EXAMPLE = """example:
  prbdm truth examples/beams/reference-random.json --modes 5 --out out/truth
  writes out/truth/truth.json and out/truth/modes.vtu (open in ParaView)"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``truth`` subparser."""
    p = subparsers.add_parser(
        "truth", help="finite-element truth: bending frequencies and tip deflection",
        description="Modal analysis (Kirchhoff plate by default) and tip-load solve of a beam.",
        epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("beam", help="beam JSON file")
    p.add_argument("--model", default="plate", choices=["plate", "plate-morley", "solid", "beam"])
    p.add_argument("--modes", type=int, default=5, help="number of bending modes (default 5)")
    p.add_argument("--mesh", type=int, default=None, help="mesh level (default: model's own)")
    p.add_argument("--selection", default="paper", choices=["paper", "shape"])
    p.add_argument("--no-static", action="store_true", help="skip the tip-load solve")
    p.add_argument("--large-deflection", default="calibrated-elastica",
                   choices=["calibrated-elastica", "elastica", "solid", "none"],
                   help="large-deflection tip solve. Default calibrated-elastica: the elastica "
                        "with EI(x) scaled so its small-load tip is the truth model's own linear "
                        "tip, consistent with the frequencies (milliseconds). elastica: plain 1D "
                        "theory; solid: the nonlinear 3D solid (reference; minutes on wide "
                        "panels)")
    p.add_argument("--error-tol", type=float, default=0.5, metavar="PCT",
                   help="refuse (exit 2) a truth whose error estimate (twice the change to the "
                        "next mesh level) exceeds PCT %% for a selected mode (default 0.5)")
    p.add_argument("--accept-coarse", action="store_true",
                   help="accept any error estimate (still reported)")
    p.add_argument("--out", required=True, help="output directory")
    add_common(p)
    p.set_defaults(func=run)
    return p


TRUTH_FILES = ("truth.json", "modes.vtu")


def check_options(args) -> None:
    """Refuse bad ``prbdm truth`` options before the beam is read."""
    from ..io.paths import writable_dir
    from ..options.limits import check_cap
    from .checks import in_range

    # a truth serves fits of up to max_joints joints: as many modes at most
    in_range("--modes", args.modes, 1, integer=True)
    check_cap("--modes", args.modes, "max_joints")
    in_range("--mesh", args.mesh, 0, 6, integer=True)
    in_range("--error-tol", args.error_tol, 0.0, lo_open=True, unit="%")
    writable_dir(args.out, "--out")


def run(args) -> int:
    """Run ``prbdm truth`` (exit code 0 on success)."""
    from ..errors import BeamInputError
    from ..files.beam_file import load_beam
    from ..io.atomic import atomic_write_text
    from ..io.output_folder import output_folder
    from ..truth import CoarseTruthError, TruthRequest, compute_truth
    from ..truth.vtu import write_modes_vtu

    check_options(args)
    t0 = time.perf_counter()
    beam = load_beam(args.beam)
    if not args.quiet:
        print(f"truth: {beam.name} with the {args.model} model ...", flush=True)
    request = TruthRequest(model=args.model, modes=args.modes, mesh_level=args.mesh,
                           selection=args.selection, static=not args.no_static,
                           large_deflection=args.large_deflection,
                           error_tol_pct=None if args.accept_coarse else args.error_tol)
    try:
        r = compute_truth(beam, request)
    except CoarseTruthError as exc:
        raise BeamInputError(str(exc)) from None
    wall = time.perf_counter() - t0
    out = Path(args.out)

    def lst(a):
        return None if a is None else [float(v) for v in a]

    doc = {
        **provenance(),
        "beam": beam.name, "beam_fingerprint": r.beam_fingerprint, "model": r.model,
        "mesh_level": r.mesh_level,
        "selection": r.selection, "dofs": int(r.modal.dofs),
        "omega_rad_s": lst(r.omega_rad_s), "mode_index": [int(i) for i in r.mode_index],
        "mpf_z": lst(r.modal.mpf_z[r.mode_index]), "mpf_z_fraction": lst(r.mpf_z_fraction),
        "mac": lst(r.mac_beam), "labels": [r.labels[i] for i in r.mode_index],
        "error_estimate_pct": lst(r.error_estimate_pct),
        "error_estimate_level": r.error_estimate_level,
        "beam_gap_pct": lst(r.beam_gap_pct), "beam_gap_cause": list(r.beam_gap_cause),
        "all_omega_rad_s": lst(r.modal.omega_rad_s), "all_labels": list(r.labels),
        "tip_position_m": lst(r.tip_position_m), "tip_displacement_m": lst(r.tip_displacement_m),
        "large_deflection": None if r.static_nonlinear is None else r.static_nonlinear.model,
        "linear_tip_displacement_m": (None if r.static_linear is None
                                      else lst(r.static_linear.tip_displacement_m)),
        "static_theory_gap_pct": r.static_theory_gap_pct,
        "wall_time_s": wall, "version": r.version, "warnings": list(r.warnings),
    }
    # truth.json and modes.vtu replace an earlier truth's as one set
    with output_folder(out, TRUTH_FILES, marker="truth.json") as stage:
        if r.modal.nodes_m is not None:
            write_modes_vtu(r.modal, stage / "modes.vtu")
        atomic_write_text(stage / "truth.json", json.dumps(doc, indent=2) + "\n")
    if not args.quiet:
        for w in r.warnings:
            print(f"warning: {w}")
        print(_summary(r))
        if r.static_theory_gap_pct is not None:
            print(f"static: 1D beam vs {r.model} linear tip {r.static_theory_gap_pct:+.3f} % "
                  "(positive: the 1D beam is softer)")
        print(f"wrote {out / 'truth.json'} ({wall:.1f} s)")
    return 0


def _summary(r) -> str:
    """One line per selected mode: frequency, label, error estimate, gap to 1D theory, cause."""
    lines = [f"{'mode':>4} {'omega rad/s':>12} {'label':>9} {'error est. %':>12} "
             f"{'1D gap %':>9}  cause of the 1D gap"]
    for k, i in enumerate(r.mode_index):
        est = "-" if r.error_estimate_pct is None else f"{r.error_estimate_pct[k]:.3g}"
        gap = "-" if r.beam_gap_pct is None else f"{r.beam_gap_pct[k]:+.2f}"
        cause = r.beam_gap_cause[k] if k < len(r.beam_gap_cause) else ""
        lines.append(f"{k + 1:>4} {r.omega_rad_s[k]:>12.6g} {r.labels[int(i)]:>9} {est:>12} "
                     f"{gap:>9}  {cause}")
    if r.error_estimate_level is not None:
        lines.append(f"error estimate: twice the change to mesh level {r.error_estimate_level}; "
                     "1D gap: 100 (omega_1D / omega - 1)")
    return "\n".join(lines)
