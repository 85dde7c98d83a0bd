"""Benchmark: simulation cost at equal accuracy, the package's integrators against MuJoCo.

Cases: finite-segment chains of the reference beam (``examples/beams/reference-random.json``,
links L/2N, L/N, ..., L/2N, the chains of ``bench_simulate.py``) with n = 1, 2, 3, 5, 8 joints;
a step tip load (the beam file's 2500 N along -z) from rest and a release from 0.1 rad on every
joint; undamped and 2 % damped in the stiffness form C = beta K (beta = 2 xi / omega_1 at the
straight pose), which the MJCF carries as joint ``damping`` (checked against the package's
matrix before any run); 1 s simulated.

Reference: ``simulate(method="DOP853", rtol=1e-11)``. Error: the largest |tip - reference| on
the 1 ms grid over the peak |tip_ref(t) - tip_ref(0)| (Euclidean norms). Cost: process CPU
time per simulated second, least of up to ``--repeats`` runs (runs under 0.2 s are repeated).

MuJoCo: the exported MJCF (``export_model(..., "mjcf")``, with its tip body; the step load is
``xfrc_applied`` on the tip body), RK4 and implicitfast at steps from 1e-2 s down, the tip read
from the ``tip`` site every step in a Python loop (and a bare ``mj_step(nstep=...)`` beside
it). The package: the default ``simulate``, then every integrator it offers (``Compiled`` when
``prbdm_pin.options.integrators`` has it, the exponential integrator's ``step_rtol``, the
solve_ivp methods' ``rtol`` from 1e-3 to 1e-11 with atol = rtol times the motion's largest joint
angle, the fixed-step schemes' ``dt_s``). Each sweep stops at the first setting that reaches
0.01 %, at the first run dearer than ``--max-run-cpu`` s, or (package) at the first run dearer
than a run that already reached 0.01 %.

Before the sweeps, the MJCF is checked against the package: the 5R step response at RK4 1e-4 s
within 0.1 % of the peak (undamped and damped; the largest n of the run where 5 is not in it).

Writes the table to results/bench_mujoco_accuracy.md and every run to
results/bench_mujoco_accuracy.csv, and with the default ``--out`` both to docs/benchmarks/ too.
BLAS is pinned to one thread before numpy is imported.

    python scripts/bench_mujoco_accuracy.py [--quick] [--n 1 2 3 5 8] [--out FILE.md]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import csv  # noqa: E402
import io  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import DOCS_TABLES, write_table  # noqa: E402
from mujoco_accuracy_mjcf import check_step_s, export_mjcf, mujoco_run, mujoco_sweep  # noqa: E402
from mujoco_accuracy_runs import (  # noqa: E402
    MUJOCO_DTS_S,
    OUTPUT_DT_S,
    TARGETS,
    Run,
    Scene,
    best_cpu,
    cheapest,
    package_methods,
    package_sweep,
)

from prbdm_pin.bench.run import finite_segment_chain  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402
from prbdm_pin.simulation.damping import damping_matrix  # noqa: E402

NAME = "bench_mujoco_accuracy"
RELEASE_RAD = 0.1
DAMPING = 0.02
REFERENCE_RTOL = 1e-11
# the MJCF's joint damping and springs are written as decimal text of the package's floats
MJCF_MATCH_RTOL = 1e-9
# the issue #29 check: RK4 at 1e-4 s (or the file's own step where RK4 needs a shorter one, as
# with stiffness-proportional damping on 8R) within 0.1 % of the peak
CHECK_DT_S, CHECK_ERROR = 1e-4, 1e-3


def scene(beam, n: int, load: str, xi: float) -> Scene:
    """Build a case and its DOP853 reference."""
    model = finite_segment_chain(beam, n)
    zero = np.zeros(n)
    force = np.asarray(beam.tip_force_N, dtype=float) if load == "step" else np.zeros(3)
    q0 = np.full(n, RELEASE_RAD) if load == "release" else zero
    # damping_pose: the MJCF's beta comes from the straight pose, simulate's from q0 by default
    kwargs = dict(damping_ratio=xi, damping="stiffness", damping_pose=zero)
    if load == "step":
        kwargs["tip_force"] = force
    else:
        kwargs["q0"] = q0
    cpu, ref = best_cpu(lambda: simulate(model, 1.0, method="DOP853", rtol=REFERENCE_RTOL,
                                         output_dt_s=OUTPUT_DT_S, **kwargs), 1)
    tip = ref.tip_position_m
    label = f"{n}R {load}, {'undamped' if xi == 0.0 else f'{xi:.0%} damped'}"
    return Scene(label, n, load, xi, model, kwargs, force, q0, tip,
                 float(np.linalg.norm(tip - tip[0], axis=1).max()),
                 float(np.abs(ref.q_rad).max()), cpu)


def mjcf_mismatch(m, sc: Scene) -> float:
    """Largest relative difference between the MJCF's joint springs and damping and the
    package's K and C (stiffness form at the straight pose; C must be diagonal)."""
    model = sc.model
    K = model.stiffness_matrix()
    C = damping_matrix(model.mass_matrix(), K, sc.damping_ratio, "stiffness")
    off = float(np.abs(C - np.diag(np.diag(C))).max()) / max(float(np.abs(C).max()), 1e-300)
    k = np.diag(K)
    dk = float(np.abs(m.jnt_stiffness - k).max() / k.max())
    c = np.diag(C)
    dc = float(np.abs(m.dof_damping - c).max() / k.max()) if sc.damping_ratio == 0.0 \
        else float(np.abs(m.dof_damping - c).max() / c.max())
    return max(off, dk, dc)


