"""Dynamic accuracy of fitted PRBDMs against the plate truth, for both eigen norms.

For 3R, 4R and 5R models (joint and paper springs; eigen and combined objectives; the paper's
Eq. 16 eigen norm and the relative per-mode norm) this fits the model to the Kirchhoff-plate
truth (cached) of each beam, then compares the exported model's tip response to a unit step tip
load over the first second and the tip FRF over [0, 1.2 omega_5] with the truth's modal
superposition (every plate mode up to the fifth selected bending mode, 2 % modal damping on
both sides). The exported model is what model.urdf carries: the fitted joint springs, or for
paper fits the springs of sweep pose 0. Writes results/dynamic_accuracy.md, with a last table
of the mean errors per norm (the choice of ``objectives.DEFAULT_EIGEN_NORM``).

usage: python scripts/dynamic_accuracy.py [--beams examples/beams/reference-random.json,...]
       [--joints 3,4,5] [--stiffness joint,paper] [--starts 16] [--out results/dynamic_accuracy.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.fitting import fit  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from docs_tables import write_table  # noqa: E402

from prbdm_pin.fitting.target import target_from_truth  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.simulation.response import (  # noqa: E402
    centerline_modal_tip,
    dynamic_accuracy,
    truth_modal_tip,
)
from prbdm_pin.truth import compute_truth  # noqa: E402

BEAMS = ("examples/beams/reference-random.json", "examples/beams/tapered.json")
NORMS = ("paper", "relative")


def beam_rows(path: str, args, joints: list[int], stiffness: list[str], rows: list) -> list[str]:
    """The table lines of one beam (and its rows, appended to ``rows``)."""
    beam = load_beam(path)
    truth = compute_truth(beam, modes=5, cache_dir=args.cache_dir)
    target = target_from_truth(truth, beam.tip_force_N)
    ref = truth_modal_tip(truth, beam)
    # truncation of the superposition: its static limit against the plate's linear static solve
    static = float(truth.static_linear.tip_displacement_m[2] / beam.tip_force_N[2])
    every = centerline_modal_tip(truth.modal, beam)
    lines = [
        f"## {beam.name}",
        "",
        f"Truth: plate, mesh level {truth.mesh_level}, bending modes (rad/s) "
        + ", ".join(f"{w:.1f}" for w in truth.omega_rad_s)
        + f"; superposition of plate modes 1-{ref.omega_rad_s.size} with their finite-element "
        f"modal masses. Static limit of the superposition: "
        f"{ref.static_compliance_m_per_N / static - 1:+.2e} relative to the plate's linear "
        f"static solve (the modes above the last superposed one carry the rest; all "
        f"{every.omega_rad_s.size} computed modes: "
        f"{every.static_compliance_m_per_N / static - 1:+.2e}).",
        "",
        "| model | springs | objective | eigen norm | eigen loss (%) | worst mode, fitted (%) "
        "| worst mode, exported (%) | step error (%) | FRF error (%) "
        "| FRF magnitude error (%) | FRF phase error (rad, rms) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for n in joints:
        for kind in stiffness:
            for objective in ("eigen", "combined"):
                for norm in NORMS:
                    r = fit(beam, target, n, objective=objective, stiffness=kind,
                            starts=args.starts, seed=0, progress=False, eigen_norm=norm)
                    model = build_model(beam, r.lengths_m, r.stiffness_Nm_per_rad)
                    acc = dynamic_accuracy(model, ref, damping_ratio=args.damping)
                    rows.append((beam.name, n, kind, objective, norm, acc.step_error,
                                 acc.frf_error, r.worst_export_error_pct))
                    lines.append(
                        f"| {n}R | {kind} | {objective} | {norm} | {r.eigen_loss_pct:.4g} | "
                        f"{r.worst_mode_error_pct:.3g} | {r.worst_export_error_pct:.3g} | "
                        f"{100 * acc.step_error:.3g} | {100 * acc.frf_error:.3g} | "
                        f"{100 * acc.frf_magnitude_error:.3g} | {acc.frf_phase_error_rad:.3g} |")
                    print(lines[-1], flush=True)
    return lines + [""]


def summary(rows: list) -> list[str]:
    """Mean step and FRF errors (%) and worst exported mode per springs kind and norm, over the
    beams, models and objectives; and how often each norm gave the better step response."""
    lines = ["## Summary: mean over beams, models and objectives", "",
             "| springs | eigen norm | fits | mean step error (%) | mean FRF error (%) "
             "| mean worst exported mode (%) | better step response (fits) |",
             "|---|---|---|---|---|---|---|"]
    for kind in sorted({r[2] for r in rows}):
        for norm in NORMS:
            sel = [r for r in rows if r[2] == kind and r[4] == norm]
            other = {r[:4]: r for r in rows if r[2] == kind and r[4] != norm}
            wins = sum(r[5] < other[r[:4]][5] for r in sel if r[:4] in other)
            lines.append(
                f"| {kind} | {norm} | {len(sel)} | {100 * np.mean([r[5] for r in sel]):.3g} | "
                f"{100 * np.mean([r[6] for r in sel]):.3g} | "
                f"{np.mean([r[7] for r in sel]):.3g} | {wins} |")
    return lines + [""]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beams", default=",".join(str(ROOT / b) for b in BEAMS))
    ap.add_argument("--joints", default="3,4,5")
    ap.add_argument("--stiffness", default="joint,paper")
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--damping", type=float, default=0.02)
    ap.add_argument("--cache-dir", default=str(ROOT / "results" / "truth-cache"))
    ap.add_argument("--out", default=str(ROOT / "results" / "dynamic_accuracy.md"))
    args = ap.parse_args()
    joints = [int(v) for v in args.joints.split(",")]
    stiffness = args.stiffness.split(",")
    lines = [
        "# Dynamic accuracy against the plate truth: eigen norm paper (Eq. 16) and relative",
        "",
        f"Modal damping {args.damping} on both sides, {args.starts} starts, seed 0. Step: "
        "relative L2 error of the tip displacement under a unit step tip force over the first "
        "second; FRF: relative L2 error of the complex tip receptance over [0, 1.2 omega_5]. "
        "The model is the exported one (model.urdf): joint springs, or paper springs of sweep "
        "pose 0; worst mode: max |omega_model / omega_truth - 1| over the fitted poses, and of "
        "the exported model at the straight pose.",
        "",
    ]
    rows: list = []
    for path in args.beams.split(","):
        lines += beam_rows(path, args, joints, stiffness, rows)
    lines += summary(rows)
    print("\n".join(summary(rows)))
    write_table(args.out, "\n".join(lines) + "\n", ap.get_default("out"), "dynamic_accuracy")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
