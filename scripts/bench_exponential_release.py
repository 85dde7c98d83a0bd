"""Benchmark: accuracy and cost of the exponential integrators (exprb32, exprb43) on releases and
step loads, against DOP853.

Writes results/bench_exponential_release.md. BLAS is pinned to one thread before numpy is
imported. Every run is 1 s simulated, 1 ms output, on the finite-segment chains (links L/2N,
L/N, ..., L/2N) of the reference beam, n = 1, 2, 3, 5, 8; the tip error is the max
|tip - DOP853 tip| (rtol 1e-11) over the run relative to the peak tip deflection. CPU time is
the process time of the whole ``simulate`` call, best of ``--repeats``.

Cases (the issue's): a release from 0.1 rad on every joint, v0 = 0, no force, and the beam
file's 2500 N tip force along -z from rest (a step load), each undamped and with modal damping
0.02. Uniform joint angles are a constant-curvature shape, not a mode: 15-20 % of the tip
motion is in modes 2 and up.

Settings: the default (exprb32 at step_rtol 3e-4: what every run took before exprb43 was
added, unchanged by it), exprb32 at 1e-5, exprb43 (``Exponential(order=4)``) at 3e-4 and 3e-5,
and DOP853 at rtol 1e-4 and 1e-6 for comparison.
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.bench.run import finite_segment_chain  # noqa: E402
from prbdm_pin.errors import SolveError  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.options.integrators import Exponential, ScipyIVP  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUTPUT_DT_S = 1e-3
REFERENCE = ScipyIVP("DOP853", rtol=1e-11)
SETTINGS = (
    ("exprb32, step_rtol 3e-4 (default, before)", Exponential()),
    ("exprb32, step_rtol 1e-5", Exponential(step_rtol=1e-5)),
    ("exprb43, step_rtol 3e-4", Exponential(order=4)),
    ("exprb43, step_rtol 3e-5", Exponential(order=4, step_rtol=3e-5)),
    ("DOP853, rtol 1e-4", ScipyIVP("DOP853", rtol=1e-4)),
    ("DOP853, rtol 1e-6", ScipyIVP("DOP853", rtol=1e-6)),
)


def best_cpu(fn, repeats: int):
    """Best process CPU time of ``fn()`` over ``repeats`` runs, s, and the last result."""
    cpu, out = np.inf, None
    for _ in range(repeats):
        c0 = time.process_time()
        out = fn()
        cpu = min(cpu, time.process_time() - c0)
    return cpu, out


def case_rows(name: str, model, duration_s: float, repeats: int, **scene) -> list[str]:
    """The table lines of one case: every setting against the DOP853 reference."""
    ref = simulate(model, duration_s, integrator=REFERENCE, output_dt_s=OUTPUT_DT_S, **scene)
    peak = float(np.abs(ref.tip_displacement_m).max())
    lines = []
    for label, integrator in SETTINGS:
        try:
            cpu, tr = best_cpu(lambda integrator=integrator: simulate(
                model, duration_s, integrator=integrator, output_dt_s=OUTPUT_DT_S, **scene),
                repeats)
        except SolveError as exc:
            lines.append(f"| {name} | {label} | SolveError: {exc} | | |")
            print(lines[-1], flush=True)
            continue
        err = float(np.abs(tr.tip_position_m - ref.tip_position_m).max()) / peak
        lines.append(f"| {name} | {label} | {err:.2e} | {tr.steps / duration_s:.0f} | "
                     f"{1e3 * cpu / duration_s:.1f} |")
        print(lines[-1], flush=True)
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time, s")
    ap.add_argument("--repeats", type=int, default=2, help="best of this many runs")
    ap.add_argument("--joints", default="1,2,3,5,8", help="chains, comma-separated joint counts")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_exponential_release.md"))
    args = ap.parse_args()
    cpu0, load_start = time.process_time(), os.getloadavg()
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    dur = args.duration
    joints = [int(j) for j in args.joints.split(",")]
    lines = ["# Exponential integrators on releases and step loads against DOP853", "",
             f"{dur:g} s simulated, 1 ms output, best of {args.repeats}; tip error relative to "
             "the peak deflection, against DOP853 at rtol 1e-11. Finite-segment chains of the "
             f"reference beam. Load average at the start {load_start[0]:.2f}.", "",
             "| case | integrator | tip error | steps per s | CPU ms per s |",
             "|---|---|---:|---:|---:|"]
    for n in joints:
        model = finite_segment_chain(beam, n)
        for xi in (0.0, 0.02):
            lines += case_rows(f"{n}R release, damping {xi}", model, dur, args.repeats,
                               q0=np.full(n, 0.1), damping_ratio=xi)
            lines += case_rows(f"{n}R step load, damping {xi}", model, dur, args.repeats,
                               tip_force=beam.tip_force_N, damping_ratio=xi)
    lines += ["", f"Load average at the end {os.getloadavg()[0]:.2f}; the script's CPU time "
              f"{time.process_time() - cpu0:.0f} s."]
    atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
