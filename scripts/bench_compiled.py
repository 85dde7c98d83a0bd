"""Benchmark: CPU per simulated second of the "compiled" integrator against scipy's DOP853, the
exponential integrator and MuJoCo's RK4 on the exported MJCF, at their accuracy.

Writes docs/benchmarks/bench_compiled.md (or the path given as the first argument). BLAS is
pinned to one thread before numpy is imported. CPU time (``time.process_time``), best of
``REPEATS`` (one run for a setting that costs more than a second), the whole ``simulate`` call.

Cases: finite-segment chains nR (n = 1, 3, 5, 8) of the uniform narrow strip, 1 s simulated:
a step tip load (-0.5 N along z, from rest) and a release from 0.1 rad on every joint,
undamped and with 2 % damping in the stiffness form (C = beta K, beta from mode 1 of the
straight pose: what the MJCF carries). Error: the largest tip deviation over the run (1 ms
samples) against scipy's DOP853 at rtol 1e-11 on Pinocchio's ABA, % of the peak tip
displacement. MuJoCo: RK4 on ``mjcf_text`` of the same chain and damping, released from the
same pose (releases only: a tip force through ``xfrc_applied`` acts at the body's centre of
mass, not the tip), timesteps 1 ms / 2^k so its steps land on the 1 ms samples, run by
``mujoco.rollout`` (C, no Python per step; only the rollout timed).
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.export import mjcf_text  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.options.integrators import Compiled, Exponential, ScipyIVP  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DURATION_S = 1.0
OUTPUT_DT_S = 1e-3
REPEATS = 3
FORCE_N = np.array([0.0, 0.0, -0.5])
Q0_RAD = 0.1
RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10)
STEP_RTOLS = (3e-4, 3e-5, 3e-6)  # the exponential integrator's step control (default 3e-4)
MJ_LEVELS = range(0, 9)  # timestep 1 ms / 2^k
TARGETS_PCT = (1.0, 0.1, 0.01)


def chain(beam, n: int):
    lengths = np.full(n + 1, 1.0 / (n + 1)) * beam.length_m
    return build_model(beam, lengths, finite_segment_stiffness(beam, lengths))


def cpu_per_s(fn) -> tuple[float, object]:
    """Best CPU time of ``fn`` per simulated second (s/s), and its last result."""
    best, out = np.inf, None
    for i in range(REPEATS):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
        if i == 0 and best > 1.0:
            break
    return best / DURATION_S, out


def scene(model, load: str, zeta: float) -> dict:
    n = model.n_joints
    kw = {"damping_ratio": zeta, "damping": "stiffness", "output_dt_s": OUTPUT_DT_S,
          "damping_pose": np.zeros(n)}
    if load == "step":
        kw["tip_force"] = FORCE_N
    else:
        kw["q0"] = np.full(n, Q0_RAD)
    return kw


def mujoco_tip(model, zeta: float, level: int) -> tuple[float, np.ndarray]:
    """CPU per simulated second of MuJoCo RK4 released from Q0 and its tip at the 1 ms samples.

    The steps run inside ``mujoco.rollout`` (C, no Python per step); only the rollout is timed,
    the tip positions are read from its joint angles afterwards (the floor of MuJoCo's cost).
    """
    import mujoco
    from mujoco import rollout

    m = mujoco.MjModel.from_xml_string(mjcf_text(model, zeta, timestep_s=OUTPUT_DT_S / 2**level))
    d = mujoco.MjData(m)
    d.qpos[:] = Q0_RAD
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, state0, spec)
    every = 2**level
    nstep = every * int(round(DURATION_S / OUTPUT_DT_S))
    cpu, (state, _) = cpu_per_s(lambda: rollout.rollout(m, d, state0, nstep=nstep))
    # FULLPHYSICS: time, then qpos
    q = np.vstack([state0[1:1 + m.nq], state[0, every - 1::every, 1:1 + m.nq]])
    return cpu, np.array([model.tip_position(qi) for qi in q])


def error_pct(tip: np.ndarray, ref_tip: np.ndarray) -> float:
    if not np.all(np.isfinite(tip)):
        return np.inf
    d_ref = ref_tip - ref_tip[0]
    return 100.0 * float(np.abs(tip - ref_tip).max() / np.abs(d_ref).max())


def bench_case(model, load: str, zeta: float) -> list[tuple[str, str, float, float, int]]:
    """Rows (method, setting, CPU s per simulated s, error %, steps) of one case."""
    kw = scene(model, load, zeta)
    ref = simulate(model, DURATION_S, integrator=ScipyIVP("DOP853", rtol=1e-11), **kw)
    rows = []
    settings = [("compiled", f"rtol {r:.0e}", Compiled(rtol=r)) for r in RTOLS]
    settings += [("DOP853", f"rtol {r:.0e}", ScipyIVP("DOP853", rtol=r)) for r in RTOLS[::2]]
    settings += [("exponential", f"step_rtol {r:.0e}", Exponential(step_rtol=r))
                 for r in STEP_RTOLS]
    for name, label, integ in settings:
        cpu, run = cpu_per_s(lambda integ=integ: simulate(model, DURATION_S, integrator=integ,
                                                          **kw))
        rows.append((name, label, cpu, error_pct(run.tip_position_m, ref.tip_position_m),
                     run.steps))
    if load == "release":
        for level in MJ_LEVELS:
            cpu, tip = mujoco_tip(model, zeta, level)
            rows.append(("MuJoCo RK4", f"dt {1e6 * OUTPUT_DT_S / 2**level:.3g} us", cpu,
                         error_pct(tip, ref.tip_position_m),
                         2**level * int(round(DURATION_S / OUTPUT_DT_S))))
    return rows


def cheapest(rows, method: str, target: float) -> str:
    ok = [(cpu, label) for name, label, cpu, err, _ in rows if name == method and err <= target]
    if not ok:
        return "not reached"
    cpu, label = min(ok)
    return f"{1e3 * cpu:.3g} ({label})"


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else \
        ROOT / "docs" / "benchmarks" / "bench_compiled.md"
    beam = load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
    simulate(chain(beam, 1), 0.01, integrator=Compiled())  # compile (or load the cache) first
    detail, summary = [], []
    methods = ("compiled", "DOP853", "exponential", "MuJoCo RK4")
    for n in (1, 3, 5, 8):
        model = chain(beam, n)
        for load in ("step", "release"):
            for zeta in (0.0, 0.02):
                rows = bench_case(model, load, zeta)
                case = f"{n}R {load}, zeta {zeta:g}"
                detail += [f"| {case} | {m} | {label} | {1e3 * cpu:.3g} | {err:.2g} | {steps} |"
                           for m, label, cpu, err, steps in rows]
                for target in TARGETS_PCT:
                    cells = [cheapest(rows, m, target) if (m != "MuJoCo RK4" or load ==
                                                           "release") else "-" for m in methods]
                    summary.append(f"| {case} | {target:g} | " + " | ".join(cells) + " |")
                print(*summary[-3:], sep="\n", flush=True)
    text = "\n".join([
        "# The compiled integrator against DOP853, the exponential integrator and MuJoCo",
        "",
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        "BLAS pinned to one thread; `python scripts/bench_compiled.py`. CPU ms per simulated "
        "second (best of 3, the whole call), 1 s simulated, 1 ms samples; error: largest tip "
        "deviation against scipy's DOP853 at rtol 1e-11, % of the peak tip displacement. "
        "Chains: finite-segment nR of the uniform narrow strip; step: -0.5 N tip load from "
        "rest; release: 0.1 rad on every joint; damping: 2 % in the stiffness form (the "
        "MJCF's). MuJoCo: RK4 on the exported MJCF, releases only, timesteps 1 ms / 2^k, "
        "stepped by `mujoco.rollout` (only the rollout timed: MuJoCo's floor).",
        "",
        "## Cheapest setting reaching each accuracy (CPU ms per simulated second)",
        "",
        "| case | error <= (% of peak) | " + " | ".join(methods) + " |",
        "|---|---|---|---|---|---|",
        *summary,
        "",
        # where the docs' include of the first table ends (a MyST option reads # as a comment)
        "<!-- every setting -->",
        "## Every setting",
        "",
        "| case | method | setting | CPU ms per simulated s | error (% of peak) | steps |",
        "|---|---|---|---|---|---|",
        *detail,
        "",
    ])
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
