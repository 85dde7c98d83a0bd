"""Benchmark: many designs at once (``simulate_batch``, ``frequencies_batch``, ``linearize_batch``)
against one design at a time.

Writes results/bench_batch_simulate.md and, with the default ``--out``, the same table to
docs/benchmarks/bench_batch_simulate.md (the benchmarks page includes it). BLAS on one thread
(set before numpy is imported), CPU time (process time), the best of ``--repeats`` for a batch
and of five times as many for a single run (a shared machine only ever adds time).

The designs: the finite-segment 5R chain of the reference random beam (springs E / int dx/I),
its B springs each scaled by a factor drawn uniformly in [0.8, 1.2] (seed 0). The load: a step
tip force of 2500 N along -z from rest, 1 s simulated, 1 ms output; undamped and with modal
damping 0.02. The error of a run: the largest tip-z deviation over the peak tip-z displacement,
against ``simulate(method="DOP853", rtol=1e-11)`` of the same design; for a batch, the largest
over ``--checks`` designs (the softest and stiffest highest mode and others drawn at random).

Rows: one design through ``simulate`` at a sweep of settings (the exponential integrator's
``step_rtol``, DOP853's and the compiled DOP853's ``rtol``, the latter over the batch's range),
and the batch through ``simulate_batch`` at a sweep of ``rtol`` (its steps: the most any
block of designs took); the cheapest of each reaching 0.1 % (the issue's
target: the batch of 1,000 at most 100 times the cheapest single run). Then the frequencies
and the linear plants of the B designs at the straight pose: the batched call against a loop
of ``model.natural_frequencies()`` and of ``linearize(model)``.

usage: python scripts/bench_batch_simulate.py [--designs 1000] [--repeats 2] [--checks 6]
       [--out results/bench_batch_simulate.md]
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.bench.run import finite_segment_chain  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / "results" / "bench_batch_simulate.md"
DOCS_OUT = ROOT / "docs" / "benchmarks" / "bench_batch_simulate.md"
FORCE = np.array([0.0, 0.0, -2500.0])  # N
TARGET = 1e-3  # 0.1 % of the peak
SINGLE = ([("exponential", {"integrator": pp.Exponential(step_rtol=r)}, f"step_rtol {r:g}")
           for r in (1e-3, 3e-4, 1e-4, 3e-5)]
          + [("DOP853", {"method": "DOP853", "rtol": r}, f"rtol {r:g}")
             for r in (1e-2, 1e-3, 1e-4)]
          # the compiled DOP853 (numba): the cheapest single run of an explicit scheme
          + [("compiled", {"integrator": pp.Compiled(rtol=r)}, f"rtol {r:g}")
             for r in (3e-2, 1e-2, 1e-3, 1e-4, 1e-6)])
BATCH_RTOLS = (3e-2, 1e-2, 3e-3, 1e-3, 1e-4)


def cpu(f, repeats: int):
    """Best CPU time over ``repeats`` calls of f() (s), and the last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        c = time.process_time()
        out = f()
        best = min(best, time.process_time() - c)
    return best, out


def designs(count: int):
    beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    base = finite_segment_chain(beam, 5)
    scale = np.random.default_rng(0).uniform(0.8, 1.2, (count, base.n_joints))
    return [base.with_stiffness(base.stiffness_Nm_per_rad * s) for s in scale]


def tip_error(tip_z: np.ndarray, ref_z: np.ndarray) -> float:
    return float(np.abs(tip_z - ref_z).max() / np.abs(ref_z).max())


