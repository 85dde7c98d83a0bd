"""The 1D Timoshenko truth: its convergence against the closed-form cantilever, and the criterion.

1. Convergence: a uniform steel bar (50 x 10 mm, nu = 0.28, Cowper's kappa) at slenderness
   L / r_g = 10, 50 and 1000; the relative error of modes 1 and 4 against the roots of the
   closed-form frequency equation (tests/timoshenko_reference.py) for both elements, per element
   count, and the observed order (log2 of the error ratio between the last two counts).
2. Criterion: the Euler-Bernoulli error 100 (omega_EB / omega_T - 1) of modes 1-4 from the
   frequency equation against the first-order estimate e_n = 50 c_n (r_g / L)^2 (1 + E / (kappa
   G)) of ``timoshenko_criterion``, at L / r_g = 10 ... 400.
3. The shipped strips: per mode the estimate and the two 1D truths' gap, and the first mode past
   0.1 %.

Writes a Markdown table to results/bench_timoshenko.md and docs/benchmarks/bench_timoshenko.md
(or the path given with --out). BLAS is pinned to one thread before numpy is imported.

    python scripts/bench_timoshenko.py [--out results/bench_timoshenko.md]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402
from timoshenko_reference import timoshenko_cantilever_omega  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.truth.beam_timoshenko import timoshenko_modal  # noqa: E402
from prbdm_pin.truth.timoshenko_criterion import (  # noqa: E402
    eb_error_estimate_pct,
    timoshenko_criterion,
)
from prbdm_pin.truth.timoshenko_sections import SectionLaws, shear_coefficient  # noqa: E402

E, NU, RHO = 205e9, 0.28, 7850.0
G = E / (2 * (1 + NU))
KAPPA = shear_coefficient("rectangle", NU)
B, T = 0.05, 0.01
A, I = B * T, B * T**3 / 12
RG = np.sqrt(I / A)
BETA = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875])
COUNTS = (10, 20, 40, 80)


def _bar(slenderness: float):
    L = slenderness * RG
    exact = timoshenko_cantilever_omega(L, E * I, KAPPA * G * A, RHO * A, RHO * I, 4)
    return L, SectionLaws(E * I, KAPPA * G * A, RHO * A, RHO * I), exact


def convergence_rows() -> list[str]:
    lines = ["## Convergence against the closed-form cantilever", "",
             "| L / r_g | element | mode | " + " | ".join(f"{n} el." for n in COUNTS)
             + " | order | time at 80 el. (s) |",
             "|---|---|---|" + "---|" * len(COUNTS) + "---|---|"]
    for slender in (10.0, 50.0, 1000.0):
        L, laws, exact = _bar(slender)
        for element in ("quadratic", "interdependent"):
            errs, dt = [], 0.0
            for n in COUNTS:
                t0 = time.process_time()
                w = timoshenko_modal(laws, L, 4, n, element=element).omega_rad_s
                dt = time.process_time() - t0
                errs.append(w / exact - 1.0)
            errs = np.array(errs)
            for k in (0, 3):
                e = errs[:, k]
                order = np.log2(abs(e[-2] / e[-1])) if e[-1] != 0 else float("nan")
                lines.append(f"| {slender:g} | {element} | {k + 1} | "
                             + " | ".join(f"{v:.1e}" for v in e) + f" | {order:.2f} | {dt:.3f} |")
    return lines


def criterion_rows() -> list[str]:
    lines = ["", "## The criterion's estimate against the frequency equation", "",
             f"Steel rectangle, kappa = {KAPPA:.4f}, 1 + E / (kappa G) = "
             f"{1 + E / (KAPPA * G):.3f}. Per mode: exact Euler-Bernoulli error (%) / estimate "
             "(%) / their ratio.", "",
             "| L / r_g | mode 1 | mode 2 | mode 3 | mode 4 |", "|---|---|---|---|---|"]
    for slender in (10.0, 20.0, 50.0, 100.0, 200.0, 400.0):
        L, _, exact = _bar(slender)
        eb = BETA**2 / L**2 * np.sqrt(E * I / (RHO * A))
        gap = 100 * (eb / exact - 1)
        est = eb_error_estimate_pct(4, 1 / slender, E / (KAPPA * G))
        lines.append(f"| {slender:g} | " + " | ".join(
            f"{g:.3g} / {e:.3g} / {g / e:.3f}" for g, e in zip(gap, est, strict=True)) + " |")
    return lines


def shipped_rows() -> list[str]:
    lines = ["", "## The shipped strips (estimate / gap of the two 1D truths, %)", "",
             "| beam | L / r_g | " + " | ".join(f"mode {k}" for k in range(1, 9))
             + " | first mode past 0.1 % |", "|---|---|" + "---|" * 8 + "---|"]
    for name in ("uniform-narrow", "tapered", "stepped-narrow"):
        beam = load_beam(ROOT / "examples" / "beams" / f"{name}.json")
        r = timoshenko_criterion(beam, n_modes=8)
        lines.append(f"| {name} | {r.slenderness:.0f} | " + " | ".join(
            f"{e:.3f} / {g:.3f}" for e, g in zip(r.estimate_pct, r.gap_pct, strict=True))
            + f" | {r.first_mode_needing} |")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_timoshenko.md"))
    args = ap.parse_args()
    lines = ["# The 1D Timoshenko truth and the criterion", ""]
    lines += convergence_rows() + criterion_rows() + shipped_rows()
    lines += ["", "Written by `python scripts/bench_timoshenko.py`."]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_timoshenko")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
