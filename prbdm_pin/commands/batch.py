"""``prbdm batch``: truth + fit for many beams, resumable, on a local pool or a Dask cluster."""

from __future__ import annotations

import argparse
import os
import sys

from ..options.validate import MAX_SHARD_BEAMS  # shared with BatchSpec
from . import add_common
from .options import add_axes_option, stiffness_of

EXAMPLES = """\
examples:
  prbdm batch --beams 1000 --seed 7 --joints 4 --out runs/study --workers 2
  prbdm batch --beams 50000 --seed 7 --joints 4 --out runs/study-3 --shard 3/100
  prbdm batch --beams 50000 --seed 7 --joints 4 --out runs/study --scheduler tcp://head:8786
  prbdm batch --beams-dir my_beams/ --seed 0 --joints 3 --stiffness joint --out runs/mine

Rerunning the same command resumes: beams already in OUT/results.jsonl are skipped.
Beam i is random_beam(default_rng(SeedSequence(SEED, spawn_key=(i,)))).
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Create the ``batch`` subparser."""
    from ..options.choices import (
        DEFAULT_EIGEN_NORM,
        EIGEN_NORMS,
        OBJECTIVES,
        STIFFNESS_KINDS,
        TRUTH_MODELS,
    )

    p = subparsers.add_parser(
        "batch",
        help="fit many random beams (or a folder of beams), resumable",
        description="Compute the truth and fit a PRBDM for many beams. One JSON line per beam "
        "goes to OUT/results.jsonl as it finishes; OUT/results.csv consolidates them.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--beams", type=int, metavar="N", help="number of random beams")
    src.add_argument("--beams-dir", metavar="DIR", help="folder of beam JSON files instead")
    p.add_argument("--seed", type=int, default=0, help="root seed (default 0)")
    p.add_argument("--joints", type=int, required=True, help="number of PRBDM joints n")
    p.add_argument("--frequencies", type=int, default=None,
                   help="truth frequencies to match (default: joints)")
    p.add_argument("--objective", choices=OBJECTIVES, default="eigen")
    p.add_argument("--stiffness", choices=STIFFNESS_KINDS, default=None,
                   help="paper (default) or joint (the default with a spatial --axes)")
    add_axes_option(p)
    p.add_argument("--starts", type=int, default=64, help="multistart points per fit (64)")
    p.add_argument("--truth-model", choices=TRUTH_MODELS, default="plate")
    p.add_argument("--min-link", type=float, default=0.02, metavar="FRACTION",
                   help="shortest link as a fraction of the beam length (Eq. 15; default 0.02); "
                        "needs 0 < FRACTION < 1/(joints+1)")
    p.add_argument("--eigen-norm", choices=EIGEN_NORMS, default=DEFAULT_EIGEN_NORM,
                   help="eigen error per pose: Eq. 16's l2 norm (paper) or the rms of the "
                        f"per-mode relative errors (relative); default {DEFAULT_EIGEN_NORM}")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument("--cache-dir", metavar="DIR", default=None,
                   help="truth cache (default OUT/truth-cache)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None,
                       help="local worker processes (default: all cores)")
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                       help="run on this Dask cluster (pip install prbdm_pin[dask])")
    p.add_argument("--shard", default="0/1", metavar="i/N",
                   help="take only the beams with index %% N == i (job arrays)")
    p.add_argument("--retry-failed", action="store_true",
                   help="also recompute beams recorded as failed")
    add_common(p)
    p.set_defaults(func=run)
    return p


