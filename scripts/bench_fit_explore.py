"""Does refining only the best explored starts find the optimum of every start refined?

For each beam (the shipped tapered, reference and uniform panels, and random panels of the
paper's Sec. 2.1), the combined nR joint fit with 16 starts, seed 0, on the 1D beam truth:
- the default: every start explored for ``explore_nfev`` residual evaluations, the 3 best
  refined (``fitting/explore.py``);
- every start refined to convergence (``refine_starts=0``, cap 3000 residual evaluations).
The table gives the CPU time, evaluations, best loss and success of each, and the relative
difference of the two best losses (positive: the default's is higher). BLAS on one thread, one
worker, each fit timed by CPU (process) time.

usage: python scripts/bench_fit_explore.py [--random 10] [--joints 4]
       [--out results/bench_fit_explore.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from docs_tables import write_table  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ("tapered", "reference-random", "uniform-narrow")
DEFAULT_OUT = ROOT / "results" / "bench_fit_explore.md"


def timed_fit(beam, target, joints: int, **kw):
    """The combined joint fit and its CPU time, s."""
    c = time.process_time()
    r = pp.fit(beam, target, joints, objective="combined", stiffness="joint", starts=16, seed=0,
               progress=False, **kw)
    return r, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=10, help="random panels (seeds 1..N)")
    ap.add_argument("--joints", type=int, default=4)
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    args = ap.parse_args()
    beams = [(b, pp.load_beam(ROOT / "examples" / "beams" / f"{b}.json")) for b in SHIPPED]
    beams += [(f"random (seed {k})", pp.random_beam(np.random.default_rng(k)))
              for k in range(1, args.random + 1)]
    o = pp.FitOptions()
    lines = [f"# Explore every start, refine the best: combined {args.joints}R joint fits",
             "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared), Python "
             f"{platform.python_version()}; BLAS on one thread; one worker; 16 starts, seed 0; "
             f"1D beam truth; load average at start {os.getloadavg()[0]:.1f}. Default: explore "
             f"{o.explore_nfev} residual evaluations per start, refine the {o.refine_starts} "
             f"best (cap {o.max_nfev}). Every start: all 16 refined (cap 3000). Evaluations "
             "count residuals and Jacobians.", "",
             "| beam | default: CPU (s) | evaluations | loss (%) | converged | every start: "
             "CPU (s) | evaluations | loss (%) | converged | loss difference (relative) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    worst = 0.0
    for name, beam in beams:
        truth = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
        target = pp.target_from_truth(truth, beam.tip_force_N)
        d, cd = timed_fit(beam, target, args.joints)
        e, ce = timed_fit(beam, target, args.joints, refine_starts=0, max_nfev=3000)
        diff = d.combined_loss_pct / e.combined_loss_pct - 1.0
        worst = max(worst, diff)
        lines.append(f"| {name} | {cd:.2f} | {d.nfev} | {d.combined_loss_pct:.8g} | "
                     f"{'yes' if d.success else 'no (cap)'} | {ce:.2f} | {e.nfev} | "
                     f"{e.combined_loss_pct:.8g} | {'yes' if e.success else 'no (cap)'} | "
                     f"{diff:+.1e} |")
        print(lines[-1], flush=True)
    lines += ["", f"Largest relative excess of the default's best loss: {worst:.1e}.", ""]
    for path in write_table(args.out, "\n".join(lines), DEFAULT_OUT, "fit_explore"):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
