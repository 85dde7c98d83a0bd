"""The fit options on the command line.

The flags of ``prbdm fit`` and ``prbdm pareto``, and the one function each that turns parsed
arguments into the frozen options object the library takes (and the result records).
"""

from __future__ import annotations

import argparse

from ..options.choices import (
    AXES,
    DEFAULT_EIGEN_NORM,
    DEFLECTION_NORMS,
    EIGEN_NORMS,
    EPS_RAD,
    MIN_FRACTION,
    OBJECTIVES,
    PARETO_EPS_RAD,
    STIFFNESS_KINDS,
    XI_RAD,
)
from ..options.objects import FitOptions, ParetoOptions

__all__ = ["add_problem_options", "add_fit_options", "add_pareto_options", "add_axes_option",
           "fit_options", "pareto_options", "stiffness_of"]


def add_axes_option(p: argparse.ArgumentParser) -> None:
    """Add ``--axes {y,xy,yz,xyz}``: the joint axes at each node (fit, pareto, batch)."""
    p.add_argument("--axes", default="y", choices=list(AXES),
                   help="joint axes at each node: y bending (the planar chain, default), xy "
                        "adds torsion, yz in-plane bending, xyz all three (each its own spring)")


def stiffness_of(args: argparse.Namespace) -> str:
    """Return ``--stiffness``, or its default: ``joint`` for a spatial ``--axes``, else paper."""
    if args.stiffness is not None:
        return args.stiffness
    return "paper" if getattr(args, "axes", "y") == "y" else "joint"


def add_problem_options(p: argparse.ArgumentParser) -> None:
    """Add the flags that define the fit problem (shared by ``prbdm fit`` and ``pareto``)."""
    p.add_argument("--frequencies", type=int, default=None,
                   help="truth frequencies to match, <= n (default n)")
    p.add_argument("--stiffness", default=None, choices=list(STIFFNESS_KINDS),
                   help="paper: one SCF per pose (Eq. 14); joint: one factor per joint "
                        "(default paper; joint with a spatial --axes)")
    add_axes_option(p)
    p.add_argument("--xi", type=float, default=XI_RAD, help="pose sweep offset, rad (Eq. 11)")
    p.add_argument("--squared", action="store_true", help="compare omega^2 instead of omega")
    p.add_argument("--min-link", type=float, default=MIN_FRACTION, metavar="FRACTION",
                   help="shortest link as a fraction of the beam length (Eq. 15; default "
                        f"{MIN_FRACTION:g}); needs 0 < FRACTION < 1/(joints+1)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--eigen-norm", default=DEFAULT_EIGEN_NORM, choices=list(EIGEN_NORMS),
                   help="eigen error per pose: Eq. 16's l2 norm, dominated by the highest mode "
                        "(paper), or the rms of the per-mode relative errors, each mode weighed "
                        f"equally (relative); default {DEFAULT_EIGEN_NORM}")
    p.add_argument("--deflection-norm", default="position", choices=list(DEFLECTION_NORMS),
                   help="normalise the tip error by the truth tip position (Eq. 19, default) "
                        "or by its displacement")


def add_fit_options(p: argparse.ArgumentParser) -> None:
    """Add the flags of ``prbdm fit`` beyond the problem's."""
    p.add_argument("--objective", default="eigen", choices=list(OBJECTIVES))
    p.add_argument("--starts", type=int, default=64, help="multistart start points")
    p.add_argument("--eps", type=float, default=EPS_RAD, help="pose sweep step, rad (Eq. 11)")
    p.add_argument("--loss-tol", type=float, default=None, help="stop once a start reaches it (%%)")
    p.add_argument("--joint-sweep", action="store_true",
                   help="--stiffness joint: match the frequencies over the pose sweep instead "
                        "of at the straight pose")
    p.add_argument("--polish", type=int, default=4, metavar="K",
                   help="--stiffness paper --objective eigen: polish up to K distinct best "
                        "starts on the paper's loss (0: none; default 4)")
    p.add_argument("--max-nfev", type=int, default=400,
                   help="evaluation cap of each least-squares start (default 400)")
    p.add_argument("--explore-nfev", type=int, default=64, metavar="N",
                   help="--stiffness joint, deflection or combined: residual evaluations of "
                        "every start before the best continue (default 64)")
    p.add_argument("--refine-starts", type=int, default=3, metavar="K",
                   help="--stiffness joint, deflection or combined: how many of the best "
                        "explored starts continue to convergence (0: every start; default 3)")


