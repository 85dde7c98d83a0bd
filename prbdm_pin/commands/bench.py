"""``prbdm bench``: error against cost of fitted PRBDMs, finite-segment chains and the FE truth."""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

from . import add_common

EXAMPLE = """example:
  prbdm bench --quick --out results/bench
  writes results/bench/results.md (tables), results.json (raw numbers) and
  results/bench/error_vs_cost.png (log-log plot with the non-dominated frontier); the plate
  truths are cached in results/bench/truth-cache"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``bench`` subparser."""
    p = subparsers.add_parser(
        "bench", help="benchmark: model error against simulation cost",
        description="Fitted nR models (n = 1..8) beside finite-segment chains (N = 2..64) and the "
                    "FE truth mesh levels on the shipped and five seeded random beams.",
        epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true",
                   help="reduced set (2 beams, n in {2, 4}, N in {4, 16, 32}, one truth level)")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--cache-dir", default=None,
                   help="truth cache directory (default OUT/truth-cache)")
    p.add_argument("--no-mujoco", action="store_true", help="skip the MuJoCo peer")
    add_common(p)
    p.set_defaults(func=run)
    return p


BENCH_FILES = ("results.md", "results.json", "error_vs_cost.png")


def check_options(args) -> None:
    """``--out`` and the truth cache folder must be writable: refused before the first fit."""
    from ..io.paths import writable_dir

    writable_dir(args.out, "--out")
    if args.cache_dir is not None:
        writable_dir(args.cache_dir, "--cache-dir")
    else:
        writable_dir(Path(args.out) / "truth-cache", "--out")


def run(args) -> int:
    """Run ``prbdm bench`` (exit code 0 on success)."""
    from dataclasses import replace

    import numpy as np

    from ..bench.config import FULL, QUICK
    from ..bench.plot import plot_error_vs_cost
    from ..bench.report import markdown_report, result_dict
    from ..bench.run import run_benchmark, work_units
    from ..io.atomic import atomic_write_json, atomic_write_text
    from ..io.output_folder import output_folder
    from ..io.provenance import provenance

    check_options(args)
    config = QUICK if args.quick else FULL
    if args.no_mujoco:
        config = replace(config, mujoco=False)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cache = Path(args.cache_dir) if args.cache_dir else out / "truth-cache"
    bar = None
    if not args.quiet:
        from ..io.progress import progress_bar

        bar = progress_bar(work_units(config), desc="bench", unit="step")

    def tick(label: str) -> None:
        if bar is not None:
            bar.set_postfix_str(label, refresh=False)
            bar.update(1)

    try:
        result = run_benchmark(config, cache_dir=cache, progress=tick)
    finally:
        if bar is not None:
            bar.close()
    machine = (f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python "
               f"{platform.python_version()}, numpy {np.__version__}; BLAS threads "
               f"{os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}. ")
    # the truth cache OUT/truth-cache is not the command's own: the new set keeps it
    with output_folder(out, BENCH_FILES, marker="results.json") as stage:
        atomic_write_text(stage / "results.md", markdown_report(result, machine))
        plot_error_vs_cost(result, stage / "error_vs_cost.png")
        # each model's fit seed is in its row; the run as a whole draws nothing of its own
        atomic_write_json(stage / "results.json", {**provenance(), **result_dict(result)},
                          indent=1)
    md, png = out / "results.md", out / "error_vs_cost.png"
    if not args.quiet:
        print(f"wrote {md} and {png} ({result.wall_time_s:.1f} s)")
    return 0
