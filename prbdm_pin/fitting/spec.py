"""What one local solve of a fit is given (FitSpec) and what it returns (StartResult)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..options.checks import check_choice
from ..options.choices import OBJECTIVES, Objective
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
    objective : Objective
        What the solve minimises (not always the options' objective: the seeding and the
        knee polish of a Pareto fit, the projected SCFs that start a ``paper`` deflection fit).
    max_nfev : int
        Evaluation cap of each least-squares start.

    The tip-error normalisation is the problem's (``problem.deflection_norm``).
    """

    problem: FitProblem
    objective: Objective
    max_nfev: int

    def __post_init__(self) -> None:
        """Take the objective as an :class:`Objective` (its string is accepted)."""
        object.__setattr__(self, "objective", check_choice("objective", self.objective,
                                                           Objective))


def tip_scales_m(problem: FitProblem) -> np.ndarray:
    """Return what each load case's tip error is divided by (``objectives.tip_scale_m``), m.

    In the problem's normalisation (``problem.deflection_norm``).
    """
    return np.array([tip_scale_m(c.tip_position_m, c.tip_displacement_m,
                                 problem.deflection_norm)
                     for c in problem.target.load_cases])
