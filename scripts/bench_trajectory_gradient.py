"""Cost of a trajectory gradient (``prbdm_pin.trajectory_gradient``) against the trajectory.

The issue's target: a gradient costs <= 3x the trajectory. Per case, process CPU of

- the trajectory: the same fixed-step RK4 run with its cost integral and no sensitivities
  (``parameters=()``, the same steps);
- the gradient in each parameter group (``springs``, ``gain``, ``beta`` + ``dampers``,
  ``stations``, ``initial``: the start state) and in all of them at once;
- the central differences of J the gradient replaces: 2 runs per parameter;
- ``simulate``'s default integrator on the same closed loop, as a reference of what one
  simulated response costs in the package (its own steps and accuracy; the stiffness-proportional
  damping and the dampers enter it as a rate feedback on joint torques).

Cases: planar chains of 2, 3, 5 and 8 joints on the tapered strip, released from 0.01 rad per
joint under a 2 N step load at the tip, damped (beta = 1e-4 s, dampers 0.05 N m s/rad), with a
angle and rate feedback on joint 0; 0.2 s simulated, the default step (40 per fastest
oscillation's period, within RK4's stability).

Times are process CPU seconds, the best of ``--repeats`` runs (BLAS on one thread).
Writes ``<out>/bench_trajectory_gradient.md`` (with the default ``--out`` also
``docs/benchmarks/bench_trajectory_gradient.md``) and prints the table.

    python scripts/bench_trajectory_gradient.py [--repeats 3] [--duration 0.2] [--out results]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=0.01)
GROUPS = {"springs": ("springs",), "gain": ("gain",), "damping": ("beta", "dampers"),
          "stations": ("stations",), "initial": ("initial",),
          "all": ("springs", "stations", "beta", "dampers", "gain", "initial")}


def case(n: int):
    """The n-joint chain and the keyword arguments of its run."""
    L = np.full(n + 1, 1.0 / (n + 1))
    k = 3000.0 * (n + 1) / np.arange(1, n + 1) ** 0.5  # N m/rad, softer toward the tip
    model = pp.build_model(BEAM, L, k)
    G = np.zeros((1, 2 * n))
    G[0, 0], G[0, n] = 20.0, 2.0  # N m/rad, N m s/rad on joint 0
    kw = dict(q0=np.full(n, 0.01), tip_force=[0.0, 0.0, -2.0], inputs=("joint_torque[0]",),
              feedback=pp.StateFeedback(G), beta_s=1e-4,
              joint_damping_Nms_per_rad=np.full(n, 0.05))
    return model, kw


def _cpu(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        best = min(best, time.process_time() - c0)
    return best


def _simulate(model, kw, T):
    """simulate's default on the same loop: damping as rate feedback on every joint."""
    n = model.n_joints
    G = np.zeros((n, 2 * n))
    G[0] = kw["feedback"].gain[0]
    C = kw["beta_s"] * model.stiffness_Nm_per_rad + kw["joint_damping_Nms_per_rad"]
    G[np.arange(n), n + np.arange(n)] += C
    names = tuple(f"joint_torque[{j}]" for j in range(n))
    return pp.simulate(model, T, q0=kw["q0"], tip_force=kw["tip_force"], inputs=names,
                       u=pp.StateFeedback(G), damping_ratio=0.0)


def measure(n: int, T: float, repeats: int) -> dict:
    """CPU seconds of the trajectory, each gradient and the alternatives for the n-joint case."""
    model, kw = case(n)
    cost = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=1e-2)
    base = pp.trajectory_gradient(model, T, cost, parameters=(), **kw)
    out = {"steps": base.trajectory.steps,
           "trajectory": _cpu(lambda: pp.trajectory_gradient(model, T, cost, parameters=(),
                                                             **kw), repeats)}
    for name, groups in GROUPS.items():
        g = pp.trajectory_gradient(model, T, cost, parameters=groups, **kw)
        out[f"P_{name}"] = g.gradient.size
        out[name] = _cpu(lambda groups=groups: pp.trajectory_gradient(
            model, T, cost, parameters=groups, **kw), repeats)
    out["simulate"] = _cpu(lambda: _simulate(model, kw, T), repeats)
    return out


def table(rows: dict[int, dict], T: float) -> str:
    """The markdown table: CPU seconds and ratios to the trajectory."""
    lines = ["| chain | RK4 steps | trajectory, s | " + " | ".join(
        f"gradient: {g} (P), s (x)" for g in GROUPS) + " | central differences, all: 2P "
        "runs (x) | simulate default, s | trajectory / simulate | gradient all / simulate |",
        "|" + "---|" * (7 + len(GROUPS))]
    for n, m in rows.items():
        tr = m["trajectory"]
        cells = [f"{m[g]:.3f} ({m[f'P_{g}']}) ({m[g] / tr:.2f}x)" for g in GROUPS]
        lines.append(f"| {n}R | {m['steps']} | {tr:.3f} | " + " | ".join(cells)
                     + f" | {2 * m['P_all']}x | {m['simulate']:.3f} | "
                     f"{tr / m['simulate']:.0f}x | {m['all'] / m['simulate']:.0f}x |")
    lines.append("")
    lines.append(f"Process CPU seconds, best of the repeats, {T:g} s simulated; python "
                 f"{platform.python_version()}, numpy {np.__version__}, BLAS on one thread, "
                 f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores. The "
                 "trajectory is the same RK4 run with its cost and no sensitivities; x: the "
                 "gradient's CPU over it. Per stage the gradient adds Pinocchio's ABA "
                 "derivatives, one compiled call for the sensitivities' rates and, with the "
                 "stations, one compiled call evaluating the two moved chains per station in "
                 "the planar closed forms (the vector field's central difference). The last "
                 "two columns: the same run against simulate's default integrator on the same "
                 "loop (its own error-controlled steps, compiled).")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--duration", type=float, default=0.2)
    ap.add_argument("--joints", type=int, nargs="+", default=[2, 3, 5, 8])
    ap.add_argument("--out", default=str(ROOT / "results"))
    args = ap.parse_args(argv)
    rows = {n: measure(n, args.duration, args.repeats) for n in args.joints}
    text = table(rows, args.duration)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = "bench_trajectory_gradient"
    write_table(out / f"{name}.md", "# Cost of a trajectory gradient\n\n" + text + "\n",
                Path(ap.get_default("out")) / f"{name}.md", name)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
