"""Benchmark: what the default integrator's rule (``Auto()``) picks per scene, against the two
integrators it picks between, at their accuracy.

Writes docs/benchmarks/bench_default_rule.md (or the path given as the first argument). BLAS is
pinned to one thread before numpy is imported. CPU time (``time.process_time``), best of
three (one run for a setting that costs more than a second), the whole ``simulate``
call (the rule's eigenvalues included in "auto").

Cases: finite-segment chains nR (n = 1, 2, 3, 5, 8) of the uniform narrow strip, 1 s simulated,
1 ms samples: a step tip load (-0.5 N along z, from rest) and a release from 0.1 rad on every
joint; undamped, 2 % modal damping (``simulate``'s default) and 2 % in the stiffness form
(C = beta K, beta from mode 1 of the straight pose). Error: the largest tip deviation over the
run against scipy's DOP853 at rtol 1e-11, % of the peak tip displacement. "compiled" is
``Compiled(rtol=1e-6)`` (the rule's pick at its default tolerance 1e-4), "exponential"
``Exponential()``.
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import platform  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.options.integrators import Auto, Compiled, Exponential, ScipyIVP  # noqa: E402
from prbdm_pin.simulation import simulate  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from bench_compiled import chain, cpu_per_s, error_pct  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DURATION_S = 1.0
OUTPUT_DT_S = 1e-3
FORCE_N = np.array([0.0, 0.0, -0.5])
Q0_RAD = 0.1
DAMPINGS = (("none", "modal", 0.0), ("2 % modal", "modal", 0.02),
            ("2 % stiffness", "stiffness", 0.02))


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else \
        ROOT / "docs" / "benchmarks" / "bench_default_rule.md"
    beam = load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
    simulate(chain(beam, 1), 0.01, integrator=Compiled())  # compile (or load the cache) first
    rows = []
    worst = 0.0
    for n in (1, 2, 3, 5, 8):
        model = chain(beam, n)
        for label, form, zeta in DAMPINGS:
            for load in ("step", "release"):
                kw = {"damping_ratio": zeta, "damping": form, "output_dt_s": OUTPUT_DT_S,
                      "damping_pose": np.zeros(n)}
                if load == "step":
                    kw["tip_force"] = FORCE_N
                else:
                    kw["q0"] = np.full(n, Q0_RAD)
                ref = simulate(model, DURATION_S, integrator=ScipyIVP("DOP853", rtol=1e-11),
                               **kw)
                cells = []
                for integ in (Compiled(rtol=1e-6), Exponential(), Auto()):
                    cpu, run = cpu_per_s(lambda m=model, integ=integ, kw=kw: simulate(
                        m, DURATION_S, integrator=integ, **kw))
                    cells.append((cpu, error_pct(run.tip_position_m, ref.tip_position_m),
                                  run.method))
                ok = [c for c in cells[:2] if c[1] <= 1e-2]  # the 0.01 % of the peak
                best = min(c[0] for c in ok)
                worst = max(worst, cells[2][0] / best)
                rows.append(f"| {n}R | {load} | {label} | "
                            + " | ".join(f"{1e3 * c:.3g} ({e:.2g} %)" for c, e, _ in cells[:2])
                            + f" | {cells[2][2]} | {1e3 * cells[2][0]:.3g} ({cells[2][1]:.2g} %)"
                            f" | {cells[2][0] / best:.2f} |")
                print(rows[-1], flush=True)
    text = "\n".join([
        "# The default integrator's rule against the two it picks between",
        "",
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        "BLAS pinned to one thread; `python scripts/bench_default_rule.py`. CPU ms per "
        "simulated second (best of 3, the whole call), 1 s simulated, 1 ms samples; in "
        "brackets the largest tip deviation against scipy's DOP853 at rtol 1e-11, % of the "
        "peak tip displacement. Chains: finite-segment nR of the uniform narrow strip; step: "
        "-0.5 N tip load from rest; release: 0.1 rad on every joint. compiled: "
        "`Compiled(rtol=1e-6)`; exponential: `Exponential()`; auto: `Auto()` (the default), "
        "the method it picked and its cost; last column: auto's cost over the cheaper of the "
        "two that reaches 0.01 % of the peak.",
        "",
        "| chain | load | damping | compiled | exponential | auto picks | auto | "
        "auto / cheapest at 0.01 % |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"Largest ratio: {worst:.2f}.",
        "",
    ])
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
