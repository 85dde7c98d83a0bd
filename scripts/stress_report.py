"""Write results/stress_report.md: condition numbers of M, K and K^-1/2 M K^-1/2 at the extremes,
and the convergence of the static load sweep (P L^2 / EI 1e-6 ... 20, several directions).

Usage: python scripts/stress_report.py [--out results/stress_report.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.chain.eigen import COND_LIMIT, FREQUENCY_RTOL  # noqa: E402
from prbdm_pin.chain.stiffness import finite_segment_stiffness  # noqa: E402
from prbdm_pin.errors import SolveError  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.member.geometry import Beam  # noqa: E402
from prbdm_pin.member.material import Material  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402

LAYOUTS = {
    "0.02 L root link, 0.98 L": [0.02, 0.98],
    "0.98 L, 0.02 L tip link": [0.98, 0.02],
    "four 0.02 L links, 0.92 L tip": [0.02, 0.02, 0.02, 0.02, 0.92],
    "0.92 L root, four 0.02 L": [0.92, 0.02, 0.02, 0.02, 0.02],
    "8 equal links": [0.125] * 8,
    "40 equal links": [1 / 41] * 41,
}
TAPERS = {"uniform": (0.025, 0.025), "1000:1 narrowing": (0.5, 0.0005),
          "1:1000 widening": (0.0005, 0.5)}


def conditioning_rows():
    rows = []
    for tname, w in TAPERS.items():
        for lname, lengths in LAYOUTS.items():
            for t in (1e-4, 1e-2, 1e-1):
                for E in (1e6, 1e12):
                    beam = Beam(np.array([0.0, 1.0]), np.array(w), t, Material("m", E, 7850.0, 0.3))
                    lengths_a = np.array(lengths)
                    lengths_a[-1] = 1.0 - lengths_a[:-1].sum()
                    k = finite_segment_stiffness(beam, lengths_a)
                    model = build_model(beam, lengths_a, k)
                    M = model.mass_matrix()
                    A = M / np.sqrt(np.outer(k, k))
                    cA = np.linalg.cond(A)
                    try:
                        model.natural_frequencies()
                        status = "ok"
                    except SolveError:
                        status = "SolveError"
                    rows.append((tname, lname, t, E, np.linalg.cond(M), k.max() / k.min(), cA,
                                 np.finfo(float).eps * cA, status))
    return rows


def statics_rows():
    beam = Beam(np.array([0.0, 1.0]), np.array([0.025, 0.025]), 0.01)
    EI, n = beam.root_EI_Nm2, 32
    h = 1.0 / n
    lengths = np.concatenate([[h / 2], np.full(n - 1, h), [h / 2]])
    model = build_model(beam, lengths, np.full(n, EI / h), min_fraction=0.0)
    alphas = np.concatenate([np.logspace(-6, -1, 6), np.linspace(0.2, 20.0, 100)])
    rows = []
    for beta_deg in (0.0, 1.0, 10.0, 30.0, 60.0, 90.0, 120.0, 180.0):
        b = np.radians(beta_deg)
        ok = fail = 0
        worst = 0.0
        t0 = time.perf_counter()
        for a in alphas:
            F = a * EI * np.array([-np.cos(b), 0.0, -np.sin(b)])
            try:
                q, _ = model.static_deflection(F)
            except SolveError:
                fail += 1
                continue
            ok += 1
            JtF = model.tip_jacobian(q).T @ F
            kq = model.stiffness_Nm_per_rad * q
            worst = max(worst, np.linalg.norm(kq - JtF) / max(np.linalg.norm(JtF),
                                                              np.linalg.norm(kq), 1e-300))
        rows.append((beta_deg, alphas.size, ok, fail, worst, time.perf_counter() - t0))
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results/stress_report.md")
    args = ap.parse_args(argv)
    lines = ["# Stress report", "",
             f"Frequencies raise SolveError when cond(A) = cond(K^-1/2 M K^-1/2) exceeds "
             f"{COND_LIMIT:.3g} (highest frequency not accurate to {FREQUENCY_RTOL:g}).",
             "", "## Conditioning at the extremes (straight pose, finite-segment springs)", "",
             "| planform | layout | t (m) | E (Pa) | cond M | cond K | cond A | eps cond A | "
             "frequencies |", "|---|---|---|---|---|---|---|---|---|"]
    for r in conditioning_rows():
        lines.append("| {} | {} | {:g} | {:g} | {:.3g} | {:.3g} | {:.3g} | {:.2g} | {} |"
                     .format(*r))
    lines += ["", "## Static load sweep (32-joint chain, P L^2/EI = 1e-6 ... 20, 106 loads)", "",
              "Direction beta: 0 = axial compression, 90 = transverse, 180 = axial tension.", "",
              "| beta (deg) | loads | converged | SolveError | worst relative residual | "
              "time (s) |", "|---|---|---|---|---|---|"]
    for r in statics_rows():
        lines.append("| {:g} | {} | {} | {} | {:.2g} | {:.2f} |".format(*r))
    path = atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
