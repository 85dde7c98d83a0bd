"""The target of ``prbdm fit`` and ``prbdm pareto``: the truth, its load cases and gains.

From ``--truth TRUTH.json`` or a computed truth (cached), with the ``--extra-loads`` cases, a
spatial fit's 3D tip truth (``--load-point``) and its modal amplitudes (``--gain-points``).
"""

from __future__ import annotations

import sys
from pathlib import Path

from .fit_checks import cache_dir, load_factors

__all__ = ["load_target", "gain_points", "gravity_option"]


def load_target(args, beam):
    """Return the FitTarget of the command, with the ``--extra-loads`` cases.

    The truth comes from ``--truth`` or from ``compute_truth`` (cached).
    """
    import dataclasses

    g = gravity_option(args)
    if g is not None:
        from ..fitting.gravity_target import gravity_target

        return gravity_target(beam, g, modes=max(args.joints, args.frequencies or 0))
    target = _base_target(args, beam)
    # a Pareto front (no --objective) has the deflection objective too
    if getattr(args, "axes", "y") != "y" and getattr(args, "objective", "combined") != "eigen":
        return _spatial_load(args, beam, target)
    factors = load_factors(getattr(args, "extra_loads", None))
    if not factors:
        return target
    from ..errors import BeamInputError
    from ..fitting.load_cases import extra_load_cases  # shared with fit(..., extra_loads=)

    if args.truth:
        raise BeamInputError("extra-loads: needs a computed truth, not --truth TRUTH.json")
    cases = extra_load_cases(beam, factors, args.large_deflection,
                             target.static_theory_gap_pct)
    return dataclasses.replace(target, extra_loads=cases,
                               source=f"{target.source}; extra loads x{args.extra_loads} "
                                      f"({args.large_deflection})")


def _spatial_load(args, beam, target):
    """Return ``target`` with the 3D tip truth of a spatial deflection or combined fit.

    The beam's tip force at ``--load-point``, solved by the plate (linear) or the solid
    (geometrically nonlinear) at the truth's mesh level.
    """
    from ..errors import BeamInputError
    from ..fitting.spatial_deflection import spatial_load_target
    from ..truth.corner_static import corner_static

    if args.truth or args.truth_model not in ("plate", "solid"):
        what = f"--objective {args.objective}" if hasattr(args, "objective") else "a front"
        raise BeamInputError(f"{what} with --axes {args.axes}: the 3D tip "
                             "truth comes from the plate or the solid (--truth-model plate or "
                             "solid, no --truth file)")
    if load_factors(getattr(args, "extra_loads", None)):
        raise BeamInputError("--extra-loads: a spatial fit takes the one load case")
    sol = corner_static(beam, args.truth_model, beam.tip_force_N, args.load_point,
                        level=args.mesh_level, nonlinear=args.truth_model == "solid")
    return spatial_load_target(target, sol)


def _base_target(args, beam):
    from ..errors import BeamInputError
    from ..fitting.target import FitTarget, target_from_truth

    if args.truth:
        from ..files.truth_file import read_truth_file

        if gain_points(args):
            raise BeamInputError("--gain-points: the modal amplitudes come from a computed "
                                 "truth (--truth-model), not from --truth TRUTH.json")

        t = read_truth_file(args.truth)
        fingerprint = t.beam_fingerprint
        # a truth of another beam would be fitted without a word: refuse it; a hand-made file
        # without a fingerprint cannot be checked and is taken on trust
        if fingerprint is not None and fingerprint != beam.fingerprint():
            raise BeamInputError(
                f"truth = {args.truth!r}: computed for beam fingerprint {fingerprint}, but "
                f"{args.beam!r} has fingerprint {beam.fingerprint()}: compute its own truth")
        if fingerprint is None and not getattr(args, "quiet", False):
            print(f"truth warning: {args.truth} carries no beam_fingerprint: cannot check "
                  "that it belongs to this beam", file=sys.stderr)
        try:
            return FitTarget(t.omega_rad_s, beam.tip_force_N, t.tip_position_m,
                             t.tip_displacement_m, t.mac,
                             source=f"truth file {Path(args.truth).name}",
                             static_theory_gap_pct=t.static_theory_gap_pct)
        except (ValueError, KeyError, TypeError) as exc:
            raise BeamInputError(f"truth = {args.truth!r}: cannot be used ({exc})") from None
    from ..truth import CoarseTruthError, TruthRequest

    # --accept-coarse drops the tolerance; without it the request's default holds
    coarse = {"error_tol_pct": None} if getattr(args, "accept_coarse", False) else {}
    # a spatial chain is fitted to its frequencies alone, over the truth's modes of every kind
    spatial = getattr(args, "axes", "y") != "y"
    if spatial:  # a spatial load case is solved apart (_spatial_load)
        coarse.update(spatial=True, static=False)
    request = TruthRequest(model=args.truth_model, modes=max(args.joints, args.frequencies or 0),
                           mesh_level=args.mesh_level, selection=args.mode_selection,
                           large_deflection=args.large_deflection, **coarse)
    try:
        truth = request.compute(beam, cache_dir=cache_dir(args))
    except CoarseTruthError as exc:
        raise BeamInputError(f"{exc}") from None
    if not getattr(args, "quiet", False):
        for note in truth.warnings:
            print(f"truth warning: {note}", file=sys.stderr)
    target = target_from_truth(truth, beam.tip_force_N, request)
    points = gain_points(args)
    if points:
        from ..fitting.spatial_gains import with_point_gains

        target = with_point_gains(target, truth, beam, points)
    return target


def gravity_option(args):
    """Return ``--gravity`` (m/s^2, (3,)) or None without it; refuse what it cannot take.

    A fit in gravity is the planar ``joint`` chain against the 1D beam truth computed here
    (``--truth-model beam --stiffness joint``, no ``--truth`` file, ``--extra-loads``,
    ``--gain-points`` or ``--axes`` other than y); BeamInputError naming the option otherwise.
    """
    from ..errors import BeamInputError
    from ..truth.self_weight import check_gravity
    from .checks import xyz_option

    text = getattr(args, "gravity", None)
    if text is None:
        return None
    g = check_gravity(xyz_option(text, "--gravity", "m/s^2"), "--gravity")
    if not g.any():
        return None
    for option, bad in (("--truth-model", args.truth_model != "beam"),
                        ("--stiffness", getattr(args, "stiffness", None) != "joint"),
                        ("--axes", getattr(args, "axes", "y") != "y"),
                        ("--truth", bool(args.truth)),
                        ("--extra-loads", bool(getattr(args, "extra_loads", None))),
                        ("--gain-points", bool(gain_points(args)))):
        if bad:
            raise BeamInputError(f"{option}: a fit in gravity (--gravity) takes the planar "
                                 "chain with --stiffness joint against the 1D beam truth in "
                                 "that gravity (--truth-model beam), without --truth, "
                                 "--extra-loads, --gain-points or --axes")
    return g


def gain_points(args) -> tuple[str, ...]:
    """Return ``--gain-points`` as a tuple of names (() without it)."""
    text = getattr(args, "gain_points", None)
    return () if not text else tuple(v.strip() for v in text.split(","))
