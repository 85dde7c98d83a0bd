"""Plate truth of a stepped beam: a true width step (two vertices at one station) against the
same beam with the step faked by a short ramp, and both against the exact stepped
Euler-Bernoulli frequencies. Writes results/width_step.md.

    PYTHONPATH=$PWD OMP_NUM_THREADS=1 python scripts/bench_width_step.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.io.atomic import atomic_write_text
from prbdm_pin.member.geometry import Beam
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.truth import compute_truth

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from stepped_eb import stepped_frequencies  # noqa: E402


def ramped(beam: Beam, ramp_m: float) -> Beam:
    x = beam.x_m.copy()
    for k in beam.step_index:
        x[k + 1] = x[k] + ramp_m
    return Beam(x, beam.half_width_m, beam.thickness_m, beam.material, beam.tip_force_N,
                f"{beam.name}-ramp", beam.description)


def _exact(beam: Beam) -> np.ndarray | None:
    """The exact two-segment Euler-Bernoulli frequencies of a beam with one step and constant
    width on either side, else None."""
    w = beam.half_width_m
    if beam.x_m.size != 4 or beam.step_index.tolist() != [1] or w[0] != w[1] or w[2] != w[3]:
        return None
    a, L, t = beam.x_m[1], beam.length_m, beam.thickness_m
    E, rho = beam.material.E_Pa, beam.material.rho_kg_m3
    return stepped_frequencies(4, a, L, E * 2 * w[0] * t**3 / 12, rho * 2 * w[0] * t,
                               E * 2 * w[2] * t**3 / 12, rho * 2 * w[2] * t)


def main() -> None:
    narrow = load_beam(Path(__file__).resolve().parent.parent
                       / "examples/beams/stepped-narrow.json")
    # a tapered steel panel (L 0.6 m, half-width 0.05 -> 0.02 m, t 5 mm) stepped at mid-span
    panel = Beam([0.0, 0.3, 0.3, 0.6], [0.05, 0.035, 0.025, 0.02], 0.005, name="stepped-panel")
    rows = ["| beam | planform | DOFs | mesh level | time (s) | f1..f4 vs exact stepped EB (%) |",
            "|---|---|---|---|---|---|"]
    for beam in (narrow, panel):
        ex = _exact(beam)
        for label, b in (("true step", beam), ("0.1 mm ramp", ramped(beam, 1e-4))):
            t0 = time.perf_counter()
            tr = compute_truth(b, model="plate", modes=4, static=False)
            dt = time.perf_counter() - t0
            err = "n/a" if ex is None else " ".join(
                f"{e:+.3f}" for e in 100 * (np.asarray(tr.omega_rad_s) / ex - 1))
            rows.append(f"| {beam.name} | {label} | {tr.modal.dofs} | {tr.modal.mesh_level} | "
                        f"{dt:.2f} | {err} |")
            print(rows[-1], flush=True)
    # the finite-segment PRBDM of the narrow strip (half links at both ends) against exact
    ex = _exact(narrow)
    rows += ["", "| finite-segment chain | f1..f4 vs exact stepped EB (%) |", "|---|---|"]
    for n in (10, 20, 40, 80):
        h = narrow.length_m / n
        lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
        K = finite_segment_stiffness(narrow, lengths, min_fraction=1e-3)
        w = build_model(narrow, lengths, K, min_fraction=1e-3).natural_frequencies()[:4]
        rows.append(f"| {n}R | " + " ".join(f"{e:+.4f}" for e in 100 * (w / ex - 1)) + " |")
        print(rows[-1], flush=True)
    out = Path("results") / "width_step.md"
    atomic_write_text(out, "# Plate truth of stepped beams: true step against a 0.1 mm ramp\n\n"
                      + "\n".join(rows) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
