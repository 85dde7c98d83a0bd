"""Benchmark of the finite-element truth: DOFs, time split and mesh convergence per model and level.

For every shipped beam (examples/beams/*.json) and every model (Argyris plate, Morley plate, 1D
beam, and the 3D solid when ``--models`` asks for it) this solves the modal problem at several
mesh levels, selects the bending modes (``paper`` policy) and reports each level's error against
the finest level computed. Writes a Markdown table (default results/bench_truth.md).

``--plate-vs-solid`` adds a table of every beam-like bending mode of the plate (the ``shape``
selection's definition, lowest five) beside the 3D solid mode of the same centreline shape, for
the reference beam and the ``--seeds`` random beams, at each of ``--thicknesses``.

Wall times on a shared machine can be inflated several times by other processes: the table also
gives the process CPU time (``time.process_time``) of each solve, which is what the solve costs.

usage: python scripts/bench_truth.py [--models plate,plate-morley,beam] [--modes 5] [--out PATH]
       [--plate-vs-solid] [--seeds 0,1,2] [--thicknesses 0.01,0.005]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402
from prbdm_pin.member.geometry import Beam  # noqa: E402
from prbdm_pin.member.random_beams import random_beam  # noqa: E402
from prbdm_pin.truth import DEFAULT_PLATE_LEVEL, compute_modal  # noqa: E402
from prbdm_pin.truth.modes import label_modes, mac_matrix, select_modes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LEVELS = {
    "plate": (0, 1, 2),
    "plate-morley": (0, 1, 2, 3),
    "solid": (2, 3),
    "beam": (50, 100, 200, 400),
}


@dataclass(frozen=True)
class Row:
    beam: str
    model: str
    level: int
    dofs: int
    mesh_s: float
    basis_s: float
    assembly_s: float
    solve_s: float
    wall_s: float
    cpu_s: float
    mode_index: np.ndarray
    omega_rad_s: np.ndarray


def _run(beam, model: str, level: int, n_modes: int, n_computed: int) -> Row:
    t0, c0 = time.perf_counter(), time.process_time()
    if model == "beam":
        from prbdm_pin.truth.beam import beam_modal

        modal = beam_modal(beam, n_modes=n_computed, n_elements=level)
    else:
        modal = compute_modal(beam, model, level, n_computed)
    idx = select_modes(modal, n_modes, "paper")
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    t = modal.timings
    return Row(beam.name, model, level, int(modal.dofs), t.mesh_s, t.basis_s, t.assembly_s,
               t.solve_s, wall, cpu, idx, modal.omega_rad_s[idx])


def _table(rows: list[Row]) -> list[str]:
    out = [
        "Observed order: p in err ~ h^p between this level and the next, from the max error "
        "against the finest level, with h ~ DOFs^(-1/2) (plate, solid: planform refinement) or "
        "h ~ 1/elements (beam); the finest level is the reference, so the last rate of a group "
        "is biased high.",
        "",
        "| beam | model | level | DOFs | mesh s | basis s | assembly s | eigensolve s | wall s "
        "| CPU s | selected modes | max err vs finest % | err per mode vs finest % "
        "| observed order |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    groups: dict[tuple[str, str], list[Row]] = {}
    for r in rows:
        groups.setdefault((r.beam, r.model), []).append(r)
    for grp in groups.values():
        finest = grp[-1]
        maxerr = [float(np.max(np.abs(r.omega_rad_s / finest.omega_rad_s - 1.0))) for r in grp]
        dim = 1 if grp[0].model == "beam" else 2
        for k, r in enumerate(grp):
            err = 100.0 * (r.omega_rad_s / finest.omega_rad_s - 1.0)
            same = np.array_equal(r.mode_index, finest.mode_index)
            errs = " ".join(f"{e:+.4f}" for e in err) if r is not finest else "(reference)"
            mx = f"{np.max(np.abs(err)):.4f}" if r is not finest else "-"
            sel = " ".join(str(i + 1) for i in r.mode_index) + ("" if same else " (differs)")
            rate = "-"
            if k + 2 < len(grp) and maxerr[k + 1] > 0 and maxerr[k] > 0:
                h_ratio = (grp[k + 1].dofs / r.dofs) ** (1.0 / dim)
                rate = f"{np.log(maxerr[k] / maxerr[k + 1]) / np.log(h_ratio):.2f}"
            out.append(
                f"| {r.beam} | {r.model} | {r.level} | {r.dofs} | {r.mesh_s:.2f} | {r.basis_s:.2f} "
                f"| {r.assembly_s:.2f} | {r.solve_s:.2f} | {r.wall_s:.2f} | {r.cpu_s:.2f} | {sel} "
                f"| {mx} | {errs} | {rate} |"
            )
    return out


def _plate_vs_solid(beam: Beam, label: str, level: int | None) -> str:
    """One table row: the plate's beam-like modes and the solid modes of the same shape."""
    p = compute_modal(beam, "plate")
    c0 = time.process_time()
    s = compute_modal(beam, "solid", level)
    cpu = time.process_time() - c0
    keep = np.flatnonzero(np.array(label_modes(p)) == "bending")[:5]
    us = np.array([np.interp(p.centerline_x_m, s.centerline_x_m, u) for u in s.centerline_uz])
    us[~np.isin(label_modes(s), ("bending", "chordwise", "mixed"))] = 0.0
    mac = mac_matrix(p.centerline_uz[keep], us)
    j = mac.argmax(axis=1)
    wp, ws = p.omega_rad_s[keep], s.omega_rad_s[j]
    row = (f"| {label} | {1e3 * beam.thickness_m:g} | {s.mesh_level} | {s.dofs} | {cpu:.1f} "
           f"| {' '.join(str(i + 1) for i in keep)} | {' '.join(f'{w:.2f}' for w in wp)} "
           f"| {' '.join(f'{w:.2f}' for w in ws)} "
           f"| {' '.join(f'{100 * (b / a - 1):+.2f}' for a, b in zip(wp, ws, strict=True))} "
           f"| {mac[np.arange(keep.size), j].min():.3f} |")
    print(row, flush=True)
    return row


