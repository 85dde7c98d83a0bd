"""How far the 1D elastica is from the nonlinear 3D solid on the shipped beams.

Writes results/elastica_vs_solid.md: per beam, the large-deflection tip displacement of the
elastica and of the total-Lagrangian solid (default mesh), their difference relative to the solid's
displacement, the linear beam and solid for scale, and wall and CPU times (the CPU time is the
honest measure on a shared machine).

Usage: python scripts/elastica_vs_solid.py [BEAM.json ...]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.truth.beam_static import beam_static  # noqa: E402
from prbdm_pin.truth.elastica import elastica_static  # noqa: E402
from prbdm_pin.truth.solid import solid_static  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main(paths: list[str]) -> int:
    files = [Path(p) for p in paths] or sorted((ROOT / "examples" / "beams").glob("*.json"))
    rows = [
        "| beam | P L^2/EI_root | elastica tip disp. (x, z) mm | solid NL tip disp. (x, z) mm "
        "| elastica - solid, % of solid | linear beam z mm | linear solid z mm "
        "| solid DOFs | load steps | elastica s | solid NL wall s | solid NL CPU s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for path in files:
        beam = load_beam(path)
        t0 = time.perf_counter()
        el = elastica_static(beam)
        t1, c1 = time.perf_counter(), time.process_time()
        so = solid_static(beam, nonlinear=True)
        t2, c2 = time.perf_counter(), time.process_time()
        lb = beam_static(beam)
        ls = solid_static(beam)
        d_el, d_so = el.tip_displacement_m, so.tip_displacement_m
        rel = np.linalg.norm(d_el - d_so) / np.linalg.norm(d_so)
        rows.append(
            f"| {beam.name} | {beam.load_index():.3f} "
            f"| ({1e3 * d_el[0]:.3f}, {1e3 * d_el[2]:.3f}) "
            f"| ({1e3 * d_so[0]:.3f}, {1e3 * d_so[2]:.3f}) "
            f"| {100 * rel:.2f} | {1e3 * lb.tip_displacement_m[2]:.3f} "
            f"| {1e3 * ls.tip_displacement_m[2]:.3f} | {so.dofs} | {so.load_steps} | {t1 - t0:.2f} "
            f"| {t2 - t1:.1f} | {c2 - c1:.1f} |"
        )
        print(rows[-1], flush=True)
    out = ROOT / "results" / "elastica_vs_solid.md"
    out.parent.mkdir(exist_ok=True)
    atomic_write_text(out, "# Elastica vs nonlinear solid (default solid mesh)\n\n"
                      + "\n".join(rows) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
