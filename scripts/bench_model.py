"""Benchmark of the core model: frequencies per pose, model build, static deflection.

Writes a Markdown table to results/bench_model.md (or the path given as the first argument).
BLAS is pinned to one thread before numpy is imported: on 2 cores a threaded BLAS made small
eigensolves many times slower.
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
import pinocchio as pin  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.model.urdf import render_urdf  # noqa: E402

BATCH = 32
REPEATS = 5


class Timing(tuple):
    """(wall, cpu) microseconds per call; formats as "wall (cpu)"."""

    def __format__(self, spec: str) -> str:
        return f"{self[0]:{spec}} ({self[1]:{spec}})"

    def __truediv__(self, k: float) -> Timing:
        return Timing((self[0] / k, self[1] / k))


def per_call_us(fn, budget_s: float = 0.05) -> Timing:
    """Best (over REPEATS) mean wall and process-CPU time of one call, in microseconds.

    On a shared machine the wall time includes waiting for a core; the CPU time does not.
    """
    fn()
    t0 = time.perf_counter()
    fn()
    once = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(budget_s / once))
    wall = cpu = np.inf
    for _ in range(REPEATS):
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(number):
            fn()
        wall = min(wall, (time.perf_counter() - t0) / number)
        cpu = min(cpu, (time.process_time() - c0) / number)
    return Timing((wall * 1e6, cpu * 1e6))


def main(out: Path) -> None:
    beam = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    rng = np.random.default_rng(0)
    load0 = os.getloadavg()[0]
    rows = []
    for n in range(1, 21):
        lengths = np.full(n + 1, beam.length_m / (n + 1))
        k = finite_segment_stiffness(beam, lengths)
        model = build_model(beam, lengths, k)
        data = model.new_data()
        pm = model.pin_model
        q = rng.uniform(0, np.pi / 2 / n, n)
        Q = rng.uniform(0, np.pi / 2 / n, (BATCH, n))
        urdf = model.urdf
        rows.append((
            n,
            per_call_us(lambda pm=pm, data=data, q=q: pin.crba(pm, data, q)),
            per_call_us(lambda model=model, q=q: model.natural_frequencies(q)),
            per_call_us(lambda model=model, Q=Q: model.natural_frequencies_batch(Q)) / BATCH,
            per_call_us(lambda lengths=lengths, k=k: build_model(beam, lengths, k)),
            per_call_us(lambda urdf=urdf: pin.buildModelFromXML(urdf)),
            per_call_us(lambda model=model: render_urdf(
                model.sections, model.lengths_m, model.stiffness_Nm_per_rad)),
        ))
    static_rows = []
    EI, L = beam.root_EI_Nm2, beam.length_m
    for n in (5, 10, 20):
        lengths = np.full(n + 1, L / (n + 1))
        model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
        times = []
        for alpha in (0.01, beam.load_index(), 10.0):
            F = np.array([0.0, 0.0, -alpha * EI / L**2])
            times.append(per_call_us(lambda model=model, F=F: model.static_deflection(F), 0.2))
        static_rows.append((n, *times))

    lines = [
        "# Core model benchmark",
        "",
        f"Beam `reference-random.json`, equal link lengths, finite-segment stiffness. "
        f"Python {platform.python_version()}, pinocchio {pin.__version__}, numpy "
        f"{np.__version__}, BLAS threads pinned to 1, {os.cpu_count()} CPUs, load average "
        f"{load0:.2f} at start. Each cell: wall time (process CPU time) per call, best of "
        f"{REPEATS} repeats of the mean; on a loaded machine the CPU time is the fairer figure.",
        "",
        "## Frequencies and model build (microseconds)",
        "",
        f"| n | bare `pin.crba` | frequencies, single pose | frequencies per pose, batch of "
        f"{BATCH} | `build_model` (hand-built, sections included) | "
        f"`pin.buildModelFromXML` (URDF string) | URDF rendering |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r[0]} | {r[1]:.2f} | {r[2]:.1f} | {r[3]:.2f} | {r[4]:.0f} | {r[5]:.0f} "
                     f"| {r[6]:.0f} |")
    lines += [
        "",
        "## Static deflection under a dead tip force (microseconds per solve)",
        "",
        f"Load index P L^2/(E I_root): small 0.01, the beam's load case "
        f"{beam.load_index():.3f} ({float(np.linalg.norm(beam.tip_force_N)):.0f} N), large 10.",
        "",
        "| n | small load | beam load case | large load |",
        "|---:|---:|---:|---:|",
    ]
    for r in static_rows:
        lines.append(f"| {r[0]} | {r[1]:.0f} | {r[2]:.0f} | {r[3]:.0f} |")
    atomic_write_text(out, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "results" / "bench_model.md")
