"""What the shared loop returns and the grids it steps on: the raw samples, the sample times."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError


@dataclass(frozen=True, eq=False)
class Samples:
    """A run's samples before the tip positions are added (what ``loop.integrate`` returns).

    Attributes
    ----------
    t_s : ndarray, shape (s,)
        Sample times, s.
    q_rad, v_rad_s : ndarray, shape (s, n)
        Joint angles (rad) and velocities (rad/s).
    steps : int
        Steps taken.
    rhs_evaluations : int
        Dynamics evaluations.
    jacobian_updates : int
        Iteration matrices or eigen-decompositions built.
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    v_rad_s: np.ndarray
    steps: int
    rhs_evaluations: int
    jacobian_updates: int = 0


def output_times(duration_s: float, output_dt_s: float) -> np.ndarray:
    """Sample times 0, output_dt, ... up to ``duration_s`` (a rounding slack of 1e-9), s."""
    return np.arange(math.floor(duration_s / output_dt_s + 1e-9) + 1) * output_dt_s


def equal_steps(duration_s: float, dt_s: float, max_steps: int) -> int:
    """Return the number of equal steps ending on ``duration_s``, each at most ``dt_s``.

    Up to a 1e-6 relative rounding slack; BeamInputError beyond ``max_steps``.
    """
    nsteps = max(1, math.ceil(duration_s / dt_s - 1e-6))
    if nsteps > max_steps:
        raise BeamInputError(f"dt = {dt_s} s: {nsteps} steps exceed max_steps = {max_steps}")
    return nsteps
