"""What every integrator takes and returns: the step settings, the raw samples, the step grid."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError


@dataclass(frozen=True)
class StepSettings:
    """How an integrator steps and samples a run (validated by ``simulate``).

    Attributes
    ----------
    duration_s : float
        Simulated time, s.
    dt_s : float or None
        Fixed step (``"gauss"``, ``"trapezoidal"``) or nominal, largest step
        (``"exponential"``), s; unused by ``solve_ivp``.
    output_dt_s : float or None
        Sample interval of the output, s (None: every step).
    max_steps : int
        Refuse runs that would take more steps.
    refresh_rad : float
        ``"exponential"``: joint-angle travel that triggers a new eigen-decomposition, rad.
    method : str
        Integrator name (the ``solve_ivp`` method for ``prbdm_pin.simulation.ivp``).
    rtol : float
        ``solve_ivp`` relative tolerance.
    atol : float or None
        ``solve_ivp`` absolute tolerance (None: rtol times a joint-angle scale).
    """

    duration_s: float
    dt_s: float | None
    output_dt_s: float | None
    max_steps: int
    refresh_rad: float = 0.01
    method: str = "exponential"
    rtol: float = 1e-9
    atol: float | None = None


@dataclass(frozen=True, eq=False)
class Samples:
    """An integrator's output before the tip positions are added.

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
