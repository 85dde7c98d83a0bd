"""Benchmark of the plant, in one run: ``linearize`` for n = 1..8 joints, one closed-loop
simulated second for 3R-8R on a hub with a strain actuator, and the exported MJCF in MuJoCo
against ``simulate`` at equal accuracy.

- linearize: the straight pose (tip force in, tip z out), a deflected equilibrium under a tip
  load with a strain actuator and three outputs, and a hub model under the load and gravity.
- closed loop: the reference beam on a hub (J_h = 2 kg m^2, r = 0.1 m) with a strain patch over
  [0.05 L, 0.45 L], 2 % modal damping; an LQR (python-control) on the linearised plant slews
  the hub by 0.1 rad; ``simulate`` (exponential integrator, the gain inside its linearisation)
  over 1 s: CPU time per simulated second, and the error against DOP853 at rtol 1e-10 of the
  same closed loop (% of the peaks of hub angle and tip z).
- MuJoCo at equal accuracy: the open-loop scenario of ``bench_mjcf_plant.py`` (a hub-torque
  step and a patch sine, 0.5 s, stiffness-form damping): MuJoCo's RK4 at its largest step within
  0.5 % of the peaks, and ``simulate`` (exponential) on the same reference.

Writes a Markdown table to results/bench_plant.md (or the path given as the first argument).
BLAS is pinned to one thread before numpy is imported (small eigensolves on 2 shared cores).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.hub import Hub  # noqa: E402
from prbdm_pin.model.inputs import StrainActuator  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.plant.linearize import linearize  # noqa: E402

REPEATS = 5
HUB = Hub(2.0, 0.1)


def cpu_per_call_s(fn) -> float:
    """Best (over 3) process CPU time of one call, s."""
    best = np.inf
    for _ in range(3):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def closed_loop_row(beam, n: int) -> str:
    """One closed-loop simulated second of the n-joint hub plant under an LQR slew."""
    import control

    from prbdm_pin.simulation import StateFeedback, simulate

    L = beam.length_m
    lengths = np.full(n + 1, L / (n + 1))
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths), hub=HUB)
    acts = (StrainActuator(0.05 * L, 0.45 * L),)
    names = ("hub_torque", "strain[0]")
    lin = linearize(model, inputs=names, outputs=("hub_angle",), actuators=acts)
    nv = n + 1
    # hub angle error and rate weighted; the flexible coordinates through the spring energy
    Q = np.zeros((2 * nv, 2 * nv))
    Q[:nv, :nv] = lin.stiffness_Nm_per_rad
    Q[0, 0] += 100.0 * float(lin.mass_kg_m2[0, 0]) * float(lin.modal().omega_rad_s[1]) ** 2
    Q[nv:, nv:] = lin.mass_kg_m2
    K = control.lqr(lin.to_control(), Q, np.eye(2))[0]
    x_ref = np.zeros(2 * nv)
    x_ref[0] = 0.1
    fb = StateFeedback(K, x_ref=x_ref)
    kw = dict(inputs=names, u=fb, actuators=acts, outputs=("hub_angle", "tip_z"),
              output_dt_s=1e-3, damping_ratio=0.02)
    run = simulate(model, 1.0, **kw)
    ref = simulate(model, 1.0, method="DOP853", rtol=1e-10, **kw)
    err = np.abs(run.output_values - ref.output_values).max(axis=0) / np.abs(
        ref.output_values).max(axis=0)
    cpu = cpu_per_call_s(lambda: simulate(model, 1.0, **kw))
    cpu_ref = cpu_per_call_s(lambda: simulate(model, 1.0, method="DOP853", rtol=1e-10, **kw))
    return (f"| {n} | {run.steps} | {1e3 * cpu:.1f} | {1.0 / cpu:.0f}x | "
            f"{100 * err[0]:.2g} / {100 * err[1]:.2g} | {1e3 * cpu_ref:.0f} |")


def equal_accuracy_rows(beam) -> list[str]:
    """MuJoCo (RK4 at its largest step within 0.5 %) and simulate (exponential) on the open-loop
    scenario of bench_mjcf_plant, against the same DOP853 reference."""
    import bench_mjcf_plant as mj

    from prbdm_pin.simulation import simulate

    rows = []
    for n in (3, 5):
        r = mj.bench_case(beam, n)
        model, acts = mj.hub_plant(beam, n)
        ref = mj.reference_run(model, acts)
        kw = dict(inputs=mj.NAMES, u=mj.plant_input, actuators=acts,
                  outputs=("hub_angle", "tip_z"), damping_ratio=mj.XI, damping="stiffness",
                  output_dt_s=1e-3)
        run = simulate(model, mj.DURATION_S, **kw)
        errs = mj.errors_pct(ref, (run.t_s, run.output("hub_angle"), run.output("tip_z")))
        wall = mj.per_simulated_s(lambda m=model, k=kw: simulate(m, mj.DURATION_S, **k),
                                  mj.DURATION_S)
        rows.append(f"| {n} | MuJoCo RK4, step {1e6 * r['step_s']:.0f} us | "
                    f"{r['error'][0]:.2g} / {r['error'][1]:.2g} | {r['loop_ms']:.1f} "
                    f"(bare mj_step {r['bare_ms']:.1f}) |")
        rows.append(f"| {n} | simulate, exponential, {run.steps} steps | "
                    f"{errs[0]:.2g} / {errs[1]:.2g} | {wall:.1f} |")
        print(rows[-2], rows[-1], sep="\n", flush=True)
    return rows


def per_call_ms(fn, budget_s: float = 0.2) -> float:
    """Best (over REPEATS) mean wall time of one call, ms."""
    fn()
    t0 = time.perf_counter()
    fn()
    number = max(1, int(budget_s / max(time.perf_counter() - t0, 1e-7)))
    best = np.inf
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return 1e3 * best


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "results" / "bench_plant.md"
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    L = beam.length_m
    patch = StrainActuator(0.05 * L, 0.5 * L)
    load = np.array([0.0, 0.0, -5.0])
    rows = []
    for n in range(1, 9):
        lengths = np.full(n + 1, L / (n + 1))
        k = finite_segment_stiffness(beam, lengths)
        model = build_model(beam, lengths, k)
        hub = build_model(beam, lengths, k, hub=Hub(0.5, 0.05))
        straight = per_call_ms(lambda m=model: linearize(m))
        loaded = per_call_ms(lambda m=model: linearize(
            m, inputs=("tip_force_z", "strain[0]"), outputs=("tip_z", "q[0]", "tip_z_rate"),
            load_N=load, actuators=[patch]))
        hubbed = per_call_ms(lambda m=hub: linearize(
            m, inputs=("hub_torque", "tip_force_z"), outputs=("hub_angle", "tip_z"),
            load_N=load, gravity_m_s2=[0.0, 0.0, -9.81]))
        rows.append(f"| {n} | {straight:.3f} | {loaded:.3f} | {hubbed:.3f} |")
        print(rows[-1], flush=True)
    loop = []
    for n in range(3, 9):
        loop.append(closed_loop_row(beam, n))
        print(loop[-1], flush=True)
    equal = equal_accuracy_rows(beam)
    text = "\n".join([
        "# linearize timing",
        "",
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        "BLAS pinned to one thread; best of 5 mean wall time per call, ms.",
        "",
        "- straight: tip force in, tip z out, straight pose, modal damping",
        "- loaded: tip force and a strain actuator in, three outputs, equilibrium under a "
        "5 N tip load (planar statics)",
        "- hub: hub torque and tip force in, a hub model under the load and gravity (Newton "
        "equilibrium with Pinocchio's gravity terms)",
        "",
        "| n | straight (ms) | loaded (ms) | hub + gravity (ms) |",
        "|---|---|---|---|",
        *rows,
        "",
        "# Closed loop: one simulated second, hub + strain actuator, LQR slew of 0.1 rad",
        "",
        "| n | steps | CPU per simulated s (ms) | faster than real time | error hub / tip z "
        "(% of peak, vs DOP853 rtol 1e-10) | DOP853 CPU (ms) |",
        "|---|---|---|---|---|---|",
        *loop,
        "",
        "# Open loop at equal accuracy: MuJoCo (exported MJCF) and simulate",
        "",
        "| n | run | error hub / tip z (% of peak) | wall ms per simulated s |",
        "|---|---|---|---|",
        *equal,
        "",
    ])
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
