"""``prbdm sensitivity``: the truth's frequencies and linear tip with their design gradients."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from ..io.provenance import provenance
from . import add_common

EXAMPLE = """example:
  prbdm sensitivity examples/beams/tapered.json --design thickness,half_width[1],E --out out/sens
  writes out/sens/sensitivity.json (values, gradients, relative sensitivities p / omega
  d omega / dp) and out/sens/sensitivity.png (bar plot of the relative sensitivities)"""

SENSITIVITY_FILES = ("sensitivity.json", "sensitivity.png")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``sensitivity`` subparser."""
    p = subparsers.add_parser(
        "sensitivity", help="design gradients of the truth's frequencies and tip deflection",
        description="Derivatives of the truth's bending frequencies and linear tip deflection "
                    "with respect to design variables (thickness, E, rho, nu, half_width[i], "
                    "x[i]): closed form for the thickness and material, shape derivatives on a "
                    "mesh moving with the planform for the planform.",
        epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("beam", help="beam JSON file")
    p.add_argument("--design", required=True, metavar="SPEC",
                   help="comma-separated design variables, e.g. thickness,half_width[1],x[2],E")
    p.add_argument("--model", default="plate", choices=["plate", "beam"],
                   help="Kirchhoff plate (default) or 1D Euler-Bernoulli beam")
    p.add_argument("--modes", type=int, default=3, help="number of bending modes (default 3)")
    p.add_argument("--mesh", type=int, default=None, help="plate mesh level (default: truth's)")
    p.add_argument("--selection", default="paper", choices=["paper", "shape"])
    p.add_argument("--out", required=True, help="output directory")
    add_common(p)
    p.set_defaults(func=run)
    return p


def parse_design(spec: str) -> tuple[str, ...]:
    """Return the variable names of ``--design``, comma-separated.

    An empty name (``thickness,,E``, a trailing comma) is refused, naming its position: it is
    a typo, not a variable to skip.
    """
    from ..errors import BeamInputError

    names = tuple(s.strip() for s in spec.split(","))
    if not any(names):
        raise BeamInputError(f"--design {spec!r}: name at least one design variable")
    for i, name in enumerate(names):
        if not name:
            raise BeamInputError(f"--design {spec!r}: variable {i + 1} of {len(names)} is "
                                 "empty (two commas, or one at an end); remove it or name it")
    return names


def run(args) -> int:
    """Run ``prbdm sensitivity`` (exit code 0 on success)."""
    from ..errors import BeamInputError
    from ..files.beam_file import load_beam
    from ..io.atomic import atomic_write_text
    from ..io.output_folder import output_folder
    from ..io.paths import writable_dir
    from ..member.design import Design
    from ..options.limits import check_cap
    from ..truth.compute_derivatives import truth_gradient
    from .checks import in_range

    in_range("--modes", args.modes, 1, integer=True)
    check_cap("--modes", args.modes, "max_joints")
    in_range("--mesh", args.mesh, 0, 6, integer=True)
    writable_dir(args.out, "--out")
    names = parse_design(args.design)
    t0 = time.perf_counter()
    beam = load_beam(args.beam)
    try:
        design = Design(beam, names)
    except BeamInputError as exc:  # name the option the variables came from
        raise BeamInputError(f"--design {args.design!r}: {exc}") from exc
    if not args.quiet:
        print(f"sensitivity: {beam.name} with the {args.model} model ...", flush=True)
    g = truth_gradient(beam, design, model=args.model, modes=args.modes, mesh_level=args.mesh,
                       selection=args.selection)
    wall = time.perf_counter() - t0
    rel = g.relative_d_omega
    rel_tip = g.relative_d_tip_z
    doc = {
        **provenance(),
        "beam": beam.name, "beam_fingerprint": beam.fingerprint(), "model": g.model,
        "mesh_level": g.mesh_level, "selection": args.selection, "dofs": g.dofs,
        "variables": [{"name": n, "unit": u, "value": float(v)}
                      for n, u, v in zip(g.names, g.units, g.values, strict=True)],
        "mode_index": [int(i) for i in g.mode_index],
        "omega_rad_s": [float(w) for w in g.omega_rad_s],
        "d_omega_rad_s": {n: [float(x) for x in g.d_omega_rad_s[:, j]]
                          for j, n in enumerate(g.names)},
        "d_omega_units": [f"rad/s per {u}" for u in g.units],
        "relative_d_omega": {n: [float(x) for x in rel[:, j]] for j, n in enumerate(g.names)},
        "tip_z_m": g.tip_z_m,
        "d_tip_z_m": {n: float(x) for n, x in zip(g.names, g.d_tip_z_m, strict=True)},
        "d_tip_z_units": [f"m per {u}" for u in g.units],
        "relative_d_tip_z": None if rel_tip is None else {
            n: float(x) for n, x in zip(g.names, rel_tip, strict=True)},
        "solve_s": g.solve_s, "gradient_s": g.gradient_s, "wall_time_s": wall,
        "note": "relative sensitivities are p / omega d omega / dp (dimensionless); derivatives "
                "are of the truth on its own mesh moving with the planform (fixed topology)",
    }
    out = Path(args.out)
    with output_folder(out, SENSITIVITY_FILES, marker="sensitivity.json") as stage:
        plot_sensitivity(g, stage / "sensitivity.png", beam.name)
        atomic_write_text(stage / "sensitivity.json", json.dumps(doc, indent=2) + "\n")
    if not args.quiet:
        print(_summary(g))
        print(f"wrote {out / 'sensitivity.json'} ({wall:.1f} s)")
    return 0


def _summary(g) -> str:
    """One line per mode (and the tip): value and relative sensitivity per variable."""
    head = f"{'':>10} {'value':>12} " + " ".join(f"{n:>14}" for n in g.names)
    lines = [head + "   (p / value d value / dp)"]
    for k, w in enumerate(g.omega_rad_s):
        lines.append(f"{f'mode {k + 1}':>10} {w:>12.6g} "
                     + " ".join(f"{x:>14.5g}" for x in g.relative_d_omega[k]))
    if g.relative_d_tip_z is not None:
        lines.append(f"{'tip_z':>10} {g.tip_z_m:>12.6g} "
                     + " ".join(f"{x:>14.5g}" for x in g.relative_d_tip_z))
    return "\n".join(lines)


def plot_sensitivity(g, path: Path | None = None, title: str = "", *, ax=None):
    """Draw the relative frequency sensitivities p/omega d omega/dp as bars; return the Figure.

    One group of bars per design variable, one bar per mode. ``g`` is a
    :class:`~prbdm_pin.TruthGradient`; drawn into ``ax`` or a new figure, written to ``path``
    when given (PNG, PDF or SVG by the suffix).
    """
    import numpy as np

    from ..views.plots import figure_format, own_axes, save_png

    if path is not None:
        figure_format(path)
    rel = g.relative_d_omega
    n_modes, n_vars = rel.shape
    fig, ax, own = own_axes(ax, (max(5.0, 1.2 * n_vars + 2.0), 3.6))
    width = 0.8 / n_modes
    x = np.arange(n_vars)
    for k in range(n_modes):
        ax.bar(x + (k - (n_modes - 1) / 2) * width, rel[k], width,
               label=f"mode {k + 1} ({g.omega_rad_s[k]:.4g} rad/s)")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xticks(x, g.names, rotation=20)
    ax.set_xlabel("design variable p (each in its unit: the ratio is unitless)")
    ax.set_ylabel("p / omega  d omega / dp (-)")
    ax.set_title(f"{title}: relative frequency sensitivities ({g.model} truth)")
    ax.legend(fontsize=8)
    if own:
        fig.tight_layout()
    if path is not None:  # a caller's figure is written whole, cropped
        save_png(fig, path, bbox_inches=None if own else "tight")
    return fig
