"""Cost of the co-design chain's gradient: one design through truth -> fit -> PRBDM with and
without the chained derivatives (``prbdm_pin.codesign_point``), and the fit's design derivative
(``fit_design_gradient``) alone.

Designs (3R, 1D beam truth in the loop):

- ``tapered``: the co-design example's panel (examples/beams/tapered.json resampled at four
  equally spaced vertices), thickness and the four half-widths, at the example's start design;
- ``reference``: the reference random panel (examples/beams/reference-random.json) with
  thickness, two half-widths, two interior stations, E and rho.

Times are process CPU seconds, the best of ``--repeats`` runs (BLAS pinned to one thread).
Writes results/bench_codesign_gradient.md and prints the table.

    python scripts/bench_codesign_gradient.py [--repeats 3] [--out results]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.codesign import codesign_point  # noqa: E402
from prbdm_pin.fitting.design_gradient import fit_design_gradient  # noqa: E402
from prbdm_pin.io import atomic_write_text  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
JOINTS = 3


def designs() -> dict[str, tuple[pp.Design, np.ndarray]]:
    """The benchmark's designs and their points (SI units)."""
    tap = pp.load_beam(ROOT / "examples" / "beams" / "tapered.json")
    x = np.linspace(0.0, tap.length_m, 4)
    tap = dataclasses.replace(tap, x_m=x, half_width_m=tap.half_width_at(x))
    d_tap = pp.Design(tap, ("thickness",) + tuple(f"half_width[{i}]" for i in range(4)))
    ref = pp.load_beam(ROOT / "examples" / "beams" / "reference-random.json")
    d_ref = pp.Design(ref, ("thickness", "half_width[3]", "half_width[8]", "x[4]", "x[9]", "E",
                            "rho"))
    return {"tapered": (d_tap, np.array(d_tap.values)),
            "reference": (d_ref, np.array(d_ref.values))}


def best_cpu(fn, repeats: int) -> float:
    """Least process CPU time of ``repeats`` calls, s."""
    out = np.inf
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        out = min(out, time.process_time() - c0)
    return out


def measure(design: pp.Design, p: np.ndarray, repeats: int) -> dict[str, float]:
    """CPU seconds of: the design without and with gradients, the truth gradient, and the fit's
    design derivative alone."""
    beam = design.beam_at(p)
    tg = pp.truth_gradient(beam, design, model="beam", modes=JOINTS, static=False)
    target = pp.FitTarget(tg.omega_rad_s[:JOINTS], beam.tip_force_N)
    fr = pp.fit(beam, target, JOINTS, stiffness="joint", unique="nearest", progress=False)
    return {
        "values": best_cpu(lambda: codesign_point(design, p, JOINTS, gradient=False), repeats),
        "gradient": best_cpu(lambda: codesign_point(design, p, JOINTS), repeats),
        "truth_gradient": best_cpu(lambda: pp.truth_gradient(
            beam, design, model="beam", modes=JOINTS, static=False), repeats),
        "fit_gradient": best_cpu(lambda: fit_design_gradient(fr, design, p, tg), repeats),
    }


def table(rows: dict[str, tuple[int, dict[str, float]]]) -> str:
    """The markdown table of :func:`measure` per design."""
    lines = ["| design | variables | point, values only (CPU s) | point with gradients (CPU s) "
             "| of which the truth gradient (CPU s) | fit_design_gradient (CPU s) | chain rule "
             "(gradients - values - truth gradient, CPU s) |",
             "|" + "---|" * 7]
    for name, (nv, m) in rows.items():
        # the values-only point solves the truth too (one closed-form derivative): the truth
        # gradient's extra cost is its time less that solve, so the remainder is bounded below
        rest = m["gradient"] - m["values"]
        lines.append(f"| {name} | {nv} | {m['values']:.3f} | {m['gradient']:.3f} | "
                     f"{m['truth_gradient']:.3f} | {m['fit_gradient']:.3f} | <= {rest:.3f} |")
    lines.append("")
    lines.append(f"{JOINTS}R, 1D beam truth; best of the repeats; python {platform.python_version()}"
                 f", numpy {np.__version__}, BLAS on one thread.")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "results"))
    args = ap.parse_args(argv)
    rows = {name: (d.size, measure(d, p, args.repeats)) for name, (d, p) in designs().items()}
    text = table(rows)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / "bench_codesign_gradient.md",
                      "# Cost of the co-design chain's gradient\n\n" + text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
