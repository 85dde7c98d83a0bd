"""Round members and section tables: the 1D truth of tubes and cones against their references,
and joint-spring fits of a tube boom and a cone against that truth.

Tube (aluminium, L 1 m, D 30 mm, d 26 mm): the first three bending frequencies against
beta_n L = 1.8751, 4.6941, 7.8548 with I = pi (D^4 - d^4) / 64, and the first three torsion
frequencies against (2n - 1) pi / (2 L) sqrt(G J / (rho I_p)). Solid cones (D tapering linearly
to D_tip / D_0): lambda_1 = omega_1 L^2 sqrt(rho A_0 / (E I_0)) against a separate numpy Hermite
FE with Richardson extrapolation (tests/tapered_reference.py) and the complete cone's Bessel root
8.7193. Then 5R joint-spring fits (eigen, 5 modes) of the tube and of a cone (D_tip / D_0 = 0.1),
planar, and a spatial 3R xyz fit of the tube (bending in both planes and torsion); and a section
table built from a width-tapered strip against that strip.

Writes a Markdown table to results/bench_round_sections.md and
docs/benchmarks/bench_round_sections.md (or the path given with --out).

    python scripts/bench_round_sections.py [--out results/bench_round_sections.md]
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
from scipy.optimize import brentq  # noqa: E402

from prbdm_pin.files.beam_file import beam_from_dict  # noqa: E402
from prbdm_pin.fitting import fit  # noqa: E402
from prbdm_pin.fitting.target import FitTarget  # noqa: E402
from prbdm_pin.member.geometry import Beam  # noqa: E402
from prbdm_pin.member.material import Material  # noqa: E402
from prbdm_pin.member.section_law import section_properties  # noqa: E402
from prbdm_pin.member.section_member import round_beam  # noqa: E402
from prbdm_pin.truth.beam import beam_modal  # noqa: E402
from prbdm_pin.truth.beam_spatial import beam_spatial_modal, beam_torsion_modes  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))
from docs_tables import write_table  # noqa: E402
from tapered_reference import complete_taper_lambda1, richardson_lambda1  # noqa: E402

ALU = Material("aluminium 6061", 69e9, 2700.0, 0.33)
L, D, DI, D0 = 1.0, 0.03, 0.026, 0.04  # m


def _tube() -> Beam:
    return round_beam([0.0, L], [D, D], [DI, DI], ALU, [0.0, 0.0, -1.0], "tube boom")


def _cone(ratio: float) -> Beam:
    return round_beam([0.0, L], [D0, ratio * D0], None, ALU, [0.0, 0.0, -1.0], "cone")


def tube_rows() -> list[str]:
    b = _tube()
    bl = np.array([brentq(lambda z: np.cos(z) * np.cosh(z) + 1.0, (k - 0.5) * np.pi - 0.6,
                          (k - 0.5) * np.pi + 0.6, xtol=1e-15) for k in (1, 2, 3)])
    I, A = np.pi * (D**4 - DI**4) / 64.0, np.pi * (D**2 - DI**2) / 4.0
    bend = bl**2 / L**2 * np.sqrt(ALU.E_Pa * I / (ALU.rho_kg_m3 * A))
    n = np.arange(1, 4)
    tors = (2 * n - 1) * np.pi / (2.0 * L) * np.sqrt(ALU.G_Pa / ALU.rho_kg_m3)
    wb, wt = beam_modal(b, 3).omega_rad_s, beam_torsion_modes(b, 3)[0]
    lines = ["Tube: aluminium 6061, L 1 m, D 30 mm, d 26 mm (200 elements).", "",
             "| mode | bending: truth (rad/s) | beta_n L formula | rel. error "
             "| torsion: truth (rad/s) | Saint-Venant | rel. error |",
             "|---|---|---|---|---|---|---|"]
    for k in range(3):
        lines.append(f"| {k + 1} | {wb[k]:.4f} | {bend[k]:.4f} | {wb[k] / bend[k] - 1:+.1e} | "
                     f"{wt[k]:.3f} | {tors[k]:.3f} | {wt[k] / tors[k] - 1:+.1e} |")
    return lines


def cone_rows() -> list[str]:
    exact = complete_taper_lambda1(2)
    A0, I0 = np.pi * D0**2 / 4.0, np.pi * D0**4 / 64.0
    lines = ["", f"Complete cone (Bessel root of J2 I3 + I2 J3): lambda_1 = {exact:.6f} "
             "(tabulated 8.719).", "",
             "| D_tip / D_0 | 1D truth lambda_1 | reference FE (Richardson) | truth vs reference "
             "| gap to the complete cone (%) |", "|---|---|---|---|---|"]
    for r in (0.1, 0.05, 0.02, 0.01, 0.005, 0.001):
        lam = float(beam_modal(_cone(r), 1).omega_rad_s[0] * L**2
                    * np.sqrt(ALU.rho_kg_m3 * A0 / (ALU.E_Pa * I0)))
        ref, _ = richardson_lambda1(r, 2, 50)
        lines.append(f"| {r:g} | {lam:.8f} | {ref:.8f} | {lam / ref - 1:+.1e} | "
                     f"{100 * (lam / exact - 1):+.3f} |")
    return lines


def fit_rows() -> list[str]:
    lines = ["", "| member | model | modes fitted | worst mode error vs 1D truth (%) "
             "| per mode (%) | time (s) |", "|---|---|---|---|---|---|"]
    for name, b in (("tube", _tube()), ("cone 0.1", _cone(0.1))):
        omega = beam_modal(b, 5).omega_rad_s
        t0 = time.perf_counter()
        r = fit(b, FitTarget(omega, b.tip_force_N), 5, frequencies=5, starts=4, seed=0,
                progress=False, stiffness="joint")
        dt = time.perf_counter() - t0
        e = r.omega_export_errors_pct
        lines.append(f"| {name} | 5R joint springs | 5 | {np.max(np.abs(e)):.2e} | "
                     + " / ".join(f"{v:+.1e}" for v in e) + f" | {dt:.2f} |")
    return lines


def table_rows() -> list[str]:
    strip = Beam([0.0, 0.4, 1.0], [0.05, 0.04, 0.02], 0.01)
    sp = section_properties(strip, strip.x_m)
    keys = ("EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "rhoA_kg_m", "rhoI_y_kg_m", "rhoI_z_kg_m")
    table = beam_from_dict({"x": list(strip.x_m), "section": {
        "kind": "table", **{k: [float(v) for v in getattr(sp, k)] for k in keys}}})
    a, b = beam_modal(table, 4).omega_rad_s, beam_modal(strip, 4).omega_rad_s
    return ["", "Section table of a width-tapered steel strip (half-width 0.05 -> 0.04 -> "
            "0.02 m, 10 mm: E I_y and rho A linear, so the table is the same member):", "",
            "| mode | table (rad/s) | planform (rad/s) | rel. difference |", "|---|---|---|---|",
            *(f"| {k + 1} | {a[k]:.6f} | {b[k]:.6f} | {a[k] / b[k] - 1:+.1e} |"
              for k in range(4))]


def spatial_rows() -> list[str]:
    m = beam_spatial_modal(_tube(), 3)
    kinds = ", ".join(f"{k} {w:.1f}" for k, w in zip(m.kinds, m.omega_rad_s, strict=True))
    return ["", f"Tube, all three families of the 1D truth (rad/s): {kinds}."]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_round_sections.md"))
    args = ap.parse_args()
    lines = ["# Round members and section tables: tube, cones, fits", ""]
    lines += tube_rows() + spatial_rows() + cone_rows() + fit_rows() + table_rows()
    lines += ["", "Written by `python scripts/bench_round_sections.py`."]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_round_sections")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
