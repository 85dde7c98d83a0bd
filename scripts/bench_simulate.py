"""Benchmark: wall time per simulated second of PRBDM step responses (1R ... 8R), with damping.

Writes results/bench_simulate.md. BLAS is pinned to one thread before numpy is imported.
Models: the reference random beam cut into near-equal links (half links at both ends) with the
finite-segment springs; every run is a 2500 N step tip load from rest with modal damping 0.02.
Next to them: a 32-link finite-segment chain (a finer chain, more accurate frequencies) and the
modal-superposition transient of the 1D beam truth (closed form per mode).
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.geometry import atomic_write_text, load_beam  # noqa: E402
from prbdm_pin.model import build_model  # noqa: E402
from prbdm_pin.response import centerline_modal_tip, modal_step_response  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402
from prbdm_pin.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.truth.beam import beam_modal  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def chain(beam, n):
    lengths = np.r_[0.5, np.ones(n - 1), 0.5] * beam.length_m / n
    frac = min(0.02, 0.25 / n)
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths, frac),
                       min_fraction=frac)


def best_of(fn, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time, s")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_simulate.md"))
    args = ap.parse_args()
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    force = beam.tip_force_N
    modal = beam_modal(beam, n_modes=8)
    rows = []
    for n in list(range(1, 9)) + [32]:
        model = chain(beam, n)
        omega = model.natural_frequencies()
        for method, kw in (("trapezoidal", {}), ("DOP853", {"rtol": 1e-8})):
            if method == "DOP853" and n not in (1, 5):
                continue
            dur = args.duration if n <= 8 else 0.2 * args.duration

            def run(model=model, method=method, kw=kw, dur=dur):
                return simulate(model, dur, tip_force=force, damping_ratio=0.02,
                                method=method, output_dt=1e-3, **kw)

            _, tr = best_of(run, 1 if method == "DOP853" else args.repeats)
            wall = tr.wall_time_s
            err = omega[: min(n, 5)] / modal.omega_rad_s[: min(n, 5)] - 1
            rows.append((f"{n}R chain", method, tr.steps / dur, wall / dur, dur / wall,
                         float(np.max(np.abs(err))), float(omega[-1])))
    # modal superposition of the truth (5 modes), 1 ms samples over the duration
    tip = centerline_modal_tip(modal, beam, np.arange(5))
    t = np.arange(0.0, args.duration + 5e-4, 1e-3)
    wall, _ = best_of(lambda: modal_step_response(tip, t, 0.02), args.repeats)
    rows.append(("beam truth, 5 modes", "modal superposition", float("nan"),
                 wall / args.duration, args.duration / wall, 0.0, float(tip.omega_rad_s[-1])))

    lines = [
        "# Simulation speed: wall time per simulated second",
        "",
        f"Step tip load {force.tolist()} N on the reference random beam, modal damping 0.02, "
        f"1 ms output; best of {args.repeats} (DOP853: one run); BLAS 1 thread; "
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}.",
        "Frequency error: max relative error of the chain's first min(n, 5) frequencies against "
        "the 1D beam truth (finite-segment springs, not a fitted model).",
        "",
        "| model | method | steps per s | wall s per simulated s | x real time | "
        "frequency error | omega_max (rad/s) |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for name, method, sps, w, x, fe, om in rows:
        sps_s = "" if np.isnan(sps) else f"{sps:.0f}"
        lines.append(f"| {name} | {method} | {sps_s} | {w:.4f} | {x:.1f} | {fe:.2%} | {om:.0f} |")
    text = "\n".join(lines) + "\n"
    atomic_write_text(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
