"""Dynamic accuracy of fitted PRBDMs against the plate truth on reference-random.json.

For 3R, 4R and 5R models with joint springs (eigen and combined objectives) this fits the model to
the Kirchhoff-plate truth (cached), then compares the tip response to a unit step tip load over the
first second and the tip FRF over [0, 1.2 omega_5] with the truth's modal superposition (every
plate mode up to the fifth selected bending mode, 2 % modal damping on both sides). Writes
results/dynamic_accuracy.md.

usage: python scripts/dynamic_accuracy.py [--beam examples/beams/reference-random.json]
       [--starts 16] [--out results/dynamic_accuracy.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.fitting import fit  # noqa: E402
from prbdm_pin.geometry import atomic_write_text, load_beam  # noqa: E402
from prbdm_pin.model import build_model  # noqa: E402
from prbdm_pin.problem import target_from_truth  # noqa: E402
from prbdm_pin.response import (  # noqa: E402
    centerline_modal_tip,
    dynamic_accuracy,
    truth_modal_tip,
)
from prbdm_pin.truth import compute_truth  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beam", default=str(ROOT / "examples" / "beams" / "reference-random.json"))
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--damping", type=float, default=0.02)
    ap.add_argument("--out", default=str(ROOT / "results" / "dynamic_accuracy.md"))
    args = ap.parse_args()
    beam = load_beam(args.beam)
    truth = compute_truth(beam, modes=5, cache_dir=ROOT / "results" / "truth-cache")
    target = target_from_truth(truth, beam.tip_force_N)
    ref = truth_modal_tip(truth, beam)
    # truncation of the superposition: its static limit against the plate's linear static solve
    static = float(truth.static_linear.tip_displacement_m[2] / beam.tip_force_N[2])
    every = centerline_modal_tip(truth.modal, beam)
    lines = [
        f"# Dynamic accuracy against the plate truth: {beam.name}",
        "",
        f"Truth: plate, mesh level {truth.mesh_level}, bending modes (rad/s) "
        + ", ".join(f"{w:.1f}" for w in truth.omega_rad_s)
        + f"; superposition of plate modes 1-{ref.omega_rad_s.size} with their finite-element "
        f"modal masses. Modal damping {args.damping} on both sides. Step: "
        "relative L2 error of the tip displacement under a unit step tip force over the first "
        "second; FRF: relative L2 error of the complex tip receptance over [0, 1.2 omega_5]. "
        f"Static limit of the superposition: {ref.static_compliance_m_per_N / static - 1:+.2e} "
        "relative to the plate's linear static solve (the modes above the last superposed one "
        f"carry the rest; all {every.omega_rad_s.size} computed modes: "
        f"{every.static_compliance_m_per_N / static - 1:+.2e}).",
        "",
        "| model | objective | eigen loss (%) | step error (%) | FRF error (%) "
        "| FRF magnitude error (%) | FRF phase error (rad, rms) |",
        "|---|---|---|---|---|---|---|",
    ]
    for joints in (3, 4, 5):
        for objective in ("eigen", "combined"):
            r = fit(beam, target, joints, objective=objective, stiffness="joint",
                    starts=args.starts, seed=0, progress=False)
            model = build_model(beam, r.lengths_m, r.stiffness_Nm_per_rad)
            acc = dynamic_accuracy(model, ref, damping_ratio=args.damping)
            lines.append(
                f"| {joints}R | {objective} | {r.eigen_loss_pct:.4g} | "
                f"{100 * acc.step_error:.3g} | {100 * acc.frf_error:.3g} | "
                f"{100 * acc.frf_magnitude_error:.3g} | {acc.frf_phase_error_rad:.3g} |")
            print(lines[-1], flush=True)
    atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
