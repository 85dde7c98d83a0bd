"""Warm starts: a previous fit (or explicit lengths and springs) as the one start of a fit.

A warm fit runs that start only. The point of a warm start is to stay on the previous fit's
branch: a multistart would return whichever local optimum is lowest, which is what makes the
parameters of independent fits jump between neighbouring designs. The start is recorded in the
options (``start_lengths_m``, ``start_factors``), so a fit.json says it was warm-started and
from where.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from ..options.checks import check_choice
from ..options.choices import StiffnessKind
from ..options.objects import FitOptions
from .parametrisation import parametrisation
from .results import FitResult

__all__ = ["start_changes"]


def _lengths(v: Any, beam: Beam, joints: int) -> np.ndarray:
    try:
        L = np.asarray(v, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise BeamInputError(f"start lengths = {v!r:.60}: must be numbers (m)") from None
    if L.size != joints + 1:
        raise BeamInputError(f"start lengths: {L.size} links given: a {joints}R model has "
                             f"{joints + 1}")
    if not np.all(np.isfinite(L)) or np.any(L <= 0):
        raise BeamInputError(f"start lengths = {L.tolist()}: must be finite and > 0 (m)")
    # a design path may change the span: keep the start's length fractions
    return L * (beam.length_m / L.sum())


def start_changes(start: Any, beam: Beam, joints: int, options: FitOptions) -> dict[str, Any]:
    """Return the option changes of a warm start from ``start``.

    ``start`` is a FitResult, or a pair (lengths m (n+1,), springs N m/rad (n,)) for a
    ``joint`` fit.

    ``joint``: the start keeps the previous springs (N m/rad), as factors on this beam's
    finite-segment springs. ``paper``: a FitResult's SCFs, one per pose. Lengths are rescaled to
    this beam's span. A start with another number of joints, stiffness kind or number of poses
    is a BeamInputError naming it.

    Parameters
    ----------
    start : FitResult or tuple
        The previous fit, or (lengths m, springs N m/rad).
    beam : Beam
        The beam of the fit to start.
    joints : int
        n, the number of revolute joints of the fit to start.
    options : FitOptions
        The fit's options (its stiffness kind and minimum link fraction).

    Returns
    -------
    dict
        ``start_lengths_m`` (m, rescaled to this beam's span) and ``start_factors``
        (dimensionless), as tuples of float.
    """
    springs_of = parametrisation(options.stiffness)
    if isinstance(start, FitResult):
        if start.joints != joints:
            raise BeamInputError(f"start: a {start.joints}R fit cannot start a {joints}R fit "
                                 f"(joints = {joints})")
        if check_choice("stiffness", start.stiffness, StiffnessKind) is not options.stiffness:
            raise BeamInputError(f"start: stiffness = {start.stiffness!r}: this fit's is "
                                 f"{springs_of.name!r}")
        lengths = _lengths(start.lengths_m, beam, joints)
        springs = np.asarray(start.stiffness_Nm_per_rad, dtype=float)
        factors = np.asarray(start.factors, dtype=float)
    elif isinstance(start, (tuple, list)) and len(start) == 2:
        if not springs_of.pose_independent:
            raise BeamInputError("start = (lengths, springs): needs stiffness = 'joint' (a "
                                 "'paper' fit starts from a FitResult, which has its SCFs)")
        lengths = _lengths(start[0], beam, joints)
        springs = np.asarray(start[1], dtype=float).reshape(-1)
        factors = None
    else:
        raise InputTypeError(f"start = {start!r:.60}: must be a FitResult or a pair "
                             "(lengths m, springs N m/rad)")
    # joint: the springs as factors on this beam's; paper: the SCFs (fit() checks their count)
    factors = springs_of.start_factors(beam, lengths, springs, factors, options.min_fraction)
    return {"start_lengths_m": tuple(float(v) for v in lengths),
            "start_factors": tuple(float(v) for v in factors)}
