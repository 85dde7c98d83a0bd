"""``prbdm pareto``: NSGA-II front over (eigen loss, deflection loss).

Writes pareto.csv, the knee's fit.json and model.urdf, and plots.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..options.validate import MAX_GENERATIONS, MAX_POP, MIN_POP  # shared with the API
from . import add_common
from .fit import (
    FIT_FILES,
    add_truth_options,
    export_text,
    load_target,
    print_warnings,
    worst_mode_text,
    write_fit_files,
)
from .fit_checks import MAX_STARTS, check_inputs, check_sweep, check_truth_options
from .options import add_pareto_options, pareto_options, parse_bounds

EXAMPLE = """example:
  prbdm pareto examples/beams/reference-random.json --joints 4 --pop 100 --generations 200 \\
      --seed 0 --out out/pareto4r
writes DIR/pareto.csv (the whole front), DIR/pareto.json, DIR/pareto.png and the knee's
DIR/fit.json, DIR/model.urdf, DIR/planform.png

The beam file must give "tip_force" (the deflection objective's load)."""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``pareto`` subparser."""
    p = subparsers.add_parser(
        "pareto", help="NSGA-II Pareto fit (eigen vs deflection) and its knee",
        description="NSGA-II over (eigen loss, tip deflection loss); knee by Eq. 27.",
        epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_truth_options(p)
    add_pareto_options(p)
    p.add_argument("--workers", type=int, default=1, help="processes for the evaluations")
    add_common(p)
    p.set_defaults(func=run)
    return p


PARETO_FILES = ("pareto.csv", "pareto.json", "pareto.png")


def write_pareto_outputs(res, beam, out: Path) -> None:
    """Write the front's files into ``out`` as one set (``output_folder``).

    pareto.csv (the whole front), pareto.json, pareto.png and the knee's fit.json, model.urdf
    and plots.
    """
    from ..io.atomic import atomic_write_text
    from ..io.output_folder import output_folder
    from ..views.plots import plot_pareto

    with output_folder(out, FIT_FILES + PARETO_FILES, marker="fit.json") as stage:
        atomic_write_text(stage / "pareto.csv", res.to_csv())
        res.save(stage / "pareto.json")
        plot_pareto(res, stage / "pareto.png")
        write_fit_files(res.knee, beam, stage)




def check_options(args) -> None:
    """Refuse bad ``prbdm pareto`` options before any file is read or truth computed."""
    from .checks import MAX_WORKERS, in_range

    check_truth_options(args)
    in_range("--pop", args.pop, MIN_POP, MAX_POP, integer=True)
    in_range("--generations", args.generations, 1, MAX_GENERATIONS, integer=True)
    in_range("--workers", args.workers, 1, MAX_WORKERS, integer=True)
    in_range("--seed-starts", args.seed_starts, 1, MAX_STARTS, integer=True)
    parse_bounds(args.log10_bounds)
    check_sweep(args)


def run(args) -> int:
    """Run ``prbdm pareto`` (exit code 0 on success)."""
    from ..files.beam_file import load_beam
    from ..fitting import fit_pareto

    check_options(args)
    beam = load_beam(args.beam)
    min_fraction = check_inputs(args, beam, "Pareto")
    options = pareto_options(args, min_fraction)  # refused before the truth is computed
    target = load_target(args, beam)
    res = fit_pareto(beam, target, args.joints, options, workers=args.workers,
                     progress=not args.quiet)
    out = Path(args.out)
    write_pareto_outputs(res, beam, out)
    if not args.quiet:
        print_warnings(res.knee)
        k = res.knee
        print(f"{res.joints}R front of {res.F_pct.shape[0]} designs; knee: eigen "
              f"({k.eigen_norm} norm) {k.eigen_loss_pct:.4g} %, {worst_mode_text(k)}, "
              f"deflection {k.deflection_loss_pct:.4g} %, "
              f"combined {k.combined_loss_pct:.4g} % ({res.wall_time_s:.1f} s)")
        print(export_text(k))
        print(f"wrote {out / 'pareto.csv'} and {out / 'fit.json'}")
    return 0
