"""Benchmark of the linear plant: ``linearize`` for n = 1..8 joints.

Cases: the straight pose (tip force in, tip z out), a deflected equilibrium under a tip load
with a strain actuator and three outputs, and a hub model under the load and gravity. Writes a
Markdown table to results/bench_plant.md (or the path given as the first argument). BLAS is
pinned to one thread before numpy is imported (small eigensolves on 2 shared cores).
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

from prbdm_pin.beam_file import load_beam  # noqa: E402
from prbdm_pin.io import atomic_write_text  # noqa: E402
from prbdm_pin.model import build_model  # noqa: E402
from prbdm_pin.plant.hub import Hub  # noqa: E402
from prbdm_pin.plant.inputs import StrainActuator  # noqa: E402
from prbdm_pin.plant.linearize import linearize  # noqa: E402
from prbdm_pin.stiffness import finite_segment_stiffness  # noqa: E402

REPEATS = 5


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
    ])
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