def _machine() -> str:
    import mujoco
    import pinocchio
    import scipy

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores; Python {platform.python_version()}, numpy "
            f"{np.__version__}, scipy {scipy.__version__}, pinocchio {pinocchio.__version__}, "
            f"mujoco {mujoco.__version__}")


def _ms(r: Run | None) -> str:
    return "" if r is None else f"{1e3 * r.cpu_s_per_s:.3g}"


def _dt(r: Run | None) -> str:
    return "not reached" if r is None else f"{r.value:.2g}"


def _ratio(a: Run | None, b: Run | None, bare: bool = False) -> str:
    if a is None or b is None:
        return ""
    return f"{a.cpu_s_per_s / (b.bare_cpu_s_per_s if bare else b.cpu_s_per_s):.2g}"


def tables(scenes: list[Scene], runs: dict[str, list[Run]], args, checks: list[str],
           header: list[str]) -> str:
    """The Markdown: the comparison at each target, then each case's reference and default."""
    lines = header + [
        "", "| case | target | RK4 step (s) | RK4 CPU ms/s | implicitfast step (s) | "
        "implicitfast CPU ms/s | package: cheapest setting | package CPU ms/s | package / RK4 | "
        "package / RK4 bare mj_step |", "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|"]
    for sc in scenes:
        rs = runs[sc.label]
        for tgt in TARGETS:
            rk = cheapest([r for r in rs if r.method == "rk4"], tgt)
            imp = cheapest([r for r in rs if r.method == "implicitfast"], tgt)
            pk = cheapest([r for r in rs if r.engine == "package"], tgt)
            lines.append(
                f"| {sc.label} | {tgt:.2%} | {_dt(rk)} | {_ms(rk)} | {_dt(imp)} | {_ms(imp)} | "
                f"{'not reached' if pk is None else pk.setting} | {_ms(pk)} | "
                f"{_ratio(pk, rk)} | {_ratio(pk, rk, bare=True)} |")
    lines += ["", "Each case's reference, the package's default and the run closest to the "
              "reference (an independent engine or method: a bound on the reference's own "
              "error plus its own):", "",
              "| case | omega_max (rad/s) | peak (mm) | reference CPU s | default: error | "
              "default CPU ms/s | closest run | its error |",
              "|---|---:|---:|---:|---:|---:|---|---:|"]
    for sc in scenes:
        rs = runs[sc.label]
        d = next(r for r in rs if r.knob == "default")
        ok = [r for r in rs if r.knob != "default" and math.isfinite(r.error)]
        close = min(ok, key=lambda r: r.error) if ok else None
        eng = "" if close is None else ("MuJoCo " if close.engine == "mujoco" else "") \
            + close.setting
        lines.append(
            f"| {sc.label} | {sc.model.natural_frequencies()[-1]:.0f} | {1e3 * sc.peak_m:.1f} | "
            f"{sc.ref_cpu_s:.2f} | {d.error:.2e} | {1e3 * d.cpu_s_per_s:.3g} | {eng} | "
            f"{'' if close is None else f'{close.error:.1e}'} |")
    failures: dict[str, list[str]] = {}
    capped = 0
    for rs in runs.values():
        for r in rs:
            if r.failure.startswith("stopped"):
                capped += 1
            elif r.failure:
                cases = failures.setdefault(f"{r.method}: {r.failure}", [])
                if r.case not in cases:
                    cases.append(r.case)
    notes = checks + [
        f"Runs stopped at the {args.max_run_cpu:g} s CPU cap: {capped} (every run is in the "
        "CSV beside this table)."] + [
        f"Failed: {k} ({', '.join(v) if len(v) <= 4 else f'{len(v)} cases'})."
        for k, v in sorted(failures.items())]
    lines += ["", "Notes:", ""] + [f"- {s}" for s in notes]
    return "\n".join(lines) + "\n"


