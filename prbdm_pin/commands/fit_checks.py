"""The checks of ``prbdm fit``'s options.

Shared with ``prbdm pareto``, ``simulate`` and ``batch``: every range, cap and folder is
refused before any file is read or truth computed.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from ..options.validate import MAX_STARTS, MAX_SWEEP_RAD  # noqa: F401 - shared with FitOptions


def cache_dir(args) -> str:
    """Return the truth cache folder.

    It is ``--cache-dir``, else ``$PRBDM_CACHE``, else ``~/.cache/prbdm_pin``.
    """
    if args.cache_dir:
        return args.cache_dir
    return os.environ.get("PRBDM_CACHE") or str(Path.home() / ".cache" / "prbdm_pin")


def load_factors(text: str | None) -> list[float]:
    """Return ``--extra-loads`` as multiples of the tip force ([] when not given).

    Raises BeamInputError for a non-finite or zero factor.
    """
    from ..errors import BeamInputError

    if not text:
        return []
    try:
        factors = [float(v) for v in text.split(",")]
    except ValueError:
        raise BeamInputError(f"--extra-loads = {text!r}: must be numbers separated by commas "
                             "(multiples of the beam's tip force)") from None
    bad = [f for f in factors if not (math.isfinite(f) and f != 0.0)]
    if bad:
        raise BeamInputError(f"--extra-loads = {text!r}: {bad[0]} is not a finite, non-zero "
                             "multiple of the tip force")
    return factors


def check_truth_options(args) -> None:
    """Check the options of :func:`add_truth_options` (shared with ``prbdm pareto``).

    Ranges, the joint cap, the extra loads, a writable ``--out`` and cache folder; nothing is
    read or computed yet.
    """
    from ..chain.layout import check_min_fraction
    from ..errors import BeamInputError
    from ..io.paths import writable_dir
    from ..options.limits import check_cap
    from .checks import MAX_SEED, in_range

    in_range("--joints", args.joints, 1, integer=True)
    check_cap("--joints", args.joints, "max_joints")
    in_range("--frequencies", args.frequencies, 1, args.joints, integer=True,
             why=f"a {args.joints}R model has {args.joints} frequencies")
    in_range("--mesh-level", args.mesh_level, 0, 6, integer=True)
    in_range("--xi", args.xi, 0.0, MAX_SWEEP_RAD, unit="rad")
    in_range("--seed", args.seed, 0, MAX_SEED, integer=True)
    check_min_fraction(args.min_link, args.joints, "--min-link")
    if load_factors(args.extra_loads) and args.truth:
        raise BeamInputError(f"--extra-loads = {args.extra_loads!r}: needs a computed truth, "
                             "not --truth TRUTH.json")
    writable_dir(args.out, "--out")
    if not args.truth:
        check_cache_dir(args)


def check_cache_dir(args) -> None:
    """Refuse a truth cache folder that is not writable.

    The folder is ``--cache-dir``, else ``$PRBDM_CACHE``, else ``~/.cache/prbdm_pin`` (each
    named as what it is).
    """
    from ..io.paths import writable_dir

    if args.cache_dir is not None:
        field = "--cache-dir"
    elif os.environ.get("PRBDM_CACHE"):
        field = "PRBDM_CACHE"
    else:
        field = "cache folder (default; set --cache-dir or PRBDM_CACHE)"
    writable_dir(cache_dir(args) if args.cache_dir is None else args.cache_dir, field)


def check_sweep(args) -> None:
    """``--eps``: > 0, and (for the paper's pose sweep) a sweep of at most ``MAX_POSES``."""
    from .checks import in_range
    from .options import stiffness_of

    in_range("--eps", args.eps, 0.0, MAX_SWEEP_RAD, lo_open=True, unit="rad")
    if stiffness_of(args) == "paper":
        from ..chain.stiffness import MAX_POSES

        in_range("--xi", args.xi, 0.0, math.pi / 2 / args.joints, unit="rad",
                 why="the sweep's first pose turns the tip by joints * xi <= pi/2")
        ratio = (math.pi / 2 / args.joints - args.xi) / args.eps  # inf for a subnormal eps
        poses = math.floor(ratio) + 1 if math.isfinite(ratio) else math.inf
        if poses > MAX_POSES:
            from ..errors import BeamInputError

            raise BeamInputError(
                f"--eps = {args.eps!r}: the pose sweep from --xi {args.xi:g} to a tip angle of "
                f"pi/2 would have {poses} poses (at most {MAX_POSES}): give a larger step")


def check_inputs(args, beam, objective: str) -> float:
    """Refuse, before any truth is computed, what cannot be fitted.

    That is a ``--min-link`` that leaves no room for n + 1 links, and a deflection term without
    a tip load. Returns the min_fraction.
    """
    from ..chain.layout import check_min_fraction
    from ..errors import BeamInputError

    f = check_min_fraction(args.min_link, args.joints, "--min-link")
    if objective != "eigen" and not any(beam.tip_force_N):
        raise BeamInputError(
            f"tip_force = [0, 0, 0] N: a {objective} fit matches the tip under the beam's tip "
            "load and there is none; give tip_force in the beam file (or fit --objective eigen)")
    return f
