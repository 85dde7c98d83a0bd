"""Benchmark of the fits' analytic Jacobians: CPU time and optimum of joint and paper fits, this
source tree against a baseline tree (the code before, with finite-difference Jacobians).

Each case runs in its own process for each tree (BLAS pinned to one thread, one worker), and the
CPU time of the ``fit`` call alone is measured (the machine is shared: CPU time, not wall time,
is what the code costs). The same fit with the same seed and starts in both trees; the table
gives the CPU time of each, the best loss of each, and how far apart the two optima are.

Truths (computed before the timer, identical in both trees):
- uniform-narrow: Euler-Bernoulli frequencies and the elastica tip at P L^2/EI = 1 (as
  scripts/bench_fit.py);
- tapered, reference-random: the 1D beam truth (``compute_truth(model="beam", modes=6)``, its
  frequencies and calibrated-elastica tip under the beam's load).

usage: python scripts/bench_fit_jacobian.py --baseline TREE [--starts 16] [--only TEXT]
       [--out results/bench_fit_jacobian.md]
TREE is a checkout of the code to compare against (e.g. ``git worktree add TREE main``).
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

# (beam, truth, joints, objective, stiffness)
CASES = [
    ("tapered", "beam", 4, "combined", "joint"),
    ("reference-random", "beam", 4, "combined", "joint"),
    ("uniform-narrow", "table", 4, "combined", "joint"),
    ("uniform-narrow", "table", 3, "combined", "joint"),
    ("reference-random", "beam", 4, "deflection", "joint"),
    ("uniform-narrow", "table", 3, "eigen", "joint"),
    ("reference-random", "beam", 4, "eigen", "joint"),
    ("reference-random", "beam", 4, "eigen", "paper"),
    ("uniform-narrow", "table", 3, "eigen", "paper"),
    ("tapered", "beam", 4, "combined", "paper"),
    ("uniform-narrow", "table", 3, "combined", "paper"),
]

# run in a child process with the tree to measure first on sys.path; prints one JSON line
CHILD = r"""
import json, math, sys, time
import numpy as np
import prbdm_pin as pp
beam_name, truth, n, objective, stiffness, starts = sys.argv[1:7]
beam = pp.load_beam(f"{sys.argv[7]}/examples/beams/{beam_name}.json")
if truth == "table":
    BETA_L = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875,
                       14.137168391046, 17.278759532088])
    b = 2 * beam.half_width_m[0]
    EI = beam.material.E_Pa * b * beam.thickness_m**3 / 12
    omega = BETA_L**2 * math.sqrt(EI / (beam.material.rho_kg_m3 * b * beam.thickness_m))
    L = beam.length_m
    target = pp.FitTarget(omega, beam.tip_force_N, [L * (1 - 0.056433), 0.0, -0.301721 * L],
                          [-0.056433 * L, 0.0, -0.301721 * L], source="table")
else:
    tr = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
    target = pp.target_from_truth(tr, beam.tip_force_N)
# where the CPU goes: the residuals, the Jacobian, and the rest (the solver's own linear
# algebra, the final evaluation through Pinocchio)
from prbdm_pin.fitting.joint import JointResiduals
spent = {"residuals": 0.0, "jac": 0.0}
depth = [0]
def timed(name, f):
    def g(self, *a):
        if depth[0]:  # a call inside a timed one counts to the outer one
            return f(self, *a)
        depth[0] += 1
        c = time.process_time()
        try:
            return f(self, *a)
        finally:
            spent[name] += time.process_time() - c
            depth[0] -= 1
    return g
for name in ("residuals", "jac"):
    setattr(JointResiduals, name, timed(name, getattr(JointResiduals, name)))
for name in ("eigen_residuals", "eigen_jac"):  # the eigen objective's entry points
    setattr(JointResiduals, name, timed(name.split("_")[1] if name == "eigen_jac"
                                        else "residuals", getattr(JointResiduals, name)))
c0, t0 = time.process_time(), time.perf_counter()
r = pp.fit(beam, target, int(n), objective=objective, stiffness=stiffness, starts=int(starts),
           seed=0, progress=False)