def check_options(args: argparse.Namespace) -> None:
    """Refuse bad ``prbdm batch`` options before ``--out`` is created or a beam is read."""
    from ..batch import parse_shard
    from ..chain.layout import check_min_fraction
    from ..errors import BeamInputError
    from ..io.paths import existing_dir, writable_dir
    from ..options.limits import check_cap
    from .checks import MAX_SEED, MAX_WORKERS, in_range
    from .fit_checks import MAX_STARTS

    in_range("--joints", args.joints, 1, integer=True)
    check_cap("--joints", args.joints, "max_joints")
    if args.axes != "y" and args.objective != "eigen":
        raise BeamInputError(f"--objective {args.objective} with --axes {args.axes}: a batch fits "
                             "spatial chains to the truth's frequencies by kind (--objective "
                             "eigen); the 3D tip of a corner load is a prbdm fit option")
    in_range("--frequencies", args.frequencies, 1, args.joints, integer=True,
             why=f"a {args.joints}R model has {args.joints} frequencies")
    in_range("--starts", args.starts, 1, MAX_STARTS, integer=True)
    in_range("--seed", args.seed, 0, MAX_SEED, integer=True)
    in_range("--workers", args.workers, 1, MAX_WORKERS, integer=True)
    check_min_fraction(args.min_link, args.joints, "--min-link")
    try:
        i, n = parse_shard(args.shard)
    except BeamInputError:
        raise BeamInputError(f"--shard = {args.shard!r}: must be i/N with N >= 1 and "
                             "0 <= i < N, e.g. 0/4") from None
    if args.beams is not None:
        in_range("--beams", args.beams, 1, integer=True)
        if (args.beams - i + n - 1) // n > MAX_SHARD_BEAMS:
            raise BeamInputError(f"--beams = {args.beams}: {(args.beams - i + n - 1) // n} "
                                 f"beams in one shard (at most {MAX_SHARD_BEAMS}): split the "
                                 "study with --shard i/N")
    if args.beams_dir is not None:
        existing_dir(args.beams_dir, "--beams-dir")
    if args.scheduler is not None and not args.scheduler.strip():
        raise BeamInputError(f"--scheduler = {args.scheduler!r}: must be an address "
                             "(tcp://HOST:PORT)")
    writable_dir(args.out, "--out")
    if args.cache_dir is not None:
        writable_dir(args.cache_dir, "--cache-dir")
    else:
        writable_dir(os.path.join(args.out, "truth-cache"), "--out")


def batch_fit_options(args: argparse.Namespace):
    """Return the FitOptions of a ``prbdm batch`` command line.

    Each beam's fit seed replaces ``seed``.
    """
    from ..options.objects import FitOptions

    return FitOptions(frequencies=args.frequencies, objective=args.objective,
                      stiffness=stiffness_of(args), starts=args.starts,
                      eigen_norm=args.eigen_norm, min_fraction=args.min_link, axes=args.axes)


def run(args: argparse.Namespace) -> int:
    """Run the batch; exit code 0 once every beam has a record (failed beams are data)."""
    from ..batch import BatchSpec, DaskCluster, FitSettings, LocalPool, parse_shard, run_batch
    from ..errors import BeamInputError

    check_options(args)
    cache = args.cache_dir or os.path.join(args.out, "truth-cache")
    settings = FitSettings(
        joints=args.joints, options=batch_fit_options(args), truth_model=args.truth_model,
        cache_dir=os.path.abspath(cache) if args.scheduler is None else cache,
    )
    spec = BatchSpec(
        seed=args.seed, settings=settings, n_beams=args.beams,
        beams_dir=args.beams_dir, shard=parse_shard(args.shard),
    )
    if args.scheduler is not None:
        backend = DaskCluster(args.scheduler)
    else:
        workers = args.workers if args.workers is not None else (os.cpu_count() or 1)
        if workers < 1:
            raise BeamInputError(f"workers = {workers}: must be >= 1")
        backend = LocalPool(workers)
    s = run_batch(spec, args.out, backend=backend, progress=not args.quiet,
                  retry_failed=args.retry_failed)
    if not args.quiet:
        print(f"{s.n_tasks} beams in this shard: {s.n_skipped} already done, {s.n_ok} fitted, "
              f"{s.n_failed} failed, {s.n_retried} retried after a worker died; "
              f"{s.wall_s:.1f} s -> {s.out_dir}", file=sys.stderr)
    return 0
