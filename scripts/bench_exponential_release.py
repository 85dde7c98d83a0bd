"""Benchmark: accuracy and cost of the default exponential integrator on releases and step loads.

Writes results/bench_exponential_release.md. BLAS is pinned to one thread before numpy is
imported. Every run is 1 s simulated, 1 ms output, the reference beam; the tip error is the max
|tip - DOP853 tip| (rtol 1e-10) over the run relative to the peak tip deflection. CPU time is the
process time of the whole ``simulate`` call, best of ``--repeats``.

Rows:
- Releases: q0 = 0.1 rad on every joint, v0 = 0, no force, undamped and with modal damping 0.02,
  on the 3R and 5R finite-segment chains (links L/2N, L/N, ..., L/2N) and the 5R chain with six
  equal links. Uniform joint angles are a constant-curvature shape, not a mode: 15-20 % of the
  tip motion is in modes 2 and up.
- Step loads (the ``scripts/bench_simulate.py`` PRBDM rows without the fitted model): the beam
  file's 2500 N tip force along -z from rest, modal damping 0.02, finite-segment chains 1R ... 8R
  and the 5R equal-link chain.
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.bench.run import finite_segment_chain  # noqa: E402
from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.errors import SolveError  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUTPUT_DT_S = 1e-3


def best_cpu(fn, repeats: int):
    """Best process CPU time of ``fn()`` over ``repeats`` runs, s, and the last result."""
    cpu, out = np.inf, None
    for _ in range(repeats):
        c0 = time.process_time()
        out = fn()
        cpu = min(cpu, time.process_time() - c0)
    return cpu, out


def row(name: str, model, duration_s: float, repeats: int, **scene) -> str:
    """One table line: the default exponential run and DOP853 (rtol 1e-10) on one scene."""
    ref_cpu, ref = best_cpu(lambda: simulate(model, duration_s, method="DOP853", rtol=1e-10,
                                             output_dt_s=OUTPUT_DT_S, **scene), 1)
    try:
        cpu, tr = best_cpu(lambda: simulate(model, duration_s, output_dt_s=OUTPUT_DT_S, **scene),
                           repeats)
    except SolveError as exc:
        line = f"| {name} | SolveError: {exc} | | | | | {1e3 * ref_cpu / duration_s:.0f} |"
        print(line, flush=True)
        return line
    peak = float(np.abs(ref.tip_displacement_m).max())
    err = float(np.abs(tr.tip_position_m - ref.tip_position_m).max()) / peak
    line = (f"| {name} | {err:.2e} | {tr.steps / duration_s:.0f} | "
            f"{tr.rhs_evaluations / duration_s:.0f} | {tr.jacobian_updates / duration_s:.0f} | "
            f"{1e3 * cpu / duration_s:.1f} | {1e3 * ref_cpu / duration_s:.0f} |")
    print(line, flush=True)
    return line


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time, s")
    ap.add_argument("--repeats", type=int, default=3, help="best of this many runs")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_exponential_release.md"))
    args = ap.parse_args()
    load_start = os.getloadavg()
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    dur = args.duration
    equal = np.full(6, beam.length_m / 6)
    chain5_equal = build_model(beam, equal, finite_segment_stiffness(beam, equal))
    header = ["| scene | tip error | steps per s | dynamics evaluations per s | "
              "decompositions per s | CPU ms per s | DOP853 CPU ms per s |",
              "|---|---:|---:|---:|---:|---:|---:|"]
    lines = ["# Default exponential integrator: releases and step loads against DOP853", "",
             f"1 s simulated (here {dur:g} s), 1 ms output, best of {args.repeats} (DOP853: one "
             "run); tip error relative to the peak deflection. Load average at the start "
             f"{load_start[0]:.2f}.", "", "## Releases from 0.1 rad on every joint, no force",
             ""] + header
    for label, model in (("3R chain", finite_segment_chain(beam, 3)),
                         ("5R chain", finite_segment_chain(beam, 5)),
                         ("5R equal links", chain5_equal)):
        q0 = np.full(model.n_joints, 0.1)
        for xi in (0.0, 0.02):
            lines.append(row(f"{label}, damping {xi}", model, dur, args.repeats, q0=q0,
                             damping_ratio=xi))
    lines += ["", f"## Step loads {beam.tip_force_N.tolist()} N from rest, modal damping 0.02",
              ""] + header
    models = [(f"{n}R chain", finite_segment_chain(beam, n)) for n in range(1, 9)]
    models.append(("5R equal links", chain5_equal))
    for label, model in models:
        lines.append(row(label, model, dur, args.repeats, tip_force=beam.tip_force_N,
                         damping_ratio=0.02))
    load_end = os.getloadavg()
    lines += ["", f"Load average at the end {load_end[0]:.2f}."]
    atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
