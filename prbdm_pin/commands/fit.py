"""``prbdm fit``: fit an nR PRBDM to a beam's finite-element truth.

Writes fit.json, model.urdf and plots.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..options.validate import MAX_NFEV  # shared with the API's FitOptions
from . import add_common
from .fit_checks import (
    MAX_STARTS,
    check_inputs,
    check_sweep,
    check_truth_options,
)
from .fit_target import gravity_option, load_target
from .options import add_fit_options, add_problem_options, fit_options

EXAMPLE = """examples:
  prbdm fit examples/beams/reference-random.json --joints 4 --frequencies 3 --stiffness paper \\
      --starts 64 --seed 0 --out out/fit4r
  prbdm fit examples/beams/uniform-narrow.json --joints 3 --objective combined --stiffness joint \\
      --truth-model beam --out out/fit3r
  prbdm fit examples/beams/uniform-narrow.json --joints 3 --truth-model beam --stiffness joint \\
      --gravity 0,0,-9.81 --out out/fit3r_sag
writes DIR/fit.json, DIR/model.urdf, DIR/planform.png (and DIR/scf.png for --stiffness paper)

A beam file without "tip_force" has no load (0 N): enough for --objective eigen; a deflection
or combined fit (and prbdm pareto) refuses it (exit 2)."""


def add_truth_options(p: argparse.ArgumentParser) -> None:
    """Options selecting the truth a fit is measured against (shared with ``prbdm pareto``)."""
    p.add_argument("beam", help="beam JSON file")
    p.add_argument("--joints", type=int, required=True, help="number of revolute joints n")
    add_problem_options(p)
    p.add_argument("--truth-model", default="plate", choices=["plate", "beam", "solid"],
                   help="finite-element truth model (default plate)")
    p.add_argument("--mode-selection", default="paper", choices=["paper", "shape"],
                   help="truth modes: largest z participation (paper) or beam-like (shape)")
    p.add_argument("--mesh-level", type=int, default=None, help="truth mesh level")
    p.add_argument("--large-deflection", default="calibrated-elastica",
                   choices=["calibrated-elastica", "elastica", "solid"],
                   help="large-deflection truth tip. Default calibrated-elastica: the elastica "
                        "with EI(x) scaled by the ratio of the 1D beam's and the truth model's "
                        "linear tip deflections, so that at small load it is the model the "
                        "frequencies come from (milliseconds; 0.44 %% and 0.57 %% from the "
                        "nonlinear 3D solid's tip displacement on the tapered and the reference "
                        "panel). elastica: plain 1D theory (1.30 %% and 0.23 %%; 1.05 %% softer "
                        "than the plate at small load on the tapered panel, 5.4 %% on the "
                        "square plate). solid: the nonlinear 3D solid (the reference; about a "
                        "minute)")
    p.add_argument("--accept-coarse", action="store_true",
                   help="accept a computed truth whose error estimate (twice the change to the "
                        "next mesh level) exceeds 0.5 %% for a selected mode (default: refuse, "
                        "exit 2)")
    p.add_argument("--truth", default=None, metavar="TRUTH.json",
                   help="use a truth.json written by `prbdm truth` instead of computing it")
    p.add_argument("--cache-dir", default=None,
                   help="truth cache folder (default $PRBDM_CACHE or ~/.cache/prbdm_pin)")
    p.add_argument("--extra-loads", default=None, metavar="F1,F2,...",
                   help="further load cases, as multiples of the beam's tip force, whose "
                        "large-deflection truth tips the deflection objective also matches")
    p.add_argument("--load-point", default="tip",
                   choices=["tip", "tip_corner_left", "tip_corner_right"],
                   help="spatial deflection, combined and Pareto fits (--axes): where the "
                        "beam's tip force acts, the tip centre or a tip corner (bending plus "
                        "twist); the plate (linear) or the solid (large deflection) gives its "
                        "truth")
    p.add_argument("--out", required=True, help="output directory")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``fit`` subparser."""
    p = subparsers.add_parser(
        "fit", help="fit a PRBDM to the truth (multistart, single objective)",
        description="Multistart fit of an nR PRBDM: eigen (Eq. 17), deflection (Eq. 19) or "
                    "combined (Eq. 27) objective.",
        epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_truth_options(p)
    add_fit_options(p)
    p.add_argument("--workers", type=int, default=1, help="processes for the starts")
    p.add_argument("--gain-points", default=None, metavar="P1,P2",
                   help="also match the truth's modal amplitudes at these tip points (tip, "
                        "tip_corner_left, tip_corner_right: the plate truth's, spatial fits), "
                        "so the model moves them as the truth does (the FRFs a controller "
                        "sees); the planar chain (--axes y, --stiffness joint) takes tip alone")
    p.add_argument("--gain-modes", type=int, default=None, metavar="K",
                   help="with --gain-points: the lowest K matched modes of each kind (default "
                        "all, each weighted by its share of the FRF)")
    p.add_argument("--gravity", default=None, metavar="GX,GY,GZ",
                   help="fit in gravity, m/s^2, member axes (x from root to tip, GY = 0): the "
                        "truth's frequencies about its sag and its tip under the load and its "
                        "weight, the chain's in the same gravity; needs --truth-model beam "
                        "and --stiffness joint (default: no gravity)")
    p.add_argument("--gain-weight", type=float, default=1.0,
                   help="with --gain-points: weight of the amplitude errors (default 1)")
    add_common(p)
    p.set_defaults(func=run)
    return p


def worst_mode_text(result) -> str:
    """'worst mode -15.6 % (mode 1, pose 0)': the largest per-mode error over the fitted poses."""
    import numpy as np

    if result.axes != "y":  # name the mode by its kind: the table numbers every truth mode
        from ..fitting.mode_records import worst_record

        r = worst_record(result.modes)
        return (f"worst mode {r['error_pct']:+.3g} % ({r['kind']}, "
                f"{r['omega_truth_rad_s']:.6g} rad/s)")
    e = np.asarray(result.omega_errors_pct)
    i, k = np.unravel_index(int(np.argmax(np.abs(e))), e.shape)
    where = f"mode {k + 1}" + (f", pose {i}" if e.shape[0] > 1 else "")
    return f"worst mode {e[i, k]:+.3g} % ({where})"


def export_text(result) -> str:
    """Return the exported model: which springs, and its frequencies and errors at q = 0."""
    w = " ".join(f"{v:.6g}" for v in result.omega_export_rad_s)
    e = " ".join(f"{v:+.3g}" for v in result.omega_export_errors_pct)
    where = "at the straight pose" if result.gravity_m_s2 is None else "about its sag"
    return (f"exported model: {result.stiffness_pose}\n"
            f"  {where}: omega {w} rad/s; errors {e} % "
            f"(worst {result.worst_export_error_pct:.3g} %)")


def modes_table(result) -> str:
    """Return the per-mode table of a fit by kind: truth and model rad/s, error %, MAC.

    A truth mode no chain mode represents (``chordwise``) shows ``-`` for the model; the MAC
    column (the pair's shape agreement) appears when the pairs were made by shape.
    """
    mac = any("mac" in r for r in result.modes)
    lines = [f"{'mode':>4}  {'kind':<10} {'truth rad/s':>12} {'model rad/s':>12} {'error %':>9}"
             + (f" {'MAC':>5}" if mac else "")]
    for i, r in enumerate(result.modes, 1):
        if r["omega_model_rad_s"] is None:
            model, err = f"{'-':>12}", f"{'not modelled':>12}"
        else:
            model, err = f"{r['omega_model_rad_s']:12.6g}", f"{r['error_pct']:+9.3g}"
        shape = f" {r['mac']:5.3f}" if "mac" in r else ""
        lines.append(f"{i:>4}  {r['kind']:<10} {r['omega_truth_rad_s']:12.6g} {model} {err}"
                     f"{shape}")
    return "\n".join(lines)


def print_warnings(result) -> None:
    """Every note of a FitResult as one 'fit warning:' line on stderr."""
    for note in result.warnings:
        print(f"fit warning: {note}", file=sys.stderr)


# the files a fit writes into its folder (the knee of a Pareto fit too)
FIT_FILES = ("fit.json", "model.urdf", "planform.png", "scf.png")


def write_fit_outputs(result, beam, out: Path, plots: bool = True) -> list[Path]:
    """Write fit.json, model.urdf and the plots of a FitResult into ``out`` as one set.

    With ``output_folder``, an earlier fit's files there are replaced all together; other files
    are kept.

    model.urdf is what ``prbdm export fit.json --format urdf`` writes: fit.json's
    ``stiffness_Nm_per_rad``, 2 % stiffness-proportional joint damping, and the record comment
    (its frequencies at the straight pose, its per-mode errors against ``omega_truth_rad_s``).
    """
    from ..io.output_folder import output_folder

    out = Path(out)
    with output_folder(out, FIT_FILES, marker="fit.json") as stage:
        written = write_fit_files(result, beam, stage, plots)
    return [out / p.name for p in written]


def write_fit_files(result, beam, folder: Path, plots: bool = True) -> list[Path]:
    """Write the files of :func:`write_fit_outputs` into ``folder`` (each atomically)."""
    from ..files.export import write_urdf
    from ..model.prbdm_model import build_model
    from ..options.choices import MIN_FRACTION

    out = folder
    out.mkdir(parents=True, exist_ok=True)
    lengths = result.lengths_m
    # the fit's own bound may be below Eq. 15's default (--min-link)
    model = build_model(beam, lengths, result.stiffness_Nm_per_rad,
                        min_fraction=min(MIN_FRACTION, 0.5 * float(min(lengths)) / beam.length_m),
                        axes=result.axes)
    written = [write_urdf(model, out / "model.urdf",
                          omega_truth_rad_s=result.omega_truth_rad_s,
                          gravity_m_s2=result.gravity_m_s2)]
    if plots:
        from ..views.plots import plot_planform, plot_scf

        plot_planform(beam, result.lengths_m, out / "planform.png",
                      title=f"{beam.name}: {result.joints}R, {result.stiffness}, "
                            f"{result.objective}")
        written.append(out / "planform.png")
        if result.stiffness == "paper":
            plot_scf(result, out / "scf.png")
            written.append(out / "scf.png")
    # fit.json last: its presence marks a complete output folder
    from ..files.fit_file import save_fit

    written.append(save_fit(result, out / "fit.json", beam))
    return written


def check_options(args) -> None:
    """Refuse bad ``prbdm fit`` options before any file is read or truth computed."""
    from .checks import MAX_WORKERS, in_range

    check_truth_options(args)
    in_range("--starts", args.starts, 1, MAX_STARTS, integer=True)
    in_range("--workers", args.workers, 1, MAX_WORKERS, integer=True)
    in_range("--loss-tol", args.loss_tol, 0.0, unit="%")
    in_range("--polish", args.polish, 0, MAX_STARTS, integer=True)
    in_range("--max-nfev", args.max_nfev, 1, MAX_NFEV, integer=True)
    in_range("--explore-nfev", args.explore_nfev, 1, MAX_NFEV, integer=True)
    in_range("--refine-starts", args.refine_starts, 0, MAX_STARTS, integer=True)
    check_sweep(args)
    gravity_option(args)  # refused before any truth is computed


def run(args) -> int:
    """Run ``prbdm fit`` (exit code 0 on success)."""
    from ..files.beam_file import load_beam
    from ..fitting import fit

    check_options(args)
    beam = load_beam(args.beam)
    min_fraction = check_inputs(args, beam, args.objective)
    options = fit_options(args, min_fraction)  # refused before the truth is computed
    target = load_target(args, beam)
    result = fit(beam, target, args.joints, options, workers=args.workers,
                 progress=not args.quiet)
    out = Path(args.out)
    write_fit_outputs(result, beam, out)
    if not args.quiet:
        print_warnings(result)
        if result.axes != "y":
            tip = "" if result.objective == "eigen" else (
                f", tip and twist {result.deflection_loss_pct:.4g} %, combined "
                f"{result.combined_loss_pct:.4g} %")
            print(f"{result.joints}R {result.axes} {result.stiffness} {result.objective}: eigen "
                  f"({result.eigen_norm} norm) {result.eigen_loss_pct:.4g} %, "
                  f"{worst_mode_text(result)}{tip} ({result.wall_time_s:.1f} s)")
        else:
            print(f"{result.joints}R {result.stiffness} {result.objective}: "
                  f"eigen ({result.eigen_norm} norm) {result.eigen_loss_pct:.4g} %, "
                  f"{worst_mode_text(result)}, "
                  f"tip position {result.deflection_loss_pct:.4g} %, "
                  f"tip displacement {result.displacement_loss_pct:.4g} %, "
                  f"combined {result.combined_loss_pct:.4g} % ({result.wall_time_s:.1f} s)")
        print("lengths_m:", " ".join(f"{v:.4f}" for v in result.lengths_m))
        if result.gravity_m_s2 is not None:
            print("in gravity_m_s2:", " ".join(f"{v:g}" for v in result.gravity_m_s2),
                  "(frequencies about the sag, tip under the load and the weight)")
        if result.axes != "y":
            print(modes_table(result))
        print(export_text(result))
        print(f"wrote {out / 'fit.json'}")
    return 0
