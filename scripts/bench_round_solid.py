"""Plate and 3D solid truths with a thickness law, and the 3D solid of round tubes and rods.

Part 1: a thickness-tapered strip (L 1 m, width 50 mm, t 10 -> 7 -> 4 mm with a kink at 0.4 m,
nu = 0 so that the strip's modes are the 1D beam's exactly) with the Argyris and Morley plates
and the 3D solid at several mesh levels, against the 1D truth with the law; wedges with the
plate against the tapered-member reference FE (tests/tapered_reference.py).

Part 2: tubes and rods (steel, and the same with nu = 0) with ``tube_solid_modes`` at 20, 40 and
80 elements along x, bending against the Timoshenko reference (tests/tube_timoshenko_reference.py,
Cowper's shear coefficient, Richardson-extrapolated) and Euler-Bernoulli beta_n L, torsion and
extension against the bar values.

Writes a Markdown table to results/bench_round_solid.md and docs/benchmarks/bench_round_solid.md
(or the path given with --out).

    python scripts/bench_round_solid.py [--out results/bench_round_solid.md]
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

from prbdm_pin.member.geometry import Beam  # noqa: E402
from prbdm_pin.member.material import Material  # noqa: E402
from prbdm_pin.truth.beam import beam_modal  # noqa: E402
from prbdm_pin.truth.plate import plate_modes  # noqa: E402
from prbdm_pin.truth.solid import solid_modal  # noqa: E402
from prbdm_pin.truth.tube_solid import tube_solid_modes  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))
from docs_tables import write_table  # noqa: E402
from tapered_reference import complete_taper_lambda1, richardson_lambda1  # noqa: E402
from tube_timoshenko_reference import timoshenko_richardson  # noqa: E402

STEEL = Material()
STEEL_NU0 = Material("steel, nu = 0", STEEL.E_Pa, STEEL.rho_kg_m3, 0.0)
AL_NU0 = Material("aluminium, nu = 0", 70e9, 2700.0, 0.0)
BETA_L = np.array([1.8751040687, 4.6940911330, 7.8547574382])


def _nearest(w, ref):
    return np.array([w[np.argmin(np.abs(w / r - 1.0))] for r in ref])


def _fmt(a) -> str:
    return " / ".join(f"{v:+.1e}" for v in np.atleast_1d(a))


def law_rows() -> list[str]:
    strip = Beam([0.0, 0.4, 1.0], [0.025] * 3, [0.010, 0.007, 0.004], AL_NU0)
    ref = beam_modal(strip, 5).omega_rad_s[:3]
    lines = ["## Thickness law: plate and solid against the 1D truth", "",
             "Strip L 1 m, width 50 mm, t 10 -> 7 -> 4 mm (kink at x = 0.4 m), aluminium with "
             "nu = 0 (the strip's modes are then exactly the 1D beam's). Relative error of "
             "modes 1 / 2 / 3 against the 1D truth with the law (200 Hermite elements).", "",
             "| truth | mesh level | DOFs | modes 1 / 2 / 3 vs 1D truth | time (s) |",
             "|---|---|---|---|---|"]
    for element, levels in (("argyris", (0, 1, 2)), ("morley", (0, 1, 2, 3))):
        for lv in levels:
            t0 = time.perf_counter()
            pm = plate_modes(strip, lv, 10, element)
            dt = time.perf_counter() - t0
            e = _nearest(pm.omega_rad_s, ref) / ref - 1.0
            lines.append(f"| plate-{element} | {lv} | {pm.dofs} | {_fmt(e)} | {dt:.2f} |")
    for lv in (0, 1, 2):
        t0 = time.perf_counter()
        sm = solid_modal(strip, lv, 12)
        dt = time.perf_counter() - t0
        e = _nearest(sm.omega_rad_s, ref) / ref - 1.0
        lines.append(f"| solid (shear, rotary inertia: below 1D) | {lv} | {sm.dofs} | {_fmt(e)} "
                     f"| {dt:.2f} |")
    exact = complete_taper_lambda1(1)
    lines += ["", "Wedges (plate-argyris level 0, nu = 0): lambda_1 = omega_1 L^2 sqrt(rho A_0 / "
              f"(E I_0)); complete wedge {exact:.4f}.", "",
              "| t_tip / t_0 | plate lambda_1 | reference FE (Richardson) | plate vs reference |",
              "|---|---|---|---|"]
    for r in (0.5, 0.2, 0.05, 0.01):
        b = Beam([0.0, 1.0], [0.025] * 2, [0.01, 0.01 * r], AL_NU0)
        s = np.sqrt(AL_NU0.rho_kg_m3 * 0.01 / (AL_NU0.E_Pa * 0.01**3 / 12.0))
        lam = plate_modes(b, 0, 4).omega_rad_s[0] * s
        refl, _ = richardson_lambda1(r, 1)
        lines.append(f"| {r:g} | {lam:.8f} | {refl:.8f} | {lam / refl - 1:+.1e} |")
    return lines


def round_rows() -> list[str]:
    lines = ["", "## Round tubes and rods (3D solid, `tube_solid_modes`)", "",
             "L = 1 m, 16 elements around, 1 through the wall; bending modes 1 / 2 / 3 against "
             "the Timoshenko reference (Cowper's shear coefficient) and that reference against "
             "Euler-Bernoulli (beta_n L = 1.8751, 4.6941, 7.8548); torsion and extension "
             "(mode 1) against (2 n - 1) pi / (2 L) sqrt(G / rho) and sqrt(E / rho).", "",
             "| member | material | elements along x | DOFs | bending vs Timoshenko | "
             "Timoshenko vs E-B | torsion | extension | y/z pair split | time (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    cases = (("tube D 20, d 15 mm", (0.02, 0.02, 0.015, 0.015)),
             ("rod D 20 mm", (0.02, 0.02, 0.0, 0.0)),
             ("rod D 20 -> 10 mm", (0.02, 0.01, 0.0, 0.0)),
             ("tube D 30 -> 20, d 24 -> 12 mm", (0.03, 0.02, 0.024, 0.012)))
    for name, (D0, D1, d0, d1) in cases:
        for mat in (STEEL_NU0, STEEL):
            ref, _ = timoshenko_richardson(1.0, D0, D1, d0, d1, mat.E_Pa, mat.G_Pa,
                                           mat.rho_kg_m3, mat.nu, n_modes=3, n=1000)
            uniform = D0 == D1 and d0 == d1
            if uniform:
                I_ = np.pi * (D0**4 - d0**4) / 64
                A = np.pi * (D0**2 - d0**2) / 4
                eb = _fmt(ref / (BETA_L**2 * np.sqrt(mat.E_Pa * I_ / (mat.rho_kg_m3 * A))) - 1)
            else:
                eb = "-"
            for n_along in (20, 40, 80):
                t0 = time.perf_counter()
                m = tube_solid_modes([0.0, 1.0], [D0, D1], [d0, d1], mat, n_modes=14,
                                     n_radial=1, n_along=n_along)
                dt = time.perf_counter() - t0
                y, z = m.of_kind("bending-y"), m.of_kind("bending-z")
                tor = m.of_kind("torsion")
                ax = m.of_kind("axial")
                w_t = np.pi / 2 * np.sqrt(mat.G_Pa / mat.rho_kg_m3)
                w_a = np.pi / 2 * np.sqrt(mat.E_Pa / mat.rho_kg_m3)
                tor_s = f"{tor[0] / w_t - 1:+.1e}" if uniform and tor.size else "-"
                ax_s = f"{ax[0] / w_a - 1:+.1e}" if uniform and ax.size else "-"
                k = min(y.size, z.size)
                split = f"{np.max(np.abs(z[:k] / y[:k] - 1)):.0e}"
                lines.append(f"| {name} | nu = {mat.nu:g} | {n_along} | {m.dofs} | "
                             f"{_fmt(y[:3] / ref - 1)} | {eb} | {tor_s} | {ax_s} | {split} | "
                             f"{dt:.1f} |")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_round_solid.md"))
    args = ap.parse_args()
    lines = ["# Plate and solid truths with a thickness law; round tubes and rods", ""]
    lines += law_rows() + round_rows()
    lines += ["", "Written by `python scripts/bench_round_solid.py`."]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_round_solid")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