cpu, wall = time.process_time() - c0, time.perf_counter() - t0
loss = {"eigen": r.eigen_loss_pct, "deflection": r.deflection_loss_pct,
        "combined": r.combined_loss_pct}[objective]
print(json.dumps({"cpu_s": cpu, "wall_s": wall, "residuals_s": spent["residuals"],
                  "jac_s": spent["jac"], "nfev": int(r.nfev), "loss_pct": loss,
                  "lengths_m": r.lengths_m.tolist(), "stiffness": r.stiffness_Nm_per_rad.tolist(),
                  "start_losses_pct": np.asarray(r.start_losses_pct).tolist()}))
"""


def run(tree: Path, case: tuple, starts: int, repeat: int) -> dict:
    """The case's fit in ``tree``, ``repeat`` times in fresh processes: the run of least CPU
    (a shared machine only ever adds time)."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    runs = []
    for _ in range(repeat):
        out = subprocess.run([sys.executable, "-c", CHILD, *map(str, case), str(starts),
                              str(ROOT)], env=env, capture_output=True, text=True, check=True,
                             cwd=str(tree))
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    return min(runs, key=lambda r: r["cpu_s"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, help="source tree of the code before")
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=3, help="runs per case and tree (least CPU)")
    ap.add_argument("--only", default="", help="run only the cases whose row contains TEXT "
                    "(e.g. 'paper', 'reference-random')")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_fit_jacobian.md"))
    args = ap.parse_args()
    base = Path(args.baseline).resolve()
    lines = [
        "# Fit benchmark: analytic Jacobians against finite differences",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared), Python "
        f"{platform.python_version()}; BLAS pinned to 1 thread; one worker; {args.starts} "
        f"starts, seed 0; least CPU of {args.repeat} runs; load average at start "
        f"{os.getloadavg()[0]:.1f}.",
        "",
        "CPU: process time of the `fit` call (user + system), each case in a fresh process; "
        "of it, the time in the residuals and in the Jacobian (`JointResiduals`, joint rows "
        "only; the rest is the solver's own linear algebra and the final evaluation through "
        "Pinocchio). "
        "Evaluations: model evaluations as the fit counts them (before: every finite-difference "
        "stencil row; after: one per analytic Jacobian). Same optimum: the best loss of each "
        "code and the largest differences of the fitted link lengths (relative to L) and "
        "springs (relative).",
        "",
        "| beam | truth | model | objective | CPU before (s) | CPU after (s) | speed-up | "
        "residuals / Jacobian before (s) | residuals / Jacobian after (s) | "
        "evaluations before / after | loss before (%) | loss after (%) | max dL / L | "
        "max dk / k |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for case in CASES:
        if args.only and args.only not in " ".join(map(str, case)):
            continue
        b, a = run(base, case, args.starts, args.repeat), run(ROOT, case, args.starts,
                                                              args.repeat)
        dL = np.max(np.abs(np.subtract(a["lengths_m"], b["lengths_m"]))) / np.sum(b["lengths_m"])
        dk = np.max(np.abs(np.divide(a["stiffness"], b["stiffness"]) - 1.0))
        name, truth, n, objective, stiffness = case
        split = [f"{r['residuals_s']:.2f} / {r['jac_s']:.2f}" if stiffness == "joint" else "-"
                 for r in (b, a)]
        lines.append(
            f"| {name} | {'1D beam' if truth == 'beam' else 'EB + elastica'} | {n}R {stiffness} | "
            f"{objective} | {b['cpu_s']:.2f} | {a['cpu_s']:.2f} | {b['cpu_s'] / a['cpu_s']:.2f} | "
            f"{split[0]} | {split[1]} | {b['nfev']} / {a['nfev']} | {b['loss_pct']:.8g} | "
            f"{a['loss_pct']:.8g} | "
            f"{dL:.2g} | {dk:.2g} |")
        print(lines[-1], flush=True)
    lines += ["", "Target (issue 16): a combined 4R joint fit with 16 starts <= 5 s.", ""]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(ROOT))
    from prbdm_pin.io.atomic import atomic_write_text

    atomic_write_text(out, "\n".join(lines))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
