"""Skip what a scene doesn't need: lean computation paths against computing everything.

Each path is timed (best of several repeats, process CPU and wall time, BLAS pinned to one thread)
against a naive version that calls ``pinocchio.computeAllTerms`` (M, nonlinear effects, all joint
Jacobians, frame kinematics, energies, centre of mass) on every evaluation:

- frequency path: ``PrbdmModel.natural_frequencies`` (CRBA + scaled symmetric eigensolve) against
  computeAllTerms + ``scipy.linalg.eigh(K, M)``;
- statics path: ``tip_kinematics`` (one forward-kinematics pass for the tip frame's Jacobian,
  then its placement) against computeAllTerms + frame placement update + ``getFrameJacobian``;
- dynamics right-hand side: ABA with only the terms the scene has (spring torque; + damping
  torque -C v; + tip force J^T F) against computeAllTerms + Cholesky solve of M qdd = tau - nle;
- whole simulations (``prbdm_pin.simulate``, step load or none, damping 0.02 or 0): CPU time per
  simulated second of each scene, and the naive scene run through the same number of dynamics
  evaluations.

Models: the reference random beam cut into finite-segment chains of n = 4, 16 and 64 joints.
Writes results/bench_skip_work.md.
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
from scipy.linalg import cho_factor, cho_solve, eigh  # noqa: E402

from prbdm_pin.bench.run import finite_segment_chain  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402
from prbdm_pin.simulation.damping import modal_damping  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def best(fn, evals: int, repeats: int) -> tuple[float, float]:
    """Best CPU and wall time per evaluation over ``repeats`` batches of ``evals`` calls, s."""
    cpu, wall = np.inf, np.inf
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(evals):
            fn()
        cpu = min(cpu, (time.process_time() - c0) / evals)
        wall = min(wall, (time.perf_counter() - t0) / evals)
    return cpu, wall


def paths(model, rng, evals: int, repeats: int) -> list[tuple[str, tuple, tuple]]:
    pm, n, tip = model.pin_model, model.n_joints, model.tip_frame_id
    d_lean, d_all = pm.createData(), pm.createData()
    q = rng.uniform(-0.3, 0.3, n)
    v = rng.uniform(-1.0, 1.0, n)
    k = np.asarray(model.stiffness_Nm_per_rad)
    K = np.diag(k)
    C = modal_damping(model.mass_matrix(), K, 0.02)
    F = np.array([0.0, 0.0, -10.0])

    def naive_all():
        pin.computeAllTerms(pm, d_all, q, v)
        return d_all

    def freq_naive():
        d = naive_all()
        M = np.triu(d.M) + np.triu(d.M, 1).T
        return np.sqrt(eigh(K, M, eigvals_only=True))

    def stat_lean():
        return model.tip_kinematics(q)

    def stat_naive():
        d = naive_all()
        pin.updateFramePlacements(pm, d)
        return d.oMf[tip].translation, pin.getFrameJacobian(pm, d, tip, LWA)[:3]

    def rhs_lean(damped: bool, forced: bool):
        def f():
            tau = -k * q
            if damped:
                tau = tau - C @ v
            if forced:
                J = pin.computeFrameJacobian(pm, d_lean, q, tip, LWA)[:3]
                tau = tau + J.T @ F
            return pin.aba(pm, d_lean, q, v, tau)
        return f

    def rhs_naive(damped: bool, forced: bool):
        def f():
            d = naive_all()
            pin.updateFramePlacements(pm, d)
            tau = -k * q - d.nle
            if damped:
                tau = tau - C @ v
            if forced:
                tau = tau + pin.getFrameJacobian(pm, d, tip, LWA)[:3].T @ F
            M = np.triu(d.M) + np.triu(d.M, 1).T
            return cho_solve(cho_factor(M), tau)
        return f

    # the lean and naive versions must agree before their times mean anything: to 1e-9, or to
    # the rounding of the highest frequency, eps * cond(K^-1/2 M K^-1/2), when that is larger
    # (both eigensolvers carry it: 1.9e-9 apart at 64 joints, cond 7e7)
    w = model.natural_frequencies(q)
    rtol = max(1e-9, 8 * np.finfo(float).eps * (w[-1] / w[0]) ** 2)
    np.testing.assert_allclose(w, freq_naive(), rtol=rtol)
    a, b = stat_lean(), stat_naive()
    np.testing.assert_allclose(a[0], b[0], atol=1e-12)
    np.testing.assert_allclose(a[1], b[1], atol=1e-12)
    for dm in (False, True):
        for fo in (False, True):
            np.testing.assert_allclose(rhs_lean(dm, fo)(), rhs_naive(dm, fo)(), rtol=1e-8,
                                       atol=1e-8 * float(np.max(np.abs(rhs_naive(dm, fo)()))))
    rows = [("frequencies (CRBA + eigensolve)",
             best(lambda: model.natural_frequencies(q), evals, repeats),
             best(freq_naive, evals, repeats)),
            ("statics (tip placement + Jacobian)", best(stat_lean, evals, repeats),
             best(stat_naive, evals, repeats))]
    for dm in (False, True):
        for fo in (False, True):
            name = ("dynamics RHS: spring" + (" + damping" if dm else "")
                    + (" + tip force" if fo else ""))
            rows.append((name, best(rhs_lean(dm, fo), evals, repeats),
                         best(rhs_naive(dm, fo), evals, repeats)))
    return rows


def scenes(model, duration_s: float, repeats: int) -> list[tuple[str, float, float, int]]:
    out = []
    F = np.array([0.0, 0.0, -10.0])
    for dm in (0.0, 0.02):
        for fo in (None, F):
            name = ("free vibration" if fo is None else "step tip force") + \
                (", damped" if dm else ", undamped")
            q0 = None if fo is not None else np.full(model.n_joints, 1e-3)
            cpu = np.inf
            tr = None
            for _ in range(repeats):
                c0 = time.process_time()
                tr = simulate(model, duration_s, q0=q0, tip_force=fo, damping_ratio=dm)
                cpu = min(cpu, time.process_time() - c0)
            out.append((name, cpu / duration_s, tr.steps, tr.rhs_evaluations))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--joints", default="4,16,64")
    ap.add_argument("--evals", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--duration", type=float, default=0.2, help="simulated time, s")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_skip_work.md"))
    args = ap.parse_args(argv)
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    rng = np.random.default_rng(0)
    lines = [
        "# Skip what a scene doesn't need",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, numpy {np.__version__}, pinocchio {pin.__version__}; "
        "BLAS pinned to 1 thread. Best of "
        f"{args.repeats} batches of {args.evals} evaluations at a random pose (|q| <= 0.3 rad); "
        "times per evaluation in microseconds. Naive = ``pinocchio.computeAllTerms`` on every "
        "evaluation, then what the path needs from it. Lean and naive results are checked equal "
        "before timing.",
        "",
        "| joints | path | lean CPU us | lean wall us | naive CPU us | naive wall us "
        "| speed-up (CPU) |",
        "|---|---|---|---|---|---|---|",
    ]
    sims = []
    for n in (int(s) for s in args.joints.split(",")):
        model = finite_segment_chain(beam, n)
        for name, (lc, lw), (nc, nw) in paths(model, rng, args.evals, args.repeats):
            lines.append(f"| {n} | {name} | {1e6 * lc:.1f} | {1e6 * lw:.1f} | {1e6 * nc:.1f} "
                         f"| {1e6 * nw:.1f} | {nc / lc:.2f} |")
            print(f"n={n:3d} {name:45s} lean {1e6 * lc:8.1f} us naive {1e6 * nc:8.1f} us",
                  flush=True)
        for name, cps, steps, rhs in scenes(model, args.duration, 3):
            sims.append((n, name, cps, steps, rhs))
    lines += [
        "",
        f"## Whole simulations ({args.duration:g} s simulated, best of 3, default integrator "
        "and step)",
        "",
        "CPU s per simulated second of ``simulate`` for each scene: without a tip force and "
        "without damping the integrator skips those terms. Free vibration starts from all "
        "joints at 1e-3 rad; the step load is 10 N along -z.",
        "",
        "| joints | scene | CPU s / sim s | steps | dynamics evaluations |",
        "|---|---|---|---|---|",
    ]
    for n, name, cps, steps, rhs in sims:
        lines.append(f"| {n} | {name} | {cps:.4g} | {steps} | {rhs} |")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, "\n".join(lines) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
