"""Run cost of the MJCF hub plant in MuJoCo, at the step that keeps it within 0.5 % of the peak.

Cases: 3R and 5R models of the reference beam (link lengths as in the tests, springs from the
finite-segment formula) on a hub (J_h = 2 kg m^2, r = 0.1 m) with one strain patch over
[0.05 L, 0.45 L]; damping: the stiffness form, 2 % on the lowest flexible mode. Input: a 40 N m
hub torque step and a 300 N m, 30 rad/s sine on the patch, 0.5 s. Reference: the nonlinear
equations by Pinocchio's ABA with the package's input map, DOP853 at rtol 1e-10. MuJoCo runs
the exported MJCF with RK4 (the export's integrator; ``data.ctrl`` set to the input at each
step's midpoint) at halving steps from the export's own (T_n/20) until hub angle and tip z are
within 0.5 % of their peaks; its wall time per simulated second is the best of 5 runs (the
Python loop that sets ``ctrl`` and steps included, and a loop of bare ``mj_step`` beside it).
Writes a Markdown table to results/bench_mjcf_plant.md (or the path given as the first
argument). BLAS is pinned to one thread before numpy is imported.
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

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.export import mjcf_text  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.hub import Hub  # noqa: E402
from prbdm_pin.model.inputs import StrainActuator, input_map  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.simulation.hub_damping import plant_damping  # noqa: E402

LENGTHS = {3: [0.15, 0.3, 0.3, 0.25], 5: [0.1, 0.2, 0.2, 0.2, 0.15, 0.15]}
HUB = Hub(2.0, 0.1)
XI = 0.02
DURATION_S = 0.5
TOLERANCE_PCT = 0.5
REPEATS = 5
NAMES = ("hub_torque", "strain[0]")


def plant_input(t: float) -> np.ndarray:
    """Hub torque (N m) and patch moment (N m) at time t (s)."""
    return np.array([40.0, 300.0 * np.sin(30.0 * t)])


def hub_plant(beam, n: int):
    """The n-joint hub model of ``beam`` and its strain patch."""
    lengths = np.asarray(LENGTHS[n], dtype=float) * beam.length_m / sum(LENGTHS[n])
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths), hub=HUB)
    return model, (StrainActuator(0.05 * beam.length_m, 0.45 * beam.length_m),)


def reference_run(model, actuators, u=plant_input, duration_s=DURATION_S):
    """Hub angle (rad) and tip z (m) as functions of time (s) of M(q) a = -K q - C v + B(q) u(t)
    by Pinocchio's ABA, DOP853 at rtol 1e-10 (C: the plant's stiffness form)."""
    import pinocchio as pin
    from scipy.integrate import solve_ivp

    K = model.stiffness_matrix()
    C = plant_damping(model, model.mass_matrix(), XI, "stiffness")
    data = model.new_data()
    nv = model.pin_model.nv

    def rhs(t, x):
        q, v = x[:nv], x[nv:]
        tau = -K @ q - C @ v + input_map(model, q, NAMES, actuators) @ u(t)
        return np.concatenate([v, pin.aba(model.pin_model, data, q, v, tau)])

    sol = solve_ivp(rhs, (0.0, duration_s), np.zeros(2 * nv), method="DOP853",
                    dense_output=True, rtol=1e-10, atol=1e-12)
    if not sol.success:
        raise RuntimeError(sol.message)

    def at(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        y = sol.sol(t)
        return y[0], np.array([model.tip_position(q)[2] for q in y[:nv].T])

    return at


def mujoco_run(m, u=plant_input, duration_s=DURATION_S):
    """Times (s), hub angle and tip z after every step of MuJoCo with ``m``'s step, up to
    ``duration_s``; ``ctrl`` is the input at each step's midpoint."""
    import mujoco

    h = m.opt.timestep
    d = mujoco.MjData(m)
    tip = m.site("tip").id
    mujoco.mj_forward(m, d)
    steps = int(np.floor(duration_s / h + 1e-9))
    hub, z = np.empty(steps + 1), np.empty(steps + 1)
    hub[0], z[0] = d.qpos[0], d.site_xpos[tip][2]
    for i in range(steps):
        d.ctrl[:] = u((i + 0.5) * h)
        mujoco.mj_step(m, d)
        mujoco.mj_kinematics(m, d)
        hub[i + 1], z[i + 1] = d.qpos[0], d.site_xpos[tip][2]
    return h * np.arange(steps + 1), hub, z