def write_csv(path: Path, runs: dict[str, list[Run]]) -> str:
    """Every run, one line each; returns the text."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["case", "engine", "method", "knob", "value", "error", "cpu_s_per_s",
                "bare_cpu_s_per_s", "steps", "failure"])
    for rs in runs.values():
        for r in rs:
            w.writerow([r.case, r.engine, r.method, r.knob, f"{r.value:.6g}", f"{r.error:.6g}",
                        f"{r.cpu_s_per_s:.6g}", f"{r.bare_cpu_s_per_s:.6g}", r.steps, r.failure])
    atomic_write_text(path, buf.getvalue())
    return buf.getvalue()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=None, help="joint counts")
    ap.add_argument("--loads", nargs="+", default=["step", "release"],
                    choices=["step", "release"])
    ap.add_argument("--damping", type=float, nargs="+", default=[0.0, DAMPING],
                    help="mode 1's damping ratios (stiffness form)")
    ap.add_argument("--methods", nargs="+", default=None,
                    help="the package's integrators to sweep (default: all)")
    ap.add_argument("--repeats", type=int, default=3, help="least CPU of up to this many runs")
    ap.add_argument("--max-run-cpu", type=float, default=2.0,
                    help="a sweep stops after a run dearer than this, CPU s")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: n = 1, 2, the exponential integrator and DOP853 (and "
                         "Compiled when present), MuJoCo steps down to 5e-5 s, one run each, "
                         "runs capped at 0.2 s")
    ap.add_argument("--out", default=str(ROOT / "results" / f"{NAME}.md"))
    args = ap.parse_args(argv)
    wall0, cpu0, load0 = time.perf_counter(), time.process_time(), os.getloadavg()
    ns = args.n or ([1, 2] if args.quick else [1, 2, 3, 5, 8])
    names = tuple(args.methods) if args.methods else None
    dts = MUJOCO_DTS_S
    if args.quick:
        names = names or ("compiled", "exponential", "DOP853")
        dts = tuple(d for d in MUJOCO_DTS_S if d >= 5e-5)
        args.repeats, args.max_run_cpu = 1, min(args.max_run_cpu, 0.2)
    methods = package_methods(names)
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    scenes, runs, checks = [], {}, []
    check_n = 5 if 5 in ns else max(ns)
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            for load in args.loads:
                for xi in args.damping:
                    sc = scene(beam, n, load, xi)
                    print(f"== {sc.label}: reference {sc.ref_cpu_s:.2f} s CPU", flush=True)
                    mjcf = export_mjcf(sc, Path(tmp))
                    bad = mjcf_mismatch(mjcf[0], sc)
                    if bad > MJCF_MATCH_RTOL:
                        raise SystemExit(f"{sc.label}: the MJCF's springs or damping differ from "
                                         f"the package's by {bad:.1e} relative")
                    rs = []
                    if n == check_n and load == "step":
                        dt = check_step_s(mjcf[0], CHECK_DT_S)
                        chk = mujoco_run(*mjcf, sc, "rk4", dt, 1)
                        checks.append(f"MJCF check, {sc.label}: RK4 at {dt:.3g} s is "
                                      f"{chk.error:.1e} of the peak from the reference "
                                      f"(bound {CHECK_ERROR:g}); the MJCF's springs and "
                                      f"damping match the package's K and C to {bad:.0e}.")
                        print(checks[-1], flush=True)
                        if not chk.error <= CHECK_ERROR:
                            raise SystemExit(checks[-1] + " FAILED")
                    rs += mujoco_sweep(sc, mjcf, args.repeats, args.max_run_cpu, dts)
                    rs += package_sweep(sc, methods, args.repeats, args.max_run_cpu)
                    scenes.append(sc)
                    runs[sc.label] = rs
    load1 = os.getloadavg()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    header = [
        f"Machine: {_machine()}. BLAS on one thread, one process; load average {load0[0]:.2f} "
        f"at the start, {load1[0]:.2f} at the end; the run took {wall:.0f} s wall, {cpu:.0f} s "
        f"CPU. Cases: finite-segment chains of {beam.name}, step tip load "
        f"{beam.tip_force_N.tolist()} N from rest or release from {RELEASE_RAD} rad on every "
        "joint, undamped or 2 % damped (stiffness form, as the MJCF's joint damping), 1 s. "
        f"Reference: DOP853 at rtol {REFERENCE_RTOL:g}. Error: max |tip - reference| on the 1 ms "
        "grid over the peak |tip_ref(t) - tip_ref(0)|. Cost: CPU ms per simulated second, least "
        f"of up to {args.repeats} runs. MuJoCo: the exported MJCF, the tip read from its site "
        "every step in a Python loop (the last column: `mj_step(nstep=...)` alone); the "
        "package: the whole `simulate` call, 1 ms output. Each sweep stops at the first setting "
        f"that reaches 0.01 % or after a run dearer than {args.max_run_cpu:g} s CPU, so "
        "'not reached' means no setting within that cost; steps and tolerances were swept "
        "in factors of 2-2.5 (MuJoCo, fixed steps), 3 (step_rtol) and 10 (rtol)."]
    text = tables(scenes, runs, args, checks, header)
    out = Path(args.out)
    csv_text = write_csv(out.with_suffix(".csv"), runs)
    for path in write_table(out, text, ap.get_default("out"), NAME):
        print(f"wrote {path}")
    if out.resolve() == Path(ap.get_default("out")).resolve():
        print(f"wrote {atomic_write_text(DOCS_TABLES / f'{NAME}.csv', csv_text)}")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
