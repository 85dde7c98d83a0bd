"""Mesh DOFs the truth needs: shipped and random beams, plate and solid, default and next level.

Prints, per beam, the plate's Argyris DOFs at levels 0 and 1 with the estimate made before
meshing (``truth.mesh_budget``), and the solid's DOFs at its default level with the lower bound;
with ``--solve BEAM LEVEL`` it also times one plate modal solve and reports its peak memory.

    python scripts/bench_mesh_dofs.py [--random 8] [--solve examples/beams/reference-random.json 2]
"""

from __future__ import annotations

import argparse
import resource
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=8, help="random beams (seeds 0..N-1)")
    ap.add_argument("--solve", nargs=2, metavar=("BEAM", "LEVEL"))
    a = ap.parse_args()
    from skfem import Basis

    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.member.random_beams import random_beam
    from prbdm_pin.truth import solid
    from prbdm_pin.truth.feature_mesh import planform_quad_mesh
    from prbdm_pin.truth.mesh import element_size, planform_tri_mesh
    from prbdm_pin.truth.mesh_budget import SOLID_DOFS_PER_AREA, estimate_plate_dofs
    from prbdm_pin.truth.plate_elements import ElementTriArgyrisLocal

    beams = [load_beam(p) for p in sorted((ROOT / "examples" / "beams").glob("*.json"))]
    beams += [random_beam(np.random.default_rng(s), name=f"random seed {s}")
              for s in range(a.random)]
    print("| beam | plate L0 (estimate) | plate L1 (estimate) | solid level | solid DOFs "
          "(lower bound) |\n|---|---:|---:|---:|---:|")
    for b in beams:
        cells = []
        for lev in (0, 1):
            n = Basis(planform_tri_mesh(b, lev), ElementTriArgyrisLocal()).N
            cells.append(f"{n:,} ({estimate_plate_dofs(b, lev):,})")
        lev = solid.default_solid_level(b)
        q = planform_quad_mesh(b, lev, root_size_m=solid.ROOT_THICKNESSES * b.thickness_m)
        exact = 9 * (q.p.shape[1] + q.facets.shape[1] + q.t.shape[1])
        lower = SOLID_DOFS_PER_AREA * b.planform_area_m2 / (2 * element_size(b, lev)) ** 2
        print(f"| {b.name} | {cells[0]} | {cells[1]} | {lev} | {exact:,} ({lower:,.0f}) |",
              flush=True)
    if a.solve:
        from prbdm_pin.truth.plate import plate_modal

        b, lev = load_beam(a.solve[0]), int(a.solve[1])
        t0 = time.perf_counter()
        m = plate_modal(b, lev, 25, "argyris")
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
        print(f"\nplate modal solve of {b.name} at level {lev}: {m.dofs:,} DOFs, "
              f"{time.perf_counter() - t0:.1f} s wall, peak RSS {rss:.2f} GB")


if __name__ == "__main__":
    main()
