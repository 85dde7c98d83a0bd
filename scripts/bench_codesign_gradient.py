"""Cost of the co-design chain's gradient: one design through truth -> fit -> PRBDM with the
chained derivatives (``prbdm_pin.codesign_point``), its chain-rule phase, and the fit's design
derivative (``fit_design_gradient``) alone.

Designs (3R, 1D beam truth in the loop):

- ``tapered``: the co-design example's panel (examples/beams/tapered.json resampled at four
  equally spaced vertices), thickness and the four half-widths, at the example's start design;
- ``reference``: the reference random panel (examples/beams/reference-random.json) with
  thickness, two half-widths, two interior stations, E and rho.

Times are the best of ``--repeats`` runs (BLAS pinned to one thread): process CPU seconds, and
the wall seconds of the chain-rule phase the point reports.
Writes results/bench_codesign_gradient.md and prints the table.

    python scripts/bench_codesign_gradient.py [--repeats 5] [--out results]
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


def measure(design: pp.Design, p: np.ndarray, repeats: int) -> dict[str, float]:
    """Least over ``repeats`` runs: CPU seconds of the whole point with gradients, wall seconds
    of its chain-rule phase (``CodesignPoint.gradient_s``: the fit's design derivative, the
    model's direct term, the products) and CPU seconds of ``fit_design_gradient`` alone."""
    beam = design.beam_at(p)
    tg = pp.truth_gradient(beam, design, model="beam", modes=JOINTS, static=False)
    target = pp.FitTarget(tg.omega_rad_s[:JOINTS], beam.tip_force_N)
    fr = pp.fit(beam, target, JOINTS, stiffness="joint", unique="nearest", progress=False)
    out = {"point": np.inf, "chain": np.inf, "fit_gradient": np.inf}
    for _ in range(repeats):
        c0 = time.process_time()
        c = codesign_point(design, p, JOINTS)
        out["point"] = min(out["point"], time.process_time() - c0)
        out["chain"] = min(out["chain"], c.gradient_s)
        c0 = time.process_time()
        fit_design_gradient(fr, design, p, tg)
        out["fit_gradient"] = min(out["fit_gradient"], time.process_time() - c0)
    return out


def table(rows: dict[str, tuple[int, dict[str, float]]]) -> str:
    """The markdown table of :func:`measure` per design."""
    lines = ["| design | variables | point with gradients (CPU s) | chain-rule phase (wall s) | "
             "fit_design_gradient alone (CPU s) |", "|" + "---|" * 5]
    for name, (nv, m) in rows.items():
        lines.append(f"| {name} | {nv} | {m['point']:.3f} | {m['chain']:.4f} | "
                     f"{m['fit_gradient']:.4f} |")
    lines.append("")
    lines.append(f"Best of the repeats; {JOINTS}R, 1D beam truth; python "
                 f"{platform.python_version()}, numpy {np.__version__}, BLAS on one thread. The "
                 "point includes the truth solve with its shape derivatives and the fit.")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=5)
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