def errors_pct(ref, run) -> tuple[float, float]:
    """Largest hub-angle and tip-z differences of a MuJoCo ``run`` against the reference at its
    step times, % of the reference's peaks (inf when the run blew up)."""
    t, hub, z = run
    hub_ref, z_ref = ref(t)
    if not (np.all(np.isfinite(hub)) and np.all(np.isfinite(z))):
        return np.inf, np.inf
    return tuple(100.0 * float(np.abs(g - r).max() / np.abs(r).max())
                 for r, g in ((hub_ref, hub), (z_ref, z)))


def per_simulated_s(fn, duration_s: float) -> float:
    """Best (over REPEATS) wall time of ``fn`` per simulated second, ms/s."""
    best = np.inf
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return 1e3 * best / duration_s


def bare_steps(m, duration_s=DURATION_S) -> None:
    """mj_step alone over ``duration_s`` (constant ctrl), the floor under the Python loop."""
    import mujoco

    d = mujoco.MjData(m)
    d.ctrl[:] = plant_input(0.0)
    for _ in range(int(round(duration_s / m.opt.timestep))):
        mujoco.mj_step(m, d)


def bench_case(beam, n: int) -> dict:
    """The step that reaches TOLERANCE_PCT and MuJoCo's cost there, for the n-joint plant."""
    import mujoco

    model, acts = hub_plant(beam, n)
    text = mjcf_text(model, XI, actuators=acts, inputs=NAMES)
    ref = reference_run(model, acts)
    m = mujoco.MjModel.from_xml_string(text)
    exported = m.opt.timestep

    def error_at(h: float) -> tuple[float, float]:
        m.opt.timestep = h
        err = errors_pct(ref, mujoco_run(m))
        tried.append((h, err))
        return err

    # from the export's own step: double while within the tolerance, else halve until within
    tried = []
    h = exported
    if max(error_at(h)) <= TOLERANCE_PCT:
        while max(error_at(2.0 * h)) <= TOLERANCE_PCT:
            h *= 2.0
    else:
        while max(error_at(h / 2.0)) > TOLERANCE_PCT and h > 1e-6:
            h /= 2.0
        h /= 2.0
    m.opt.timestep = h
    passed = next(e for s, e in tried if s == h)
    return {"n": n, "exported_s": exported, "tried": tried, "step_s": h, "error": passed,
            "loop_ms": per_simulated_s(lambda: mujoco_run(m), DURATION_S),
            "bare_ms": per_simulated_s(lambda: bare_steps(m), DURATION_S),
            "omega": model.natural_frequencies()[1:]}


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "results" / "bench_mjcf_plant.md"
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    rows, tried = [], []
    for n in (3, 5):
        r = bench_case(beam, n)
        hub_err, z_err = r["error"]
        rows.append(f"| {n} | {r['omega'][-1]:.0f} | {1e6 * r['exported_s']:.0f} | "
                    f"{1e6 * r['step_s']:.0f} | {r['step_s'] * r['omega'][-1]:.2f} | "
                    f"{hub_err:.3g} / {z_err:.3g} | "
                    f"{r['loop_ms']:.1f} | {r['bare_ms']:.1f} |")
        tried += [f"- {n}R, step {1e6 * h:.0f} us: hub angle {e[0]:.3g} %, tip z {e[1]:.3g} %"
                  for h, e in r["tried"]]
        print(rows[-1], flush=True)
    text = "\n".join([
        "# MuJoCo run cost of the MJCF hub plant",
        "",
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        "BLAS pinned to one thread. Hub J_h = 2 kg m^2, r = 0.1 m; strain patch [0.05 L, "
        "0.45 L]; 40 N m hub torque step and 300 N m, 30 rad/s patch sine over 0.5 s; MuJoCo "
        "RK4 against DOP853 (rtol 1e-10) of Pinocchio's ABA at every step. Step: the largest of "
        "the export's T_n/20 times a power of 2 whose hub angle and tip z are within 0.5 % of "
        "their peaks. Cost: best of 5 wall times per simulated second, the Python "
        "loop that sets ctrl each step, and bare mj_step.",
        "",
        "| n | highest hub-model frequency (rad/s) | exported step (us) | step used (us) | "
        "h omega_max | error hub / tip z (% of peak) | MuJoCo loop (ms per simulated s) | "
        "bare mj_step (ms per simulated s) |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "RK4 is stable for h omega_max below about 2.83: where the next doubling fails with a "
        "huge error, the stability limit, not the accuracy, sets the step.",
        "",
        "Steps tried:",
        "",
        *tried,
        "",
    ])
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
