"""Cost of the co-design chain's gradient: one design through truth -> fit -> PRBDM with the
chained derivatives (``prbdm_pin.codesign_point``), the fit's design derivative
(``fit_design_gradient``) alone, and the model's direct dependence on the design at fixed
lengths and springs, analytic (``frequency_design_gradient``) against the central differences
of the chain it replaced.

Designs (3R, 1D beam truth in the loop):

- ``tapered``: the co-design example's panel (examples/beams/tapered.json resampled at four
  equally spaced vertices), thickness and the four half-widths, at the example's start design;
- ``reference``: the reference random panel (examples/beams/reference-random.json) with
  thickness, two half-widths, two interior stations, E and rho.

Times are process CPU seconds, the best of ``--repeats`` runs (BLAS pinned to one thread).
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
from prbdm_pin.chain.chain_derivatives import model_gradient  # noqa: E402
from prbdm_pin.fitting.codesign import codesign_point  # noqa: E402
from prbdm_pin.fitting.design_derivatives import fit_design_gradient  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.model.prbdm_model_derivatives import frequency_design_gradient  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
JOINTS = 3
STEP_REL = 1e-3  # the former central step of the direct term, times Design.scales


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


def _cpu(fn, repeats: int) -> float:
    """Least process CPU seconds of ``repeats`` calls."""
    out = np.inf
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        out = min(out, time.process_time() - c0)
    return out


def direct_by_differences(design: pp.Design, p: np.ndarray, L: np.ndarray, K: np.ndarray,
                          step_rel: float = STEP_REL) -> np.ndarray:
    """The model's direct term d omega/dp at fixed lengths and springs by central differences
    of the chain (the former method, as the comparison): (n, nv), rad/s per unit."""
    def omega(b: pp.Beam) -> np.ndarray:
        return model_gradient(b, L, K, tip_force_N=np.zeros(3)).omega_rad_s

    h = step_rel * design.scales
    cols = []
    for j in range(design.size):
        e = np.zeros(design.size)
        e[j] = h[j]
        cols.append((omega(design.beam_at(p + e)) - omega(design.beam_at(p - e))) / (2 * h[j]))
    return np.array(cols).T


def measure(design: pp.Design, p: np.ndarray, repeats: int) -> dict[str, float]:
    """CPU seconds (least over ``repeats``) of the whole point with gradients, of
    ``fit_design_gradient`` and of the model's direct term, analytic and by differences, and
    the largest difference between the two (relative to each mode's largest entry)."""
    beam = design.beam_at(p)
    tg = pp.truth_gradient(beam, design, model="beam", modes=JOINTS, static=False)
    target = pp.FitTarget(tg.omega_rad_s[:JOINTS], beam.tip_force_N)
    fr = pp.fit(beam, target, JOINTS, stiffness="joint", unique="nearest", progress=False)
    L, K = np.array(fr.lengths_m), np.array(fr.stiffness_Nm_per_rad)
    exact = frequency_design_gradient(beam, design, L, K)[1]
    fd = direct_by_differences(design, p, L, K)
    return {
        "point": _cpu(lambda: codesign_point(design, p, JOINTS), repeats),
        "fit_gradient": _cpu(lambda: fit_design_gradient(fr, design, p, tg), repeats),
        "direct": _cpu(lambda: frequency_design_gradient(beam, design, L, K), repeats),
        "direct_fd": _cpu(lambda: direct_by_differences(design, p, L, K), repeats),
        "gap": float(np.max(np.max(np.abs(fd - exact), axis=1)
                            / np.max(np.abs(exact), axis=1))),
    }


def table(rows: dict[str, tuple[int, dict[str, float]]]) -> str:
    """The markdown table of :func:`measure` per design."""
    lines = ["| design | variables | point with gradients | fit_design_gradient | direct term, "
             "analytic | direct term, central differences | differences vs analytic |",
             "|" + "---|" * 7]
    for name, (nv, m) in rows.items():
        lines.append(f"| {name} | {nv} | {m['point']:.3f} | {m['fit_gradient']:.4f} | "
                     f"{m['direct']:.5f} | {m['direct_fd']:.4f} | {m['gap']:.1e} |")
    lines.append("")
    lines.append(f"Process CPU seconds, best of the repeats; {JOINTS}R, 1D beam truth; python "
                 f"{platform.python_version()}, numpy {np.__version__}, BLAS on one thread. The "
                 "point includes the truth solve with its shape derivatives and the fit. The "
                 f"differences: central, step {STEP_REL:g} of Design.scales; their distance to "
                 "the analytic term is relative to each mode's largest entry.")
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
