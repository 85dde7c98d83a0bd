"""What a benchmark run covers (:class:`BenchConfig`, ``FULL``, ``QUICK``) and the rows it gives."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import BeamInputError

__all__ = ["BenchConfig", "BenchResult", "Comparison", "DAMPING_RATIO", "FULL", "ModelRow",
           "QUICK", "RANDOM_SEEDS", "SHIPPED", "TruthRow"]

SHIPPED = ("uniform-narrow", "square-plate", "reference-random")
RANDOM_SEEDS = (11, 12, 13, 14, 15)
DAMPING_RATIO = 0.02


@dataclass(frozen=True)
class BenchConfig:
    """What a benchmark run covers.

    Attributes
    ----------
    beams : tuple of str
        Shipped beam names (``examples/beams``) and/or ``"random-<seed>"`` for
        ``random_beam(np.random.default_rng(seed))``.
    joints : tuple of int
        n of the fitted nR models.
    chain_joints : tuple of int
        N of the finite-segment chains.
    truth_levels : tuple of int
        Plate mesh levels timed for the FE truth rows (errors against the last).
    load_indices : tuple of float
        P L^2 / (E I_root) of the tip-error load cases.
    sim_duration_s : float
        Simulated time of each cost measurement, s.
    fit_starts : int
        Multistart size of each fit (stopped early at ``fit_loss_tol``).
    fit_loss_tol_pct : float
        Eigen loss (%) at which a fit stops drawing starts.
    mujoco : bool
        Add the MuJoCo peer when ``mujoco`` is importable.
    """

    beams: tuple[str, ...]
    joints: tuple[int, ...]
    chain_joints: tuple[int, ...]
    truth_levels: tuple[int, ...]
    load_indices: tuple[float, ...] = (1e-3, 1.0, 5.0)
    sim_duration_s: float = 0.5
    fit_starts: int = 16
    fit_loss_tol_pct: float = 1e-6
    mujoco: bool = True

    def __post_init__(self) -> None:
        """Check the lists and the durations (BeamInputError naming the field)."""
        if not self.beams or not self.joints or not self.chain_joints:
            raise BeamInputError("BenchConfig: beams, joints and chain_joints must be non-empty")
        for name, vals, lo in (("joints", self.joints, 1), ("chain_joints", self.chain_joints, 1)):
            if any(int(v) != v or v < lo for v in vals):
                raise BeamInputError(f"{name} = {vals}: must be integers >= {lo}")
        if not (self.sim_duration_s > 0 and math.isfinite(self.sim_duration_s)):
            raise BeamInputError(f"sim_duration_s = {self.sim_duration_s}: must be > 0 (s)")


FULL = BenchConfig(
    beams=SHIPPED + tuple(f"random-{s}" for s in RANDOM_SEEDS),
    joints=tuple(range(1, 9)),
    chain_joints=(2, 4, 8, 16, 32, 64),
    truth_levels=(0, 1, 2),
)
QUICK = BenchConfig(
    beams=("uniform-narrow", "reference-random"),
    joints=(2, 4),
    chain_joints=(4, 16, 32),
    truth_levels=(0,),
    sim_duration_s=0.1,
    fit_starts=8,
    mujoco=False,
)


@dataclass(frozen=True, eq=False)
class ModelRow:
    """One model of one beam.

    Attributes
    ----------
    beam : str
    kind : str
        ``"fitted"``, ``"chain"`` or ``"mujoco"`` (the fitted model run in MuJoCo).
    joints : int
    fit_wall_s : float
        Fit wall time, s (NaN for chains).
    fit_loss_pct : float
        Eigen loss of the fit, % (NaN for chains).
    omega_model_rad_s, omega_truth_rad_s : ndarray, shape (k,)
        The model's first k = min(joints, truth modes) frequencies and the truth's, rad/s.
    tip_errors_pct : ndarray, shape (loads,)
        ``|p_model - p_elastica| / |u_elastica|`` per load index, % (NaN: statics failed/not run).
    step_error_pct, frf_error_pct : float
        Relative L2 error of the tip step response and FRF, % (NaN: not run).
    sim_cpu_s_per_s, sim_wall_s_per_s : float
        CPU and wall time per simulated second, s/s.
    note : str
    """

    beam: str
    kind: str
    joints: int
    fit_wall_s: float
    fit_loss_pct: float
    omega_model_rad_s: np.ndarray
    omega_truth_rad_s: np.ndarray
    tip_errors_pct: np.ndarray
    step_error_pct: float
    frf_error_pct: float
    sim_cpu_s_per_s: float
    sim_wall_s_per_s: float
    note: str = ""

    @property
    def freq_errors_pct(self) -> np.ndarray:
        """Signed relative error of each compared frequency, %."""
        return 100.0 * (self.omega_model_rad_s / self.omega_truth_rad_s - 1.0)

    def max_freq_error_pct(self, modes: int) -> float:
        """Return the largest ``|error|`` over the first ``modes`` frequencies, %.

        NaN if fewer are available.
        """
        e = self.freq_errors_pct
        return float(np.max(np.abs(e[:modes]))) if e.size >= modes else float("nan")


@dataclass(frozen=True, eq=False)
class TruthRow:
    """The plate truth of one beam at one mesh level.

    Attributes
    ----------
    beam : str
    level, dofs : int
    cpu_s, wall_s : float
        Modal solve and mode selection, s.
    omega_rad_s : ndarray
        Selected bending frequencies, rad/s.
    errors_pct : ndarray or None
        Error of each against the finest level run, % (None for the finest itself).
    """

    beam: str
    level: int
    dofs: int
    cpu_s: float
    wall_s: float
    omega_rad_s: np.ndarray
    errors_pct: np.ndarray | None


@dataclass(frozen=True)
class Comparison:
    """Fitted nR model against the smallest finite-segment chain with >= 8n joints run.

    ``chain_joints`` is 0 when no chain that large was run.
    """

    beam: str
    joints: int
    fitted_error_pct: float
    fitted_cost_s_per_s: float
    chain_joints: int
    chain_error_pct: float
    chain_cost_s_per_s: float

    @property
    def as_accurate(self) -> bool:
        """The fitted model's max frequency error is at most the chain's."""
        return self.chain_joints > 0 and self.fitted_error_pct <= self.chain_error_pct

    @property
    def cheaper(self) -> bool:
        """The fitted model simulates at lower CPU cost than the chain."""
        return self.chain_joints > 0 and self.fitted_cost_s_per_s < self.chain_cost_s_per_s


@dataclass(frozen=True, eq=False)
class BenchResult:
    """Everything one run measured."""

    config: BenchConfig
    models: tuple[ModelRow, ...]
    truths: tuple[TruthRow, ...]
    comparisons: tuple[Comparison, ...]
    truth_modes: int
    wall_time_s: float
    notes: tuple[str, ...] = field(default_factory=tuple)
