"""Which large-deflection tip is consistent with the plate truth the frequencies come from, and how
far each candidate is from the nonlinear 3D solid.

For the tapered panel (examples/beams/tapered-linear.json) and the reference panel
(reference-random.json) this solves the nonlinear 3D solid at two mesh levels (its default and the
next: the finer one is the reference, their difference says it is converged), the linear 1D beam,
plate and solid, and every candidate large-deflection tip:

- ``elastica``: the plain 1D elastica with EI(x) = E 2 w(x) t^3 / 12;
- ``calibrated-elastica`` (the default): EI(x) scaled by u_1D / u_plate, the ratio of the 1D and
  the plate's linear tip deflections under the same load, so its small-load limit is the plate;
- ``anticlastic``: the elastica with Ashwell's anticlastic restraint of each bent section;
- ``calibrated+anticlastic``: both;
- ``solid``: the nonlinear solid at its default level (the ``large_deflection="solid"`` truth).

Errors are those of the tip displacement (x, z), normalised by the solid's tip displacement (the
honest measure) and, as the paper's Eq. 19 does, by the solid's tip position (about L); CPU times
(``time.process_time``) are what each solve costs on a shared machine.

Usage: python scripts/target_consistency.py [BEAM.json ...] [--out results/target_consistency.md]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.truth.beam_static import beam_static  # noqa: E402
from prbdm_pin.truth.elastica import elastica_static  # noqa: E402
from prbdm_pin.truth.plate_static import plate_static  # noqa: E402
from prbdm_pin.truth.solid import default_solid_level, solid_static  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BEAMS = [ROOT / "examples" / "beams" / "tapered-linear.json",
         ROOT / "examples" / "beams" / "reference-random.json"]


def _timed(f, *a, **k):
    c = time.process_time()
    out = f(*a, **k)
    return out, time.process_time() - c


def _xz(s) -> np.ndarray:
    return np.asarray(s.tip_displacement_m)[[0, 2]]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("beams", nargs="*", help="beam JSON files (default: tapered and reference)")
    ap.add_argument("--out", default=str(ROOT / "results" / "target_consistency.md"))
    args = ap.parse_args()
    paths = [Path(p) for p in args.beams] or BEAMS

    lin_rows = [
        "| beam | P L^2/EI_root | 1D beam z mm | plate z mm | solid z mm (level) "
        "| gap 100 (u_1D/u_plate - 1) % | solid vs plate % |",
        "|---|---|---|---|---|---|---|",
    ]
    nl_rows = [
        "| beam | candidate | tip displacement (x, z) mm | error / solid displacement % "
        "| error / solid position % | z error % | CPU s |",
        "|---|---|---|---|---|---|---|",
    ]
    conv_rows = ["| beam | solid level | DOFs | NL tip (x, z) mm | CPU s |",
                 "|---|---|---|---|---|"]
    for path in paths:
        beam = load_beam(path)
        lev = default_solid_level(beam)
        solids = {}
        for lv in (lev, lev + 1):
            s, c = _timed(solid_static, beam, level=lv, nonlinear=True)
            solids[lv] = (s, c)
            d = _xz(s)
            conv_rows.append(f"| {beam.name} | {lv} | {s.dofs} | ({1e3 * d[0]:.4f}, "
                             f"{1e3 * d[1]:.4f}) | {c:.1f} |")
            print(conv_rows[-1], flush=True)
        ref = _xz(solids[lev + 1][0])
        pos = ref + np.array([beam.length_m, 0.0])
        u1 = beam_static(beam).tip_displacement_m[2]
        up = plate_static(beam).tip_displacement_m[2]
        us = solid_static(beam, level=lev + 1).tip_displacement_m[2]
        gap = 100 * (u1 / up - 1)
        lin_rows.append(f"| {beam.name} | {beam.load_index():.3f} | {1e3 * u1:.3f} "
                        f"| {1e3 * up:.3f} | {1e3 * us:.3f} ({lev + 1}) | {gap:+.3f} "
                        f"| {100 * (us / up - 1):+.3f} |")
        print(lin_rows[-1], flush=True)
        scale = u1 / up
        cands = [
            ("elastica", {}),
            ("calibrated-elastica (default)", {"ei_scale": scale}),
            ("anticlastic", {"anticlastic": True}),
            ("calibrated+anticlastic", {"ei_scale": scale, "anticlastic": True}),
        ]
        results = []
        for name, kw in cands:
            c0 = time.process_time()
            # the calibration costs the plate's and the 1D beam's linear solves
            if "ei_scale" in kw:
                plate_static(beam)
                beam_static(beam)
            s = elastica_static(beam, **kw)
            results.append((name, _xz(s), time.process_time() - c0))
        s, c = solids[lev]
        results.append((f"solid (level {lev})", _xz(s), c))
        for name, d, c in results:
            e = d - ref
            nl_rows.append(
                f"| {beam.name} | {name} | ({1e3 * d[0]:.3f}, {1e3 * d[1]:.3f}) "
                f"| {100 * np.linalg.norm(e) / np.linalg.norm(ref):.3f} "
                f"| {100 * np.linalg.norm(e) / np.linalg.norm(pos):.3f} "
                f"| {100 * (d[1] / ref[1] - 1):+.3f} | {c:.2f} |")
            print(nl_rows[-1], flush=True)
    text = ("# Large-deflection target against the nonlinear 3D solid\n\n"
            "Reference: the nonlinear solid one level above its default (converged: see the "
            "first table). Produced by scripts/target_consistency.py.\n\n"
            "## Solid convergence\n\n" + "\n".join(conv_rows) + "\n\n"
            "## Linear tips (the small-load theory gap)\n\n" + "\n".join(lin_rows) + "\n\n"
            "## Large-deflection candidates\n\n" + "\n".join(nl_rows) + "\n")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
