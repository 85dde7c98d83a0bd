"""What one local solve of a fit is given (FitSpec) and what it returns (StartResult)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..options.choices import OBJECTIVES
from .objectives import tip_scale_m
from .problem import FitProblem

__all__ = ["OBJECTIVES", "BAD_LOSS", "LN_S_BOUNDS", "FitSpec", "StartResult", "tip_scales_m"]

BAD_LOSS = 1e3  # loss (fraction) reported for designs whose model cannot be solved
# the box of the joint factors' logarithms ln s (and, widened, of the SCFs' ln k)
LN_S_BOUNDS = (math.log(1e-3), math.log(1e3))


@dataclass(frozen=True)
class StartResult:
    """Local optimum of one start: lengths (m), factors, loss (%), evaluations, solver message.

    Attributes
    ----------
    index : int
        The start's index (the tie-break of equal losses).
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    factors : ndarray
        Spring factors (dimensionless): the ``joint`` factors on the finite-segment springs,
        shape (n,), or the ``paper`` SCFs, one per pose.
    loss_pct : float
        The fit loss, %.
    nfev : int
        Model evaluations of the start.
    success : bool
        The local solver's success flag.
    message : str
        The local solver's message.
    """

    index: int
    lengths_m: np.ndarray
    factors: np.ndarray
    loss_pct: float
    nfev: int
    success: bool
    message: str


@dataclass(frozen=True, eq=False)
class FitSpec:
    """What one local solve of a fit is given.

    Attributes
    ----------
    problem : FitProblem
        The fit problem (beam, target, joints, poses).
    objective : str
        One of :data:`OBJECTIVES`.
    deflection_norm : str
        The tip-error normalisation, ``"position"`` or ``"displacement"``.
    max_nfev : int
        Evaluation cap of each least-squares start.
    """

    problem: FitProblem
    objective: str
    deflection_norm: str
    max_nfev: int


def tip_scales_m(problem: FitProblem, norm: str) -> np.ndarray:
    """Return what each load case's tip error is divided by (``objectives.tip_scale_m``), m."""
    return np.array([tip_scale_m(c.tip_position_m, c.tip_displacement_m, norm)
                     for c in problem.target.load_cases])