def _plate_vs_solid_table(seeds: list[int], thicknesses: list[float]) -> list[str]:
    out = [
        "## Plate vs solid on the beam-like bending modes",
        "",
        "Plate at its default level; solid at its default level for 10 mm, at level 2 (the same "
        "in-plane mesh) for the thinner panels. Modes: the plate's modes labelled bending "
        "(symmetric, MAC >= 0.8, not chordwise), lowest five; each paired with the solid's "
        "symmetric out-of-plane mode of the most similar centreline shape.",
        "",
        "| beam | t mm | solid level | solid DOFs | solid CPU s | plate modes | plate rad/s "
        "| solid rad/s | solid/plate - 1 % | min pairing MAC |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    beams = [("reference-random", load_beam(ROOT / "examples" / "beams"
                                            / "reference-random.json"))]
    beams += [(f"seed {k}", random_beam(np.random.default_rng(k))) for k in seeds]
    for name, b in beams:
        for t in thicknesses:
            bt = Beam(b.x_m, b.half_width_m, t, b.material, b.tip_force_N, name=b.name)
            out.append(_plate_vs_solid(bt, name, None if t == b.thickness_m else 2))
    return out + [""]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default="plate,plate-morley,beam",
                    help="comma-separated: plate, plate-morley, beam, solid")
    ap.add_argument("--beams", default=None, help="comma-separated beam names (default: all)")
    ap.add_argument("--modes", type=int, default=5)
    ap.add_argument("--computed", type=int, default=25, help="modes computed before selection")
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_truth.md"))
    ap.add_argument("--plate-vs-solid", action="store_true",
                    help="add the plate vs solid table of the beam-like modes")
    ap.add_argument("--seeds", default="", help="comma-separated random_beam seeds for it")
    ap.add_argument("--thicknesses", default="0.01", help="comma-separated thicknesses, m")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore", DeprecationWarning)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    if "solid" in models:
        try:
            from prbdm_pin.truth.solid import solid_modal  # noqa: F401
        except ImportError:
            print("solid model not available: skipped")
            models.remove("solid")
    paths = sorted((ROOT / "examples" / "beams").glob("*.json"))
    if args.beams:
        wanted = set(args.beams.split(","))
        paths = [p for p in paths if p.stem in wanted]
    rows = []
    for path in paths:
        beam = load_beam(path)
        for model in models:
            for level in LEVELS[model]:
                r = _run(beam, model, level, args.modes, args.computed)
                rows.append(r)
                print(f"{r.beam:18s} {model:13s} level {level:3d} dofs {r.dofs:7d} "
                      f"wall {r.wall_s:6.2f} s cpu {r.cpu_s:6.2f} s", flush=True)
    lines = [
        "# Finite-element truth benchmark",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, numpy {np.__version__}; BLAS pinned to 1 thread. "
        f"Default plate level: {DEFAULT_PLATE_LEVEL}.",
        "",
        f"Selected modes: the {args.modes} of largest z mass participation among the "
        f"{args.computed} lowest (``paper`` policy), numbered 1-based in the model's own "
        "spectrum; error of each selected frequency against the finest level of the same model. "
        "Columns mesh/basis/assembly/eigensolve are wall times of the stages; 'wall s' is the "
        "whole call (including mode classification) and 'CPU s' its process CPU time: on a shared "
        "machine wall time can be inflated several times, the CPU time is what the solve costs. "
        "The beam model's level is its number of Hermite elements.",
        "",
        *_table(rows),
        "",
    ]
    if args.plate_vs_solid:
        seeds = [int(k) for k in args.seeds.split(",") if k.strip()]
        lines += _plate_vs_solid_table(seeds, [float(t) for t in args.thicknesses.split(",")])
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, "\n".join(lines))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
