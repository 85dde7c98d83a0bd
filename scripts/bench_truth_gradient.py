"""Benchmark of the truth's design gradients: the cost of all gradients against the truth's solve.

For each shipped panel (reference-random, tapered, stepped-narrow) and each truth model (Argyris
plate at its default level, 1D beam) this takes every design variable a beam offers (thickness,
E, rho, nu, every half-width, every interior station) and times ``truth_gradient``: its solve
(the truth's own modal solve with the bending-mode selection and the linear tip-load solve) and
all gradients after it, in wall and in CPU time. The ratio gradient / solve is the cost of the
gradients in truth solves (target: at most 2). The large-deflection tip's gradients
(``elastica_gradient``: the adjoint of the elastica's tangent equation) are timed the same way
(wall time) against the elastica's own solve, with EI's scale held fixed and with the
plate-calibrated scale (adding the plate's and the 1D beam's truth_gradient to both columns).
Wall times on a shared machine can be inflated by other processes: each case is run
``--repeats`` times and the fastest run is kept (by CPU time where the gradient reports it); the
CPU times are the steadier measure. Writes a Markdown table (default
results/bench_truth_gradient.md).

usage: python scripts/bench_truth_gradient.py [--repeats 3] [--modes 3] [--out PATH]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # pin BLAS to one thread before numpy is imported

import argparse  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.member.geometry import Beam  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the scripts' shared helpers
from docs_tables import write_table  # noqa: E402

from prbdm_pin.truth.compute_derivatives import truth_gradient  # noqa: E402
from prbdm_pin.truth.elastica_derivatives import elastica_gradient  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PANELS = ("reference-random", "tapered", "stepped-narrow")


def all_variables(beam: Beam) -> tuple[str, ...]:
    """Every design variable of ``beam``: thickness, material, half-widths, interior stations
    (one name per width step)."""
    x = beam.x_m
    stations = [f"x[{i}]" for i in range(1, x.size - 1) if x[i] != x[i - 1]]
    widths = [f"half_width[{i}]" for i in range(x.size)]
    return ("thickness", "E", "rho", "nu", *widths, *stations)


def run(repeats: int, modes: int) -> list[tuple]:
    rows = []
    for name in PANELS:
        beam = load_beam(ROOT / "examples" / "beams" / f"{name}.json")
        names = all_variables(beam)
        for model in ("plate", "beam"):
            best = None
            for _ in range(repeats):
                g = truth_gradient(beam, names, model=model, modes=modes)
                if best is None or (g.solve_cpu_s + g.gradient_cpu_s
                                    < best.solve_cpu_s + best.gradient_cpu_s):
                    best = g
            shape = sum(1 for n in names if "[" in n)
            rows.append((name, model, best.dofs, len(names), shape, best.solve_s,
                         best.gradient_s, best.solve_cpu_s, best.gradient_cpu_s))
            print(f"{name:18s} {model:6s} dofs {best.dofs:6d} variables {len(names):3d} "
                  f"solve {best.solve_s:7.3f} s gradients {best.gradient_s:7.3f} s ratio "
                  f"{best.gradient_s / best.solve_s:5.2f}; CPU {best.solve_cpu_s:7.3f} s "
                  f"{best.gradient_cpu_s:7.3f} s ratio "
                  f"{best.gradient_cpu_s / best.solve_cpu_s:5.2f}", flush=True)
        for scale, label in ((1.0, "elastica"), ("plate", "calibrated elastica")):
            best = None
            for _ in range(repeats):
                g = elastica_gradient(beam, names, ei_scale=scale)
                if best is None or g.solve_s + g.gradient_s < best.solve_s + best.gradient_s:
                    best = g
            shape = sum(1 for n in names if "[" in n)
            rows.append((name, label, best.nodes, len(names), shape, best.solve_s,
                         best.gradient_s, None, None))
            print(f"{name:18s} {label:19s} nodes {best.nodes:6d} solve {best.solve_s:7.3f} s "
                  f"gradients {best.gradient_s:7.3f} s ratio "
                  f"{best.gradient_s / best.solve_s:5.2f}", flush=True)
    return rows


def table(rows: list[tuple], repeats: int, modes: int) -> str:
    lines = [
        "# Cost of the truth's design gradients",
        "",
        f"`python scripts/bench_truth_gradient.py` ({platform.processor() or platform.machine()}, "
        f"one BLAS thread, fastest of {repeats} runs, {modes} bending modes). Every design "
        "variable of the panel: thickness, E, rho, nu, every half-width and every interior "
        "station. *solve*: the truth's modal solve (25 modes, bending-mode selection) and linear "
        "tip solve with its adjoint; *gradients*: the derivatives of the selected frequencies "
        "and the tip with respect to all variables after it (closed form for thickness and "
        "material; for the planform, shape derivatives of the moved elements' integrals: "
        "complex step on the plate, fourth-order differences on the 1D beam). Wall times and, "
        "for the plate and 1D beam, CPU times of the process (steadier on a shared machine). "
        "*elastica*: the large-deflection tip under the beam's tip force (DOFs: collocation "
        "nodes of the adjoint); solve is the elastica's load continuation, gradients the adjoint "
        "solve and the quadratures for all variables and the load; *calibrated elastica*: EI "
        "scaled by u_1D / u_plate, with the plate's and the 1D beam's truth_gradient (the scale "
        "and its gradient; their modal solves included) added to solve and gradients.",
        "",
        "| panel | model | DOFs | variables | of which planform | solve s | gradients s | "
        "gradients / solve | solve CPU s | gradients CPU s | CPU gradients / solve |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, model, dofs, n, shape, solve, grad, solve_cpu, grad_cpu in rows:
        cpu = ("| - | - | - |" if solve_cpu is None else
               f"| {solve_cpu:.3f} | {grad_cpu:.3f} | {grad_cpu / solve_cpu:.2f} |")
        lines.append(f"| {name} | {model} | {dofs} | {n} | {shape} | {solve:.3f} | {grad:.3f} "
                     f"| {grad / solve:.2f} {cpu}")
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--modes", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_truth_gradient.md"))
    args = ap.parse_args()
    rows = run(args.repeats, args.modes)
    out = Path(args.out)
    write_table(out, table(rows, args.repeats, args.modes), ap.get_default("out"),
                "bench_truth_gradient")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
