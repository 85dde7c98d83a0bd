"""Loads on a PRBDM of the uniform narrow strip against closed-form and independent references.

Rows: the follower end moment's full circle (tip back at the root) and half circle (tip at
2 L / pi) of chains of equal links with half-length end links (springs E I / h); the sag under
self weight (as a distributed load) against q L^4 / (8 E I); the base-acceleration transfer
(tip displacement relative to the base per base acceleration) at DC and at omega_1 / 2 against
the clamped-free Euler-Bernoulli modal sum, and its relative L2 error over [0, 1.2 omega_5]
with 2 % modal damping on both sides. The 5R models: equal links with the package's
finite-segment springs, and a 5R eigen fit (joint springs) to the 1D beam truth (2 starts).
The references are tests/cantilever_loads.py's (none from the package).

usage: python scripts/bench_loads.py [--cache-dir DIR] [--out PATH]
Writes a Markdown table (default results/bench_loads.md, and docs/benchmarks/).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from docs_tables import write_table  # noqa: E402

import prbdm_pin as pp  # noqa: E402
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness  # noqa: E402
from prbdm_pin.cli import main as prbdm  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))  # the references, written once, with the tests'
from cantilever_loads import (  # noqa: E402
    base_transmissibility,
    equal_lengths,
    strip_properties,
)
from reference import BETA_L  # noqa: E402

DEFAULT_OUT = ROOT / "results" / "bench_loads.md"
BEAM = ROOT / "examples" / "beams" / "uniform-narrow.json"
ZETA = 0.02


def _polygon(beam, n: int, axes: str = "y"):
    L, EI, _ = strip_properties(beam)
    lengths = equal_lengths(L, n)
    k = np.full(n, EI * n / L)
    if axes != "y":
        k = spatial_stiffness(beam, lengths, axes, min_fraction=0.5 / n).reshape(n, len(axes))
        k[:, 0] = k[:, 1] = EI * n / L  # isotropic bending
        k = k.ravel()
    return pp.build_model(beam, lengths, k, axes=axes, min_fraction=0.5 / n)


def _fit5(cache: str | None) -> Path:
    out = Path(tempfile.mkdtemp(prefix="bench-loads-")) / "fit"
    args = ["fit", str(BEAM), "--joints", "5", "--truth-model", "beam", "--objective", "eigen",
            "--stiffness", "joint", "--starts", "2", "--out", str(out), "-q"]
    if cache:
        args += ["--cache-dir", cache]
    if prbdm(args) != 0:
        raise SystemExit("the 5R fit failed")
    return out / "fit.json"


def main(argv=None) -> int:
    """Run the rows and write the table."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cache-dir", default=None, help="truth cache (default $PRBDM_CACHE)")
    p.add_argument("--out", default=str(DEFAULT_OUT))
    a = p.parse_args(argv)
    beam = pp.load_beam(BEAM)
    L, EI, rhoA = strip_properties(beam)
    lines = ["Loads on PRBDMs of the uniform narrow strip (L = 1 m) against closed-form and "
             "independent references (`python scripts/bench_loads.py`).", "",
             "| check | model | value | reference | error |", "|---|---|---:|---:|---:|"]
    for n, axes in ((8, "y"), (8, "xyz"), (16, "xyz")):
        eq = pp.statics(_polygon(beam, n, axes),
                        tip_moment_follower_Nm=[0.0, -2 * np.pi * EI / L, 0.0])
        gap = np.linalg.norm(eq.tip_position_m) / L
        lines.append(f"| follower M = 2 pi EI / L: tip to root / L | {n}R {axes}, equal links "
                     f"| {gap:.1e} | 0 | {gap:.1e} |")
    for n in (8, 16, 32):
        eq = pp.statics(_polygon(beam, n, "xyz"),
                        tip_moment_follower_Nm=[0.0, -np.pi * EI / L, 0.0])
        d = np.linalg.norm(eq.tip_position_m)
        lines.append(f"| follower M = pi EI / L: tip distance, m | {n}R xyz, equal links | "
                     f"{d:.6f} | 2 L / pi = {2 * L / np.pi:.6f} | "
                     f"{100 * (d / (2 * L / np.pi) - 1):+.3f} % |")
    fit = pp.load_model(_fit5(a.cache_dir)).model
    lengths = equal_lengths(L, 5)
    equal = pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths))
    models = {"5R equal links, finite-segment springs": equal, "5R eigen fit": fit}
    q = rhoA * 9.81
    sag = q * L**4 / (8 * EI)
    for name, m in models.items():
        eq = pp.statics(m, distributed_N_m=[0.0, 0.0, -q])
        s = -eq.tip_displacement_m[2]
        lines.append(f"| self-weight sag, m | {name} | {s:.4e} | q L^4 / 8 EI = {sag:.4e} | "
                     f"{100 * (s / sag - 1):+.2f} % |")
    om = BETA_L[:5] ** 2 * np.sqrt(EI / (rhoA * L**4))
    for name, m in models.items():
        lin = pp.linearize(m, inputs=["base_accel_z"], outputs=["tip_z"], damping_ratio=0.0)
        for label, w in (("DC", 0.0), ("omega_1 / 2", 0.5 * om[0])):
            h = lin.frequency_response([w])[0, 0, 0].real
            ref = base_transmissibility(L, EI, rhoA, [w])[0].real
            lines.append(f"| base_accel_z -> tip_z at {label}, m/(m/s^2) | {name} | {h:.4e} | "
                         f"{ref:.4e} | {100 * (h / ref - 1):+.2f} % |")
        lin = pp.linearize(m, inputs=["base_accel_z"], outputs=["tip_z"], damping_ratio=ZETA)
        w = np.linspace(0.0, 1.2 * om[4], 6000)
        h = lin.frequency_response(w)[:, 0, 0]
        ref = base_transmissibility(L, EI, rhoA, w, zeta=ZETA)
        err = np.linalg.norm(h - ref) / np.linalg.norm(ref)
        lines.append(f"| base_accel_z -> tip_z, relative L2 over [0, 1.2 omega_5], {ZETA:.0%} "
                     f"damping | {name} | | modal sum, 400 modes | {100 * err:.2f} % |")
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    for path in write_table(a.out, "\n".join(lines) + "\n", DEFAULT_OUT, "bench_loads"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
