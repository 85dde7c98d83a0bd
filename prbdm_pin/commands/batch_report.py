"""``prbdm batch-report``: distributions and correlations of a batch study, with plots.

The report itself is computed by :mod:`prbdm_pin.batch.report`; this module parses the
arguments, checks the folders and writes report.md and the figures.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import add_common


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``batch-report`` subparser."""
    p = subparsers.add_parser(
        "batch-report",
        help="summarise a batch study (distributions, correlations, plots)",
        description="Read OUT/results.jsonl of one batch (or of several shards) and write "
        "report.md and plots.",
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="batch output folder(s)")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="where report.md and the plots go (default: the first DIR/report)")
    p.add_argument("--no-plots", action="store_true", help="only the Markdown summary")
    add_common(p)
    p.set_defaults(func=run)
    return p


def check_options(args: argparse.Namespace) -> None:
    """Every DIR an existing folder and the report folder writable, before anything is read."""
    from ..io.paths import existing_dir, writable_dir

    for d in args.dirs:
        existing_dir(d, "DIR")
    writable_dir(Path(args.dirs[0]) / "report" if args.out is None else args.out, "--out")


def run(args: argparse.Namespace) -> int:
    """Write report.md (and plots) for the given batch folders."""
    from ..batch import load_study, missing_warning, summarise, to_markdown
    from ..batch.files import write_output
    from ..batch.plots import write_plots
    from ..batch.report import loss_lines

    check_options(args)
    records, manifest = load_study(args.dirs)
    rep = summarise(records, manifest)
    warning = missing_warning(rep)
    if warning is not None:
        print(f"prbdm batch-report: {warning}", file=sys.stderr)  # even with --quiet
    out = Path(args.out) if args.out else Path(args.dirs[0]) / "report"
    out.mkdir(parents=True, exist_ok=True)
    plots = [] if args.no_plots else write_plots(records, rep, out)
    path = write_output(out / "report.md", to_markdown(rep, plots))
    if not args.quiet:
        print(f"{rep.n_ok} fitted, {rep.n_failed} failed -> {path}", file=sys.stderr)
        for line in loss_lines(rep):
            print(line, file=sys.stderr)
    return 0
