"""Benchmark: wall time per simulated second of PRBDM step responses (1R ... 8R), with damping.

Writes results/bench_simulate.md. BLAS is pinned to one thread before numpy is imported.
Models: the reference random beam cut into near-equal links (half links at both ends) with the
finite-segment springs, plus the 5R model with six equal links; every run is a 2500 N step tip
load from rest with modal damping 0.02, timed as a whole simulate() call (set-up, integration,
1 ms output), wall and CPU time, for the exponential integrator (default), Gauss-Legendre and
the trapezoidal rule. Next to them: the modal-superposition transient of the 1D beam truth
(closed form per mode).
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


def chain(beam, n, equal=False):
    lengths = (np.full(n + 1, 1.0 / (n + 1)) if equal
               else np.r_[0.5, np.ones(n - 1), 0.5] / n) * beam.length_m
    frac = min(0.02, 0.25 / n)
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths, frac),
                       min_fraction=frac)


def best_of(fn, repeats):
    """Best wall and best CPU (process) time of the whole call over ``repeats`` runs, s."""
    wall, cpu, out = np.inf, np.inf, None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu, out


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
    for n, equal in [(n, False) for n in range(1, 9)] + [(5, True)]:
        model = chain(beam, n, equal)
        omega = model.natural_frequencies()
        dur = args.duration
        # reference for the accuracy column: DOP853 at a tight tolerance
        ref = simulate(model, dur, tip_force=force, damping_ratio=0.02, method="DOP853",
                       rtol=1e-10, output_dt=1e-3)
        peak = float(np.abs(ref.tip_displacement_m).max())
        runs = (("exponential", {}), ("gauss", {}), ("gauss", {"steps_per_period": 20}),
                ("trapezoidal", {}))
        for method, kw in runs:
            def run(model=model, method=method, kw=kw, dur=dur):
                return simulate(model, dur, tip_force=force, damping_ratio=0.02,
                                method=method, output_dt=1e-3, **kw)

            wall, cpu, tr = best_of(run, args.repeats)
            err = omega[: min(n, 5)] / modal.omega_rad_s[: min(n, 5)] - 1
            tip_err = float(np.abs(tr.tip_position_m - ref.tip_position_m).max()) / peak
            label = method + ("" if not kw else f", {kw['steps_per_period']} steps/T1")
            name = f"{n}R chain" + (", equal links" if equal else "")
            rows.append((name, label, tr.steps / dur, tr.rhs_evaluations / tr.steps,
                         wall / dur, cpu / dur, dur / wall, dur / cpu, tip_err,
                         float(np.max(np.abs(err))), float(omega[-1])))
    # modal superposition of the truth (5 modes), 1 ms samples over the duration
    tip = centerline_modal_tip(modal, beam, np.arange(5))
    t = np.arange(0.0, args.duration + 5e-4, 1e-3)
    wall, cpu, _ = best_of(lambda: modal_step_response(tip, t, 0.02), args.repeats)
    rows.append(("beam truth, 5 modes", "modal superposition", float("nan"), float("nan"),
                 wall / args.duration, cpu / args.duration, args.duration / wall,
                 args.duration / cpu, float("nan"), 0.0, float(tip.omega_rad_s[-1])))

    lines = [
        "# Simulation speed: time per simulated second",
        "",
        f"Step tip load {force.tolist()} N on the reference random beam, modal damping 0.02, "
        f"1 ms output; whole simulate() call, best of {args.repeats}; BLAS 1 thread; "
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}; "
        f"load average at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores "
        "(shared machine: CPU time is the fairer speed).",
        "Tip error: max |tip - DOP853 (rtol 1e-10)| over the run, relative to the peak "
        "deflection. Frequency error: the chain's first min(n, 5) frequencies against the 1D "
        "beam truth (finite-segment springs, not a fitted model). Dynamics evaluations: RNEA "
        "residuals (gauss, trapezoidal; plus one ABA per step for gauss's dense output) or "
        "ABA and ABA derivatives (exponential).",
        "",
        "| model | method | steps per s | dynamics evaluations per step | wall s per s | "
        "CPU s per s | x real time (wall) | x real time (CPU) | tip error | frequency error | "
        "omega_max (rad/s) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, method, sps, eps, w, c, xw, xc, te, fe, om in rows:
        sps_s = "" if np.isnan(sps) else f"{sps:.0f}"
        eps_s = "" if np.isnan(eps) else f"{eps:.2f}"
        te_s = "" if np.isnan(te) else f"{te:.2%}"
        lines.append(f"| {name} | {method} | {sps_s} | {eps_s} | {w:.4f} | {c:.4f} | {xw:.1f} "
                     f"| {xc:.1f} | {te_s} | {fe:.2%} | {om:.0f} |")
    text = "\n".join(lines) + "\n"
    atomic_write_text(args.out, text)
    print(text)


if __name__ == "__main__":
    main()
