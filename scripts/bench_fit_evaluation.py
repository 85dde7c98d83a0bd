"""Micro-benchmark of one evaluation of the ``joint`` fit: its residuals and analytic Jacobian.

``JointResiduals.residuals`` and ``.jac`` (4 joints, combined objective, one pose, one load
case) at the first start of a fit (seed 0), and each part they are made of, called alone with
the same inputs. Per call, CPU time (process time) with BLAS on one thread, the best of several
runs (a shared machine only ever adds time). The residuals are timed at the same x again and
again, so the static solve starts from its own equilibrium (warm); in a fit it starts from the
last x's equilibrium and takes Newton steps, so the calls of one start's local solve are also
recorded and replayed in order.

Truths: the 1D beam truth (``compute_truth(model="beam", modes=6)``: its frequencies and the
calibrated-elastica tip under the beam's load) of tapered, reference-random and uniform-narrow,
computed once here and handed to each measuring process as numbers.

Writes its table to ``--out`` and, with the default ``--out``, to
docs/benchmarks/bench_fit_evaluation.md (the benchmarks page includes it).

With ``--baseline TREE`` (a checkout of the code to compare against, e.g. ``git worktree add
TREE main``) each tree is measured in its own processes, the trees taking turns, and the table
gives both columns and their ratio; the residuals and Jacobians of the two trees are compared
too (largest difference relative to the largest entry).

usage: python scripts/bench_fit_evaluation.py [--baseline TREE] [--rounds 3] [--runs 7]
       [--calls 300] [--out results/bench_fit_evaluation.md]
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
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / "results" / "bench_fit_evaluation.md"
BEAMS = ("tapered", "reference-random", "uniform-narrow")
JOINTS = 4
# indented rows of the table: parts of the call above them
PARTS = {
    "residuals": ("planar_sections", "finite_segment_stiffness", "planar_mass_matrices",
                  "chain_frequencies", "static_deflection (warm)", "planar_tip"),
    "jac": ("planar_sections_gradient", "finite_segment_stiffness_gradient",
            "frequency_gradients", "static_tip_gradient"),
    "residuals (a fit's sequence)": (),
    "jac (a fit's sequence)": (),
}


def per_call_us(f, calls: int, runs: int) -> float:
    """Best over ``runs`` runs of the mean CPU time of ``calls`` calls of f(), microseconds."""
    best = float("inf")
    for _ in range(runs):
        c = time.process_time()
        for _ in range(calls):
            f()
        best = min(best, (time.process_time() - c) / calls)
    return 1e6 * best


def truths() -> dict:
    """The 1D beam truth of each beam as plain numbers: what a fit target is made of."""
    sys.path.insert(0, str(ROOT))
    import prbdm_pin as pp

    out = {}
    for name in BEAMS:
        beam = pp.load_beam(ROOT / "examples" / "beams" / f"{name}.json")
        t = pp.target_from_truth(pp.compute_truth(beam, model="beam", modes=6,
                                                  error_tol_pct=None), beam.tip_force_N)
        out[name] = {k: getattr(t, k).tolist() for k in (
            "omega_truth_rad_s", "tip_force_N", "tip_position_m", "tip_displacement_m")}
    return out


def measure(tree: str, name: str, target: dict, calls: int, runs: int) -> dict:
    """Per-call CPU (us) of the residuals, the Jacobian and their parts in the package of
    ``tree``, with the residuals and Jacobian at x (to compare trees)."""
    sys.path.insert(0, tree)
    import numpy as np

    import prbdm_pin as pp
    from prbdm_pin.chain.chain_derivatives import frequency_gradients, static_tip_gradient
    from prbdm_pin.chain.planar import planar_mass_matrices, planar_tip
    from prbdm_pin.chain.sections import planar_sections
    from prbdm_pin.chain.sections_derivatives import (
        finite_segment_stiffness_gradient,
        planar_sections_gradient,
    )
    from prbdm_pin.chain.statics import static_deflection_planar
    from prbdm_pin.chain.stiffness import finite_segment_stiffness_unchecked
    from prbdm_pin.fitting.evaluate import chain_frequencies
    from prbdm_pin.fitting.joint import JointResiduals
    from prbdm_pin.fitting.multistart import draw_starts
    from prbdm_pin.fitting.problem import make_problem, unit_from_lengths
    from prbdm_pin.fitting.spec import FitSpec
    from prbdm_pin.options.objects import FitOptions

    beam = pp.load_beam(Path(tree) / "examples" / "beams" / f"{name}.json")
    o = FitOptions(objective="combined", stiffness="joint")
    p = make_problem(beam, pp.FitTarget(**target), JOINTS, o)
    _, lengths, factors = draw_starts(p, 1, 0)[0]
    x = np.r_[unit_from_lengths(lengths, p.length_m, p.min_fraction), np.log(factors)]
    R = JointResiduals(FitSpec(p, o.objective, o.max_nfev))
    lengths, s = R.design(x)
    sec = planar_sections(beam, lengths)
    K0 = finite_segment_stiffness_unchecked(beam, lengths)
    M = planar_mass_matrices(lengths, *sec[:3], p.poses_rad)
    k = s * K0
    F = R.cases[0].tip_force_N
    q = static_deflection_planar(lengths, k, F)
    sg = planar_sections_gradient(beam, lengths, sec)
    r = R.residuals(x)  # the Jacobian at the residuals' x reuses what they computed
    J = R.jac(x)
    calls_of = {
        "residuals": lambda: R.residuals(x),
        "planar_sections": lambda: planar_sections(beam, lengths),
        "finite_segment_stiffness": lambda: finite_segment_stiffness_unchecked(beam, lengths),
        "planar_mass_matrices": lambda: planar_mass_matrices(lengths, *sec[:3], p.poses_rad),
        "chain_frequencies": lambda: chain_frequencies(M, k),
        "static_deflection (warm)": lambda: static_deflection_planar(lengths, k, F, q0=q),
        "planar_tip": lambda: planar_tip(lengths, q),
        "jac": lambda: R.jac(x),
        "planar_sections_gradient": lambda: planar_sections_gradient(beam, lengths, sec),
        "finite_segment_stiffness_gradient": lambda: finite_segment_stiffness_gradient(
            beam, lengths, K0),
        "frequency_gradients": lambda: frequency_gradients(lengths, sg, k, p.poses_rad, M),
        "static_tip_gradient": lambda: static_tip_gradient(lengths, k, F, q),
    }
    R.residuals(x)
    times = {key: per_call_us(f, calls, runs) for key, f in calls_of.items()}
    times.update(fit_sequence(JointResiduals, R.spec, draw_starts(p, 1, 0)[0], runs))
    return {"us": times, "residuals": r.tolist(), "jac": J.tolist()}


def fit_sequence(cls, spec, start: tuple, runs: int) -> dict:
    """Per-call CPU (us) of the residuals and Jacobians a fit's local solve asks for, in order.

    The calls of one start's solve (``fitting.local.solve_start``) are recorded, then replayed
    on fresh ``cls`` objects (the static solves start from the last design's equilibrium, as
    in the fit), the best of ``runs`` replays.
    """
    import numpy as np

    from prbdm_pin.fitting.local import solve_start

    calls, depth = [], [0]
    methods = {"residuals": cls.residuals, "jac": cls.jac}

    def recording(kind):
        def call(self, x):
            if not depth[0]:  # the residuals a Jacobian computes first are part of it
                calls.append((kind, np.array(x, dtype=float)))
            depth[0] += 1
            try:
                return methods[kind](self, x)
            finally:
                depth[0] -= 1
        return call

    for kind in methods:
        setattr(cls, kind, recording(kind))
    try:
        solve_start(spec, *start)
    finally:
        for kind, f in methods.items():
            setattr(cls, kind, f)
    best = {kind: float("inf") for kind in methods}
    for _ in range(runs):
        R, spent = cls(spec), dict.fromkeys(methods, 0.0)
        for kind, x in calls:
            f = getattr(R, kind)
            c = time.process_time()
            f(x)
            spent[kind] += time.process_time() - c
        for kind in methods:
            count = sum(k == kind for k, _ in calls)
            best[kind] = min(best[kind], spent[kind] / count)
    return {f"{kind} (a fit's sequence)": 1e6 * t for kind, t in best.items()}


def run_child(tree: Path, name: str, target_file: str, calls: int, runs: int) -> dict:
    """:func:`measure` in a fresh process whose package is the one of ``tree``."""
    out = subprocess.run(
        [sys.executable, __file__, "--child", name, "--tree", str(tree), "--targets",
         target_file, "--calls", str(calls), "--runs", str(runs)],
        env=dict(os.environ, PYTHONPATH=str(tree)), cwd=str(tree), capture_output=True,
        text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", help="source tree of the code to compare against")
    ap.add_argument("--rounds", type=int, default=3,
                    help="fresh processes per tree and beam, the trees taking turns (least CPU)")
    ap.add_argument("--runs", type=int, default=7, help="runs per timing in a process")
    ap.add_argument("--calls", type=int, default=300, help="calls per run")
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--tree", help=argparse.SUPPRESS)
    ap.add_argument("--targets", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        target = json.loads(Path(args.targets).read_text())[args.child]
        print(json.dumps(measure(args.tree, args.child, target, args.calls, args.runs)))
        return
    load = os.getloadavg()[0]
    trees = {"after": ROOT} if not args.baseline else {
        "before": Path(args.baseline).resolve(), "after": ROOT}
    with tempfile.TemporaryDirectory() as tmp:
        target_file = str(Path(tmp) / "targets.json")
        Path(target_file).write_text(json.dumps(truths()))
        best: dict = {}
        for name in BEAMS:
            for _ in range(args.rounds):
                for label, tree in trees.items():
                    got = run_child(tree, name, target_file, args.calls, args.runs)
                    old = best.get((label, name))
                    if old is not None:
                        got["us"] = {k: min(v, old["us"][k]) for k, v in got["us"].items()}
                    best[(label, name)] = got
    import numpy as np

    cols = list(trees)
    head = " | ".join(f"{b} {c} (us)" for b in BEAMS for c in cols)
    if args.baseline:
        head += " | " + " | ".join(f"{b} speed-up" for b in BEAMS)
    lines = [
        "# One evaluation of the joint fit: residuals and analytic Jacobian",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared), Python "
        f"{platform.python_version()}, numpy {np.__version__}; BLAS pinned to 1 thread; load "
        f"average at start {load:.1f}. Combined objective, {JOINTS} joints, 1D beam truth, the "
        "fit's first start (seed 0). Per call, microseconds of CPU: the least over "
        f"{args.rounds} processes per tree of the best of {args.runs} runs of {args.calls} "
        "calls. Indented rows are parts of the call above them, each timed alone with the same "
        "inputs (called in sequence they cost somewhat more than alone). The last two rows: "
        "the calls of one start's local solve (the fit's first start), recorded and replayed "
        "in order, mean per call, the best of as many replays: there the static solve starts "
        "from the last design's equilibrium and takes Newton steps.",
        "",
        f"| call | {head} |",
        "|---|" + "---:|" * (len(BEAMS) * len(cols) + (len(BEAMS) if args.baseline else 0)),
    ]
    for top, parts in PARTS.items():
        for part in (top, *parts):
            label = part if part == top else f"&nbsp;&nbsp;{part}"
            cells = [f"{best[(c, b)]['us'][part]:.0f}" for b in BEAMS for c in cols]
            if args.baseline:
                cells += [f"{best[('before', b)]['us'][part] / best[('after', b)]['us'][part]:.2f}"
                          for b in BEAMS]
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
    if args.baseline:
        lines += ["", "Same numbers: largest difference between the trees, relative to the "
                  "largest entry: " + ", ".join(
                      f"{b} residuals {_rel(best, b, 'residuals'):.1e}, Jacobian "
                      f"{_rel(best, b, 'jac'):.1e}" for b in BEAMS) + "."]
    lines.append("")
    sys.path.insert(0, str(ROOT))
    sys.path.insert(0, str(ROOT / "scripts"))  # the scripts' shared helpers
    from docs_tables import write_table

    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    print("\n".join(lines))
    for f in write_table(out, "\n".join(lines), DEFAULT_OUT, "bench_fit_evaluation"):
        print(f"wrote {f}")


def _rel(best: dict, name: str, key: str) -> float:
    """Largest |after - before| of ``key`` for beam ``name``, over its largest |entry|."""
    import numpy as np

    a, b = (np.array(best[(c, name)][key]) for c in ("after", "before"))
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


if __name__ == "__main__":
    main()
