"""Which per-mode error estimate of the plate truth is an honest bound at an acceptable cost.

For each beam (default: the reference panel, the square plate, the tapered panel) and the default
truth (Argyris, level 0, paper selection of 5 modes) this compares, per selected mode:

- the error against level 2 (the same modes on the twice-refined nested mesh, matched by MAC);
- the estimate ``compute_truth`` reports: twice the change to level 1, floored at 0.01 %;
- the Argyris/Morley bracket on the same mesh, (omega_Argyris - omega_Morley) / omega_Argyris,
  a guaranteed bound (Argyris from above, Morley from below) that needs no second mesh;

and the CPU time (``time.process_time``) of the default ``compute_truth`` with and without the
estimate (the next-level solve), of a Morley solve on the same mesh, and of the level-2 solve.

Usage: python scripts/truth_error_estimate.py [BEAM.json ...] [--out PATH]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from unittest import mock  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.truth import compute_modal, compute_truth, estimate  # noqa: E402
from prbdm_pin.truth.modes import mac_matrix  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
NAMES = ["reference-random", "square-plate", "tapered-linear"]


def _match(coarse, index, fine) -> np.ndarray:
    n0 = coarse.node_uz.shape[1]
    return mac_matrix(coarse.node_uz[index], fine.node_uz[:, :n0]).argmax(axis=1)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("beams", nargs="*")
    ap.add_argument("--out", default=str(ROOT / "results" / "truth_error_estimate.md"))
    args = ap.parse_args()
    paths = [Path(p) for p in args.beams] or [ROOT / "examples" / "beams" / f"{n}.json"
                                               for n in NAMES]
    rows = ["| beam | mode | omega rad/s | label | error vs level 2 % | estimate % "
            "| Argyris/Morley bracket % | 1D gap % | cause |",
            "|---|---|---|---|---|---|---|---|---|"]
    cost = ["| beam | default truth CPU s, before (no estimate) | after (with estimate) "
            "| Morley same mesh CPU s | level 2 CPU s |", "|---|---|---|---|---|"]
    for path in paths:
        beam = load_beam(path)
        with mock.patch.object(estimate, "next_level_modal", lambda *a, **k: None):
            c = time.process_time()
            compute_truth(beam, error_tol_pct=None)
            before = time.process_time() - c
        c = time.process_time()
        r = compute_truth(beam, error_tol_pct=None)
        after = time.process_time() - c
        c = time.process_time()
        morley = compute_modal(beam, "plate-morley", r.mesh_level, 25)
        t_m = time.process_time() - c
        c = time.process_time()
        fine = compute_modal(beam, "plate", r.mesh_level + 2, 25)
        t_f = time.process_time() - c
        j = _match(r.modal, r.mode_index, fine)
        true = 100 * np.abs(r.omega_rad_s / fine.omega_rad_s[j] - 1)
        jm = _match(r.modal, r.mode_index, morley)
        bracket = 100 * (r.omega_rad_s - morley.omega_rad_s[jm]) / r.omega_rad_s
        for k, i in enumerate(r.mode_index):
            rows.append(f"| {beam.name} | {k + 1} | {r.omega_rad_s[k]:.6g} | {r.labels[i]} "
                        f"| {true[k]:.2e} | {r.error_estimate_pct[k]:.3g} | {bracket[k]:.3g} "
                        f"| {r.beam_gap_pct[k]:+.2f} | {r.beam_gap_cause[k]} |")
            print(rows[-1], flush=True)
        cost.append(f"| {beam.name} | {before:.1f} | {after:.1f} | {t_m:.1f} | {t_f:.1f} |")
        print(cost[-1], flush=True)
    text = ("# Error estimate of the plate truth (Argyris, level 0, 5 modes, paper selection)\n\n"
            "Produced by scripts/truth_error_estimate.py. Bracket: needs no second mesh but is "
            "the Morley error, not the Argyris one.\n\n" + "\n".join(rows) + "\n\n## Cost\n\n"
            + "\n".join(cost) + "\n")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
