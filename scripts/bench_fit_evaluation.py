"""Micro-benchmark of one evaluation of the ``joint`` fit: its residuals and analytic Jacobian.

``JointResiduals.residuals`` and ``.jac`` (4 joints, combined objective, one pose, one load
case) at a start point of a fit, and each part they are made of, called alone with the same
inputs. Per call, CPU time (process time) with BLAS on one thread, the best of several repeats
(a shared machine only ever adds time). The residuals are timed at the same x again and again,
so the static solve starts from its own equilibrium (warm); in a fit it starts from the last x's
equilibrium and may take a Newton step or two more.

Truths: the 1D beam truth (``compute_truth(model="beam", modes=6)``, its frequencies and the
calibrated-elastica tip under the beam's load) of tapered, reference-random and uniform-narrow.

usage: python scripts/bench_fit_evaluation.py [--repeat 7] [--calls 400]
       [--out results/bench_fit_evaluation.md]
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.chain_gradient import frequency_gradients, static_tip_gradient  # noqa: E402
from prbdm_pin.evaluate import chain_frequencies  # noqa: E402
from prbdm_pin.fitting.joint import JointResiduals  # noqa: E402
from prbdm_pin.fitting.multistart import draw_starts  # noqa: E402
from prbdm_pin.fitting.spec import FitSpec  # noqa: E402
from prbdm_pin.io import atomic_write_text  # noqa: E402
from prbdm_pin.options import FitOptions  # noqa: E402
from prbdm_pin.planar import planar_mass_matrices, planar_tip  # noqa: E402
from prbdm_pin.problem import make_problem, unit_from_lengths  # noqa: E402
from prbdm_pin.section_gradients import (  # noqa: E402
    finite_segment_stiffness_gradient,
    planar_sections_gradient,
)
from prbdm_pin.sections import planar_sections  # noqa: E402
from prbdm_pin.statics import static_deflection_planar  # noqa: E402
from prbdm_pin.stiffness import finite_segment_stiffness_unchecked  # noqa: E402

BEAMS = ("tapered", "reference-random", "uniform-narrow")
JOINTS = 4


def per_call_us(f, calls: int, repeat: int) -> float:
    """Best over ``repeat`` runs of the mean CPU time of ``calls`` calls of f(), microseconds."""
    best = np.inf
    for _ in range(repeat):
        c = time.process_time()
        for _ in range(calls):
            f()
        best = min(best, (time.process_time() - c) / calls)
    return 1e6 * best


def residuals_at_start(name: str) -> tuple[JointResiduals, np.ndarray]:
    """The residuals of a combined 4R joint fit of beam ``name`` and the fit's first start x."""
    beam = pp.load_beam(ROOT / "examples" / "beams" / f"{name}.json")
    truth = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
    target = pp.target_from_truth(truth, beam.tip_force_N)
    o = FitOptions(objective="combined", stiffness="joint")
    p = make_problem(beam, target, JOINTS, o.frequencies, o.stiffness.value, o.xi_rad,
                     o.eps_rad, o.squared, o.joint_sweep, o.min_fraction, o.eigen_norm.value)
    _, lengths, factors = draw_starts(p, 1, 0)[0]
    x = np.r_[unit_from_lengths(lengths, p.length_m, p.min_fraction), np.log(factors)]
    return JointResiduals(FitSpec(p, "combined", o.deflection_norm.value, o.max_nfev)), x


def measure(name: str, calls: int, repeat: int) -> dict[str, float]:
    """Per-call CPU (us) of the residuals, the Jacobian and their parts for beam ``name``."""
    R, x = residuals_at_start(name)
    p = R.p
    lengths, s = R.design(x)
    sec = planar_sections(p.beam, lengths)
    K0 = finite_segment_stiffness_unchecked(p.beam, lengths)
    M = planar_mass_matrices(lengths, *sec[:3], p.poses_rad)
    k = s * K0
    case = R.cases[0]
    q = static_deflection_planar(lengths, k, case.tip_force_N)
    sg = planar_sections_gradient(p.beam, lengths, sec)
    R.residuals(x)  # the Jacobian at the residuals' x reuses their chain
    out = {
        "residuals": lambda: R.residuals(x),
        "planar_sections": lambda: planar_sections(p.beam, lengths),
        "finite_segment_stiffness": lambda: finite_segment_stiffness_unchecked(p.beam, lengths),
        "planar_mass_matrices": lambda: planar_mass_matrices(lengths, *sec[:3], p.poses_rad),
        "chain_frequencies": lambda: chain_frequencies(M, k),
        "static_deflection (warm)": lambda: static_deflection_planar(
            lengths, k, case.tip_force_N, q0=q),
        "planar_tip": lambda: planar_tip(lengths, q),
        "jac": lambda: R.jac(x),
        "planar_sections_gradient": lambda: planar_sections_gradient(p.beam, lengths, sec),
        "finite_segment_stiffness_gradient": lambda: finite_segment_stiffness_gradient(
            p.beam, lengths, K0),
        "frequency_gradients": lambda: frequency_gradients(lengths, sg, k, p.poses_rad, M),
        "static_tip_gradient": lambda: static_tip_gradient(lengths, k, case.tip_force_N, q),
    }
    return {key: per_call_us(f, calls, repeat) for key, f in out.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs per timing (least CPU)")
    ap.add_argument("--calls", type=int, default=400, help="calls per run")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_fit_evaluation.md"))
    args = ap.parse_args()
    load = os.getloadavg()[0]
    rows = {name: measure(name, args.calls, args.repeat) for name in BEAMS}
    parts = list(rows[BEAMS[0]])
    lines = [
        "# One evaluation of the joint fit: residuals and analytic Jacobian",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared), Python "
        f"{platform.python_version()}, numpy {np.__version__}; BLAS pinned to 1 thread; "
        f"load average at start {load:.1f}. Combined objective, {JOINTS} joints, 1D beam "
        "truth, the fit's first start (seed 0). Per call, microseconds of CPU: the best of "
        f"{args.repeat} runs of {args.calls} calls each. Indented rows are parts of the call "
        "above them, each timed alone with the same inputs.",
        "",
        "| call | " + " | ".join(BEAMS) + " |",
        "|---|" + "---:|" * len(BEAMS),
    ]
    for part in parts:
        label = part if part in ("residuals", "jac") else f"&nbsp;&nbsp;{part}"
        lines.append(f"| {label} | " + " | ".join(f"{rows[b][part]:.0f}" for b in BEAMS) + " |")
    lines.append("")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, "\n".join(lines))
    print("\n".join(lines))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
