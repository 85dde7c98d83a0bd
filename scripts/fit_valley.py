"""Why the combined joint fit runs the geodesic Levenberg-Marquardt solver: each start of the
reference panel's fit solved by scipy's trf (the fit's solver before; x_scale="jac", tolerances
1e-10) at the evaluation cap and on to convergence, and by the geodesic Levenberg-Marquardt
solver (``fitting/geodesic_lm.py``) to convergence; then the residual Jacobian's singular values
at the best converged optimum with the loss along its null directions.

The same problem and starts as ``pp.fit(..., objective="combined", stiffness="joint",
starts=16, seed=0)``; the truth is the 1D beam's (as scripts/bench_fit_jacobian.py). Writes a
markdown table.

usage: python scripts/fit_valley.py [--beam reference-random] [--joints 4] [--cap 400]
       [--out results/fit_valley.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import least_squares  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.fitting.geodesic_lm import lm_advance, lm_start  # noqa: E402
from prbdm_pin.fitting.joint import JointResiduals  # noqa: E402
from prbdm_pin.fitting.local import joint_box  # noqa: E402
from prbdm_pin.fitting.multistart import draw_starts  # noqa: E402
from prbdm_pin.fitting.problem import make_problem, unit_from_lengths  # noqa: E402
from prbdm_pin.fitting.spec import FitSpec  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.options.objects import FitOptions  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def solve(spec: FitSpec, x0: np.ndarray, cap: int):
    """The trf least-squares solve of one start (the fit's before) with evaluation cap ``cap``."""
    J = JointResiduals(spec)
    lb, ub = joint_box(spec.problem.n_joints)
    c = time.process_time()
    r = least_squares(J.residuals, x0, jac=J.jac, bounds=(lb, ub), method="trf", x_scale="jac",
                      ftol=1e-10, xtol=1e-10, gtol=1e-10, max_nfev=cap)
    return J, r, time.process_time() - c


def solve_geodesic(spec: FitSpec, x0: np.ndarray, cap: int):
    """The geodesic Levenberg-Marquardt solve of one start, run to convergence."""
    J = JointResiduals(spec)
    lb, ub = joint_box(spec.problem.n_joints)
    c = time.process_time()
    state = lm_advance(lm_start(J.residuals, J.jac, x0, lb, ub), J.residuals, J.jac, lb, ub, cap)
    return J, state, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beam", default="reference-random")
    ap.add_argument("--joints", type=int, default=4)
    ap.add_argument("--cap", type=int, default=FitOptions().max_nfev)
    ap.add_argument("--out", default=str(ROOT / "results" / "fit_valley.md"))
    args = ap.parse_args()
    beam = pp.load_beam(ROOT / "examples" / "beams" / f"{args.beam}.json")
    truth = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
    target = pp.target_from_truth(truth, beam.tip_force_N)
    o = FitOptions().replace(objective="combined", stiffness="joint")
    problem = make_problem(beam, target, args.joints, o)
    spec = FitSpec(problem, o.objective, args.cap)
    L = beam.length_m
    lines = [f"# The combined {args.joints}R joint fit of `{args.beam}` (1D beam truth)", "",
             f"Each start of `fit(..., starts=16, seed=0)`: trf at the cap of {args.cap} "
             "residual evaluations (what the fit returned with trf) and run on to convergence "
             "(cap 20000), and the geodesic Levenberg-Marquardt solver to convergence (same "
             "cap); evaluations count residuals and Jacobians; CPU s of one process.", "",
             "| start | trf: loss at cap (%) | status | trf: loss converged (%) | evaluations | "
             "CPU (s) | max dL / L (cap vs converged) | geodesic LM: loss (%) | evaluations | "
             "CPU (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    best = None
    for i, L0, F0 in draw_starts(problem, 16, 0):
        x0 = np.r_[unit_from_lengths(L0, L, problem.min_fraction), np.log(F0)]
        Jc, rc, _ = solve(spec, x0, args.cap)
        Jf, rf, cpu = solve(spec, x0, 20000)
        Jg, sg, cpu_g = solve_geodesic(spec, x0, 20000)
        lc, lf, lg = 100 * Jc.loss(rc.x), 100 * Jf.loss(rf.x), 100 * Jg.loss(sg.x)
        dL = np.max(np.abs(Jc.design(rc.x)[0] - Jf.design(rf.x)[0])) / L
        lines.append(f"| {i} | {lc:.7f} | {rc.status} | {lf:.7f} | {Jf.nfev} | {cpu:.2f} | "
                     f"{dL:.2g} | {lg:.7f} | {sg.nfev + sg.njev} | {cpu_g:.2f} |")
        print(lines[-1], flush=True)
        if best is None or lf < best[0]:
            best = (lf, Jf, rf.x)
    _, J, x = best
    r, A = J.residuals(x), J.jac(x)
    sv = np.linalg.svd(A, compute_uv=False)
    V = np.linalg.svd(A)[2]
    f0 = float(r @ r)
    lines += ["", f"Best converged optimum: loss {best[0]:.7f} %, lengths "
              f"{np.round(J.design(x)[0], 6).tolist()} m, residuals {np.round(r, 9).tolist()}.",
              "", "Singular values of the residual Jacobian there: "
              + ", ".join(f"{s:.2g}" for s in sv) + f" ({A.shape[0]} residuals, "
              f"{A.shape[1]} variables).", "",
              "Loss along each right singular vector v (||r(x + t v)||^2 - ||r(x)||^2) / "
              "||r(x)||^2: quadratic where it falls 100x per 10x in t, quartic where 10^4x.", "",
              "| v (singular value) | t = 1e-2 | t = 1e-3 | t = 1e-4 |", "|---|---|---|---|"]
    for k, v in enumerate(V):
        s = sv[k] if k < sv.size else 0.0
        rise = []
        for t in (1e-2, 1e-3, 1e-4):
            fp, fm = J.residuals(x + t * v), J.residuals(x - t * v)
            rise.append(0.5 * (fp @ fp + fm @ fm) / f0 - 1.0)
        lines.append(f"| {k} ({s:.2g}) | " + " | ".join(f"{q:.2g}" for q in rise) + " |")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, "\n".join(lines) + "\n")
    print("\n".join(lines[-12:]))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
