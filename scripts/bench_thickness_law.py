"""A thickness law t(x): the 1D beam truth of wedges against Kirchhoff and a converged FE, and
joint-spring fits of a thickness-tapered panel against that truth.

Wedges (constant width, thickness tapering linearly to t_tip / t_0 at the tip): lambda_1 =
omega_1 L^2 sqrt(rho A_0 / (E I_0)) of the package's 1D truth (200 Hermite elements) against a
separate numpy Hermite FE with Richardson extrapolation (tests/tapered_reference.py) and against
the complete wedge's Bessel root 5.3151. Then 3R and 5R joint-spring fits (eigen, 3 and 4 modes)
of a steel panel tapering in width and thickness, their worst mode against the 1D truth.

Writes a Markdown table to results/bench_thickness_law.md and
docs/benchmarks/bench_thickness_law.md (or the path given with --out).

    python scripts/bench_thickness_law.py [--out results/bench_thickness_law.md]
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

from prbdm_pin.fitting import fit  # noqa: E402
from prbdm_pin.fitting.target import FitTarget  # noqa: E402
from prbdm_pin.member.geometry import Beam  # noqa: E402
from prbdm_pin.truth.beam import beam_modal  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))
from docs_tables import write_table  # noqa: E402
from tapered_reference import complete_taper_lambda1, richardson_lambda1  # noqa: E402

W, T0, L = 0.05, 0.01, 1.0  # m


def wedge_rows() -> list[str]:
    exact = complete_taper_lambda1(1)
    lines = [f"Complete wedge (Bessel root of J1 I2 + I1 J2): lambda_1 = {exact:.6f} "
             "(tabulated 5.315).", "",
             "| t_tip / t_0 | 1D truth lambda_1 | reference FE (Richardson) | truth vs reference "
             "| gap to the complete wedge (%) |", "|---|---|---|---|---|"]
    for r in (0.1, 0.05, 0.02, 0.01, 0.005, 0.002):
        b = Beam([0.0, L], [W, W], [T0, r * T0])
        rhoA0 = b.material.rho_kg_m3 * 2 * W * T0
        lam = float(beam_modal(b, 1).omega_rad_s[0] * L**2 * np.sqrt(rhoA0 / b.root_EI_Nm2))
        ref, _ = richardson_lambda1(r, 1, 50)
        lines.append(f"| {r:g} | {lam:.8f} | {ref:.8f} | {lam / ref - 1:+.1e} | "
                     f"{100 * (lam / exact - 1):+.3f} |")
    return lines


def fit_rows() -> list[str]:
    panel = Beam([0.0, 0.6], [0.05, 0.02], [0.005, 0.002], tip_force_N=[0.0, 0.0, -1.0],
                 name="tapered-thickness")
    lines = ["", "Panel: L 0.6 m, half-width 0.05 -> 0.02 m, thickness 5 -> 2 mm, steel.", "",
             "| model | modes fitted | worst mode error vs 1D truth (%) | per mode (%) "
             "| time (s) |",
             "|---|---|---|---|---|"]
    for n, modes in ((3, 3), (5, 4)):
        omega = beam_modal(panel, modes).omega_rad_s
        t0 = time.perf_counter()
        r = fit(panel, FitTarget(omega, panel.tip_force_N), n, frequencies=modes, starts=4,
                seed=0, progress=False, stiffness="joint")
        dt = time.perf_counter() - t0
        e = r.omega_export_errors_pct
        lines.append(f"| {n}R joint springs | {modes} | {np.max(np.abs(e)):.2e} | "
                     + " / ".join(f"{v:+.1e}" for v in e) + f" | {dt:.2f} |")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_thickness_law.md"))
    args = ap.parse_args()
    lines = ["# Thickness law: wedges and a thickness-tapered panel", ""]
    lines += wedge_rows() + fit_rows()
    lines += ["", "Written by `python scripts/bench_thickness_law.py`."]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_thickness_law")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
