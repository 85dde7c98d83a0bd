"""Single calls against Pinocchio's own cost: frequencies, ``linearize`` and one fit evaluation.

Issue 30's targets, each as a ratio to a bare ``pinocchio.crba`` on the same model (the same
pose, the same ``pinocchio.Data``), measured in one process, side by side:

- one pose's frequencies, ``model.natural_frequencies(q)`` (target <= 5x crba at n = 5);
- ``linearize(model)`` at the straight pose and under the beam's tip load (target <= 20x);
- one fit evaluation, ``JointResiduals.residuals(x)`` of the combined joint fit at its first
  start (seed 0; warm: the static solve starts from its own equilibrium, as in
  ``bench_fit_evaluation.py``), and ``fitting.evaluate.evaluate`` of the same design through
  the Pinocchio model (target <= 20x).

The floor beside them: crba plus one LAPACK eigensolve of the n x n scaled matrix by
``scipy.linalg.lapack.dsyevd`` (the irreducible calls of one pose's frequencies).

Beam ``examples/beams/reference-random.json``, equal links (h/2, h, ..., h, h/2) with
finite-segment springs, pose 0.02 rad per joint for the frequencies and crba. Per call,
microseconds of CPU (``time.process_time``), BLAS on one thread, the least over ``--repeats``
runs of the mean of a run (a shared machine only ever adds time).

Writes its table to ``--out`` and, with the default ``--out``, to
docs/benchmarks/bench_single_calls.md.

usage: python scripts/bench_single_calls.py [--repeats 7] [--budget 0.05] [--out FILE]
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
sys.path.insert(0, str(ROOT / "scripts"))  # the scripts' shared helpers

DEFAULT_OUT = ROOT / "results" / "bench_single_calls.md"
NS = (1, 3, 5, 8, 16)
POSE_RAD = 0.02


def per_call_us(fn, repeats: int, budget_s: float) -> float:
    """Least over ``repeats`` runs of the mean CPU time of one call of fn(), microseconds."""
    fn()
    c = time.process_time()
    fn()
    once = max(time.process_time() - c, 1e-7)
    number = max(3, int(budget_s / once))
    best = float("inf")
    for _ in range(repeats):
        c = time.process_time()
        for _ in range(number):
            fn()
        best = min(best, (time.process_time() - c) / number)
    return 1e6 * best


def fit_target(beam):
    """The 1D beam truth's target of ``beam`` (frequencies and calibrated-elastica tip)."""
    import prbdm_pin as pp

    truth = pp.compute_truth(beam, model="beam", modes=6, error_tol_pct=None)
    return pp.target_from_truth(truth, beam.tip_force_N)


def row(beam, target, n: int, repeats: int, budget_s: float) -> dict:
    """Per-call CPU (us) of every measured call at ``n`` joints."""
    import numpy as np
    import pinocchio as pin
    from scipy.linalg.lapack import dsyevd

    import prbdm_pin as pp
    from prbdm_pin.chain.stiffness import finite_segment_stiffness
    from prbdm_pin.fitting.evaluate import evaluate
    from prbdm_pin.fitting.joint import JointResiduals
    from prbdm_pin.fitting.multistart import draw_starts
    from prbdm_pin.fitting.problem import make_problem, unit_from_lengths
    from prbdm_pin.fitting.spec import FitSpec
    from prbdm_pin.options.objects import FitOptions

    h = beam.length_m / n
    lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
    model = pp.build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    pm, data = model.pin_model, model.default_data
    q = np.full(n, POSE_RAD)
    s = 1.0 / np.sqrt(model.stiffness_Nm_per_rad)
    A = pin.crba(pm, data, q) * s[:, None] * s[None, :]
    F = np.asarray(beam.tip_force_N, dtype=float)

    o = FitOptions(objective="combined", stiffness="joint")
    p = make_problem(beam, target, n, o)
    _, start_lengths, factors = draw_starts(p, 1, 0)[0]
    x = np.r_[unit_from_lengths(start_lengths, p.length_m, p.min_fraction), np.log(factors)]
    R = JointResiduals(FitSpec(p, o.objective, o.max_nfev))
    calls = {
        "crba": lambda: pin.crba(pm, data, q),
        "floor": lambda: (pin.crba(pm, data, q), dsyevd(A, compute_v=0, lower=0)),
        "frequencies": lambda: model.natural_frequencies(q),
        "linearize": lambda: pp.linearize(model),
        "linearize loaded": lambda: pp.linearize(model, load_N=F),
        "fit residuals": lambda: R.residuals(x),
        "evaluate": lambda: evaluate(p, start_lengths, factors),
    }
    return {key: per_call_us(f, repeats, budget_s) for key, f in calls.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7, help="runs per timing (least CPU)")
    ap.add_argument("--budget", type=float, default=0.05, help="seconds of calls per run")
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    args = ap.parse_args()

    import numpy as np
    import pinocchio as pin
    from docs_tables import write_table

    import prbdm_pin as pp

    load = os.getloadavg()[0]
    beam = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    target = fit_target(beam)
    rows = {n: row(beam, target, n, args.repeats, args.budget) for n in NS}
    lines = [
        "# Single calls against a bare `pinocchio.crba`",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared), Python "
        f"{platform.python_version()}, numpy {np.__version__}, pinocchio {pin.__version__}; "
        f"BLAS pinned to 1 thread; load average at start {load:.1f}. Beam "
        "`reference-random.json`, equal links with finite-segment springs. Per call, "
        f"microseconds of CPU, the least over {args.repeats} runs; in brackets the ratio to "
        "crba on the same model. Floor: crba plus one LAPACK `dsyevd` of the scaled n x n "
        "matrix. Linearize: the default `tip_force_z` to `tip_z` plant with 2 % modal damping, "
        "straight and under the beam's tip load. Fit residuals: `JointResiduals.residuals` of "
        "the combined joint fit at its first start (warm statics); evaluate: "
        "`fitting.evaluate.evaluate` of the same design (builds the Pinocchio model). "
        "Targets (issue 30): frequencies <= 5x, linearize <= 20x, a fit evaluation <= 20x.",
        "",
        "| n | crba (us) | floor | frequencies | linearize | linearize loaded | "
        "fit residuals | evaluate |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, r in rows.items():
        c = r["crba"]
        cells = [f"{r[k]:.1f} ({r[k] / c:.1f}x)" for k in (
            "floor", "frequencies", "linearize", "linearize loaded", "fit residuals",
            "evaluate")]
        lines.append(f"| {n} | {c:.2f} | " + " | ".join(cells) + " |")
    lines.append("")
    text = "\n".join(lines)
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    for f in write_table(out, text, DEFAULT_OUT, "bench_single_calls"):
        print(f"wrote {f}")


if __name__ == "__main__":
    main()