def add_pareto_options(p: argparse.ArgumentParser) -> None:
    """Add the flags of ``prbdm pareto`` beyond the problem's."""
    p.add_argument("--pop", type=int, default=100, help="population size")
    p.add_argument("--generations", type=int, default=200, help="generations (termination)")
    p.add_argument("--eps", type=float, default=PARETO_EPS_RAD,
                   help="pose sweep step, rad (Eq. 11)")
    p.add_argument("--log10-bounds", default=None, metavar="LOW,HIGH",
                   help="bounds of the log10 stiffness factors (default: joint factors in "
                        "[-1, 1]; SCFs within 1.5 decades of the projected eigen optimum)")
    p.add_argument("--seed-starts", type=int, default=4,
                   help="starts of each single-objective fit seeding the population")
    p.add_argument("--no-seed-fits", action="store_true",
                   help="draw the whole initial population at random")
    p.add_argument("--no-knee-polish", action="store_true",
                   help="keep the raw NSGA-II knee (no Eq. 27 local polish)")


def fit_options(args: argparse.Namespace, min_fraction: float) -> FitOptions:
    """Return the FitOptions of a ``prbdm fit`` command line.

    ``min_fraction`` is ``--min-link``, checked against the beam.
    """
    return FitOptions(
        frequencies=args.frequencies, objective=args.objective, stiffness=stiffness_of(args),
        starts=args.starts, seed=args.seed, xi_rad=args.xi, eps_rad=args.eps,
        squared=args.squared, loss_tol_pct=args.loss_tol, joint_sweep=args.joint_sweep,
        deflection_norm=args.deflection_norm, polish=args.polish, max_nfev=args.max_nfev,
        explore_nfev=args.explore_nfev, refine_starts=args.refine_starts,
        eigen_norm=args.eigen_norm, min_fraction=min_fraction, axes=args.axes,
        **_gain_options(args))


def _gain_options(args: argparse.Namespace) -> dict:
    """Return the gain options of ``prbdm fit`` (``--gain-points`` and its companions)."""
    text = getattr(args, "gain_points", None)
    if not text:
        return {}
    return {"gain_points": tuple(v.strip() for v in text.split(",")),
            "gain_modes": args.gain_modes, "gain_weight": args.gain_weight}


def pareto_options(args: argparse.Namespace, min_fraction: float) -> ParetoOptions:
    """Return the ParetoOptions of a ``prbdm pareto`` command line."""
    return ParetoOptions(
        frequencies=args.frequencies, stiffness=stiffness_of(args), seed=args.seed,
        xi_rad=args.xi, eps_rad=args.eps, squared=args.squared,
        deflection_norm=args.deflection_norm, eigen_norm=args.eigen_norm,
        min_fraction=min_fraction, pop=args.pop, generations=args.generations,
        log10_bounds=parse_bounds(args.log10_bounds), seed_with_fits=not args.no_seed_fits,
        seed_starts=args.seed_starts, polish_knee=not args.no_knee_polish, axes=args.axes)


def parse_bounds(text: str | None) -> tuple[float, float] | None:
    """``"LOW,HIGH"`` as two finite numbers with LOW < HIGH (None stays None)."""
    if text is None:
        return None
    from ..errors import BeamInputError

    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise BeamInputError(f"--log10-bounds = {text!r}: must be LOW,HIGH, e.g. -1,1") \
            from None
    if not (abs(lo) < float("inf") and abs(hi) < float("inf") and lo < hi):
        raise BeamInputError(f"--log10-bounds = {text!r}: needs finite LOW < HIGH")
    return lo, hi
