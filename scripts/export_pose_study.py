"""Which springs should a ``paper`` fit export? Straight-pose per-mode errors of three choices.

A ``paper`` fit has one SCF per pose of the sweep (Eq. 14), so a single spring set has to be
chosen for model.urdf and every export. For 3R-5R fits (eigen and combined objectives, both
eigen norms) to the plate truth this compares the exported model's own frequencies at the
straight pose q = 0 (Pinocchio, the lengths of the fit) against the truth for

- ``scf_mean``: SCF_mean (Eq. 25) times Eq. 14, what fit.json exported before (a spring set
  that no pose was fitted with);
- ``pose 0``: the springs fitted at the sweep's first pose (every joint at xi = 0.05 rad), the
  pose nearest straight (what fit.json exports now);
- ``rescaled``: Eq. 14 springs with the one SCF that best matches the truth at q = 0 in the
  fit's own eigen norm (``objectives.best_scale`` at q = 0).

Writes results/export_pose.md.

usage: python scripts/export_pose_study.py [--beams examples/beams/reference-random.json,...]
       [--joints 3,4,5] [--starts 16] [--out results/export_pose.md]
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
from prbdm_pin.fitting.objectives import best_scale, mode_errors_pct  # noqa: E402
from prbdm_pin.fitting.target import target_from_truth  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.truth import TruthRequest  # noqa: E402

BEAMS = ("examples/beams/reference-random.json", "examples/beams/tapered.json")


def straight_errors(beam, r, springs) -> np.ndarray:
    """Signed per-mode errors (%) of the model with ``springs`` at q = 0."""
    model = build_model(beam, r.lengths_m, springs)
    w = model.natural_frequencies(np.zeros(r.joints))
    return mode_errors_pct(w, r.omega_truth_rad_s)[0]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beams", default=",".join(str(ROOT / b) for b in BEAMS))
    ap.add_argument("--joints", default="3,4,5")
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--cache-dir", default=str(ROOT / "results" / "truth-cache"))
    ap.add_argument("--out", default=str(ROOT / "results" / "export_pose.md"))
    args = ap.parse_args()
    joints = [int(v) for v in args.joints.split(",")]
    lines = [
        "# Straight-pose per-mode errors of a paper fit's exported springs",
        "",
        "Plate truth (default mesh level), paper stiffness (Eq. 14), sweep xi = 0.05, "
        f"eps = 0.1 rad, {args.starts} starts, seed 0. Columns: the fit's loss in its norm and "
        "its worst per-mode error over the fitted poses; then, for each spring choice, the "
        "exported model's omega_1 error and worst per-mode error at q = 0 (signed, %).",
        "",
        "| beam | model | objective | norm | loss (%) | worst fitted (%) "
        "| scf_mean: w1 / worst | pose 0: w1 / worst | rescaled: w1 / worst |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for path in args.beams.split(","):
        beam = load_beam(path)
        request = TruthRequest(model="plate", modes=max(joints))
        truth = request.compute(beam, cache_dir=args.cache_dir)
        target = target_from_truth(truth, beam.tip_force_N, request)
        for n in joints:
            for objective in ("eigen", "combined"):
                for norm in ("paper", "relative"):
                    r = fit(beam, target, n, objective=objective, stiffness="paper",
                            starts=args.starts, seed=0, progress=False, eigen_norm=norm)
                    K0 = r.stiffness_per_pose_Nm_per_rad[0] / r.factors[0]
                    w0 = build_model(beam, r.lengths_m, K0).natural_frequencies(np.zeros(n))
                    k0 = best_scale(w0[None, : r.frequencies], r.omega_truth_rad_s,
                                    r.squared, norm)[0]
                    cells = []
                    for springs in (r.scf_mean * K0, r.stiffness_per_pose_Nm_per_rad[0],
                                    k0 * K0):
                        e = straight_errors(beam, r, springs)
                        cells.append(f"{e[0]:+.3f} / {np.max(np.abs(e)):.3f}")
                    lines.append(f"| {beam.name} | {n}R | {objective} | {norm} | "
                                 f"{r.eigen_loss_pct:.4g} | {r.worst_mode_error_pct:.3f} | "
                                 + " | ".join(cells) + " |")
                    print(lines[-1], flush=True)
    atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