def simulation_rows(models, damping: float, repeats: int, checks: int):
    common = dict(tip_force=FORCE, output_dt_s=1e-3, damping_ratio=damping)
    top = pp.frequencies_batch(models)[:, -1]
    rng = np.random.default_rng(1)
    picks = [int(np.argmin(top)), int(np.argmax(top))]
    picks += [int(i) for i in rng.choice(len(models), checks - 2, replace=False)]
    refs = {}
    for i in dict.fromkeys([0, *picks]):
        r = pp.simulate(models[i], 1.0, method="DOP853", rtol=1e-11, **common)
        refs[i] = r.tip_displacement_m[:, 2]
    rows = []
    pp.simulate(models[0], 0.01, **common, method="compiled")  # numba's cache, loaded once
    for name, kw, setting in SINGLE:
        # a single run lasts 15-60 ms: more repeats for its best (the others' load on a shared
        # machine shows in a short run's figure more than in the batch's seconds)
        t, run = cpu(lambda kw=kw: pp.simulate(models[0], 1.0, **common, **kw), 5 * repeats)
        rows.append(("one design", name, setting, t, tip_error(run.tip_displacement_m[:, 2],
                                                                refs[0]), run.steps))
    pp.simulate_batch(models[:2], 0.01, **common, rtol=1e-3)  # numba's cache, loaded once
    for rtol in BATCH_RTOLS:
        t, run = cpu(lambda r=rtol: pp.simulate_batch(models, 1.0, **common, rtol=r), repeats)
        err = max(tip_error(run.tip_displacement_m[i, :, 2], refs[i]) for i in picks)
        rows.append((f"{len(models)} designs", "simulate_batch (DOP853)", f"rtol {rtol:g}", t,
                     err, int(run.steps.max())))
    return rows


def linear_rows(models, repeats: int):
    rows = []
    t_loop, w_loop = cpu(lambda: np.array([m.natural_frequencies() for m in models]), repeats)
    t_batch, w = cpu(lambda: pp.frequencies_batch(models), repeats)
    diff = float(np.abs(w / w_loop - 1.0).max())
    rows.append(("frequencies", t_loop, t_batch, diff))
    if hasattr(pp, "linearize_batch"):
        kw = dict(inputs=("tip_force_z", "joint_torque[0]"), outputs=("tip_z", "q[0]"))
        t_loop, lin_loop = cpu(lambda: [pp.linearize(m, **kw) for m in models], repeats)
        t_batch, lin = cpu(lambda: pp.linearize_batch(models, **kw), repeats)
        diff = max(float(np.abs(a.A - b.A).max() / np.abs(b.A).max())
                   for a, b in zip(lin, lin_loop, strict=True))
        rows.append(("linearize", t_loop, t_batch, diff))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=1000)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--checks", type=int, default=6)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    args = ap.parse_args()
    models = designs(args.designs)
    lines = ["# Many designs at once", "",
             f"{platform.processor() or platform.machine()}, numpy {np.__version__}, BLAS on "
             f"one thread, CPU time, best of {args.repeats} (a single run: of "
             f"{5 * args.repeats}); 5R finite-segment chain of the "
             f"reference random beam, {args.designs} designs (springs x U[0.8, 1.2]), step "
             "tip load 2500 N, 1 s, 1 ms output.", ""]
    for damping in (0.0, 0.02):
        rows = simulation_rows(models, damping, args.repeats, args.checks)
        ok = [r for r in rows if r[4] <= TARGET]
        one = min((r for r in ok if r[0] == "one design"), key=lambda r: r[3])
        many = min((r for r in ok if r[0] != "one design"), key=lambda r: r[3])
        lines += [f"## Damping ratio {damping:g}", "",
                  "| run | integrator | setting | CPU s | tip error / peak | steps |",
                  "|---|---|---|---:|---:|---:|"]
        lines += [f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.3g} | {r[4]:.2e} | {r[5]} |"
                  for r in rows]
        lines += ["", f"Cheapest at 0.1 %: one design {one[3]:.3g} s ({one[1]}, {one[2]}), "
                  f"{args.designs} designs {many[3]:.3g} s ({many[2]}): **{many[3] / one[3]:.1f}x"
                  "** the one (target <= 100x); per design "
                  f"{many[3] / args.designs / one[3]:.3f} of a single run.", ""]
        print("\n".join(lines[-(len(rows) + 5):]), flush=True)
    lines += ["## Frequencies and linear plants at the straight pose", "",
              f"| what | loop over {args.designs} designs, s | batched, s | speed-up | "
              "largest relative difference |", "|---|---:|---:|---:|---:|"]
    lines += [f"| {r[0]} | {r[1]:.3g} | {r[2]:.3g} | {r[1] / r[2]:.1f}x | {r[3]:.1e} |"
              for r in linear_rows(models, args.repeats)]
    text = "\n".join(lines) + "\n"
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(args.out, text)
    if args.out == DEFAULT_OUT:
        atomic_write_text(DOCS_OUT, text)


if __name__ == "__main__":
    main()
