"""Benchmark of the fits: wall time and loss of 3R/4R/5R eigen fits (64 starts, both
parametrisations) and of a 4R NSGA-II Pareto fit (population 100, 200 generations).

Writes results/bench_fit.md. BLAS is pinned to one thread before numpy is imported.

Truths (independent of the package's finite-element code, so the benchmark measures the fit only):
- reference-random.json: the prototype truth omega = 39.65, 333.8, 1018, 1974, 2800 rad/s;
- uniform-narrow.json: Euler-Bernoulli frequencies and the elastica tip at P L^2/EI = 1
  (retreat 0.056433 L, deflection 0.301721 L), used by the Pareto run.

usage: python scripts/bench_fit.py [--workers 2] [--starts 64] [--pop 100] [--generations 200]
       [--pareto-stiffness joint paper] [--out results/bench_fit.md]
       (``--pareto-stiffness`` with no value skips the Pareto runs)
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import resource  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.fitting import fit, fit_pareto  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from docs_tables import write_table  # noqa: E402

from prbdm_pin.fitting.target import FitTarget  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
REF_OMEGA = [39.65, 333.8, 1018.0, 1974.0, 2800.0]
BETA_L = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875,
                   14.137168391046, 17.278759532088])


def narrow_target(beam) -> FitTarget:
    b = 2 * beam.half_width_m[0]
    EI = beam.material.E_Pa * b * beam.thickness_m**3 / 12
    omega = BETA_L**2 * math.sqrt(EI / (beam.material.rho_kg_m3 * b * beam.thickness_m))
    L = beam.length_m
    tip = [L * (1 - 0.056433), 0.0, -0.301721 * L]
    return FitTarget(omega, beam.tip_force_N, tip, [-0.056433 * L, 0.0, -0.301721 * L],
                     source="Euler-Bernoulli + elastica table")


def cpu_s() -> float:
    """CPU time (s) of this process and of its finished children (the fit's worker pool)."""
    a = resource.getrusage(resource.RUSAGE_SELF)
    b = resource.getrusage(resource.RUSAGE_CHILDREN)
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--starts", type=int, default=64)
    ap.add_argument("--pop", type=int, default=100)
    ap.add_argument("--generations", type=int, default=200)
    ap.add_argument("--pareto-stiffness", nargs="*", default=["joint", "paper"])
    ap.add_argument("--paper-generations", type=int, default=None,
                    help="generations of the paper-parametrisation Pareto run (default: "
                         "--generations)")
    ap.add_argument("--eigen-norm", default="paper", choices=["paper", "relative"],
                    help="eigen norm of every fit (default paper: Eq. 16, comparable with the "
                         "paper's losses)")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_fit.md"))
    args = ap.parse_args()

    ref = load_beam(ROOT / "examples/beams/reference-random.json")
    narrow = load_beam(ROOT / "examples/beams/uniform-narrow.json")
    ref_target = FitTarget(REF_OMEGA, ref.tip_force_N, source="prototype truth")
    lines = [
        "# Fit benchmark",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}; BLAS pinned to 1 thread; workers = {args.workers}; "
        f"load average at start {os.getloadavg()[0]:.1f}.",
        "",
        "## Eigen fits, reference-random.json (prototype truth), "
        f"{args.starts} starts",
        "",
        "CPU = this process plus its worker processes (user + system). A machine shared with "
        "other jobs shows wall > CPU / workers; the load average is sampled before each row. "
        "Evaluations count every model evaluation (finite-difference stencils and the SLSQP "
        "polish of the paper fits included).",
        "",
        f"Eigen norm: {args.eigen_norm}. Worst mode: the largest |100 (omega_model / "
        "omega_truth - 1)| over the fitted poses and modes; exported: the same at the straight "
        "pose for the springs the fit exports.",
        "",
        "| stiffness | model | N | compared | wall (s) | CPU (s) | load | loss (%) | "
        "worst mode (%) | exported worst mode (%) | "
        "evaluations | CPU per evaluation (ms) | starts within 1e-3 rel. of best |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    cases = [("joint", n, n, False) for n in (3, 4, 5)]
    cases += [("paper", n, n, sq) for n in (3, 4, 5) for sq in (True, False)]
    cases += [("paper", 4, 3, True)]
    for stiffness, n, N, sq in cases:
        load = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), cpu_s()
        r = fit(ref, ref_target, n, frequencies=N, stiffness=stiffness, starts=args.starts, seed=0,
                squared=sq, workers=args.workers, progress=False, eigen_norm=args.eigen_norm)
        wall, cpu = time.perf_counter() - t0, cpu_s() - c0
        best = float(np.min(r.start_losses_pct))
        near = int(np.sum(r.start_losses_pct <= best * (1 + 1e-3) + 1e-12))
        lines.append(f"| {stiffness} | {n}R | {N} | {'omega^2' if sq else 'omega'} | "
                     f"{wall:.2f} | {cpu:.2f} | {load:.1f} | {r.eigen_loss_pct:.4g} | "
                     f"{r.worst_mode_error_pct:.3g} | {r.worst_export_error_pct:.3g} | {r.nfev} | "
                     f"{1e3 * cpu / r.nfev:.3f} | {near}/{r.starts_run} |")
        print(lines[-1], flush=True)
    lines += ["", f"## Five seeds, {args.starts} starts each: spread of the optimum", "",
              "| stiffness | model | N | compared | losses, seeds 0-4 (%) | max - min, "
              "relative to min |", "|---|---|---|---|---|---|"]
    for stiffness, n, N, sq in [("paper", 4, 3, True), ("paper", 4, 4, True),
                                ("paper", 5, 5, True), ("paper", 5, 5, False)]:
        losses = np.array([fit(ref, ref_target, n, frequencies=N, stiffness=stiffness,
                               starts=args.starts,
                               seed=s, squared=sq, workers=args.workers, progress=False,
                               eigen_norm=args.eigen_norm).eigen_loss_pct for s in range(5)])
        lines.append(f"| {stiffness} | {n}R | {N} | {'omega^2' if sq else 'omega'} | "
                     + ", ".join(f"{v:.7g}" for v in losses)
                     + f" | {np.ptp(losses) / losses.min():.2g} |")
        print(lines[-1], flush=True)
    if not args.pareto_stiffness:
        lines += ["", "Targets (issue 4): 5R eigen fit with 64 starts <= 5 s (joint), <= 10 s "
                  "(paper).", ""]
        write_table(args.out, "\n".join(lines), ap.get_default("out"), "bench_fit")
        print(f"wrote {args.out}")
        return
    lines += ["", "## NSGA-II, 4R, uniform-narrow.json (Euler-Bernoulli + elastica), "
              f"population {args.pop}, {args.generations} generations", "",
              "| stiffness | generations | eps (rad) | poses | wall (s) | CPU (s) | load | "
              "evaluations | front size | knee eigen (%) | knee tip position (%) | "
              "knee combined (%) | knee worst mode (%) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for stiffness in args.pareto_stiffness:
        load = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), cpu_s()
        gens = args.generations if stiffness == "joint" or args.paper_generations is None \
            else args.paper_generations
        p = fit_pareto(narrow, narrow_target(narrow), 4, frequencies=4, stiffness=stiffness,
                       pop=args.pop,
                       generations=gens, seed=0, workers=args.workers, progress=False,
                       eigen_norm=args.eigen_norm)
        wall, cpu = time.perf_counter() - t0, cpu_s() - c0
        k = p.knee
        lines.append(f"| {stiffness} | {gens} | {p.eps:g} | {k.poses_rad.shape[0]} | {wall:.1f} | "
                     f"{cpu:.1f} | {load:.1f} | "
                     f"{p.n_evals} | {p.F_pct.shape[0]} | {k.eigen_loss_pct:.4g} | "
                     f"{k.deflection_loss_pct:.4g} | {k.combined_loss_pct:.4g} | "
                     f"{k.worst_mode_error_pct:.3g} |")
        print(lines[-1], flush=True)
    lines += ["", "Targets (issue 4): 5R eigen fit with 64 starts <= 5 s (joint), <= 10 s (paper); "
              "4R Pareto <= 120 s.", ""]
    write_table(args.out, "\n".join(lines), ap.get_default("out"), "bench_fit")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
