"""The time responses of a batch of designs on one time grid (``simulate_batch``'s result)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..options.integrators import Integrator
from .trajectory import Trajectory

__all__ = ["TrajectoryBatch"]


@dataclass(frozen=True, eq=False)
class TrajectoryBatch:
    """The simulated time responses of B designs, sampled at the same times.

    Attributes
    ----------
    t_s : ndarray, shape (s,)
        Sample times, s.
    q_rad : ndarray, shape (B, s, n)
        Joint angles of each design, rad.
    v_rad_s : ndarray, shape (B, s, n)
        Joint rates, rad/s.
    tip_position_m : ndarray, shape (B, s, 3)
        Tip points in world coordinates, m.
    steps : ndarray of int, shape (B,)
        Accepted steps each design took (the vectorised run: its block's steps, the same for
        the designs stepped together; with no output grid, one block for all).
    rhs_evaluations : ndarray of int, shape (B,)
        Dynamics evaluations each design cost (the vectorised run evaluates all at once).
    rejected_steps : ndarray of int, shape (B,)
        Trial steps refused by the error control (0 where not known: the loop's solvers).
    method : str
        Integrator, by name.
    vectorised : bool
        True when the designs were integrated together (planar clamped chains), False when
        looped through :func:`prbdm_pin.simulate`.
    cpu_time_s, wall_time_s : float
        Process CPU and wall time of the whole call, s.
    integrator : Integrator or None
        The integrator whole: its tolerances and caps.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> models = [pp.build_model(beam, [0.2, 0.5, 0.3], [k, 1200.0]) for k in (2500.0, 3000.0)]
    >>> runs = pp.simulate_batch(models, 0.02, q0=[0.01, 0.0], output_dt_s=0.01, rtol=1e-6)
    >>> runs.q_rad.shape, runs.tip_position_m.shape, runs.t_s.tolist()
    ((2, 3, 2), (2, 3, 3), [0.0, 0.01, 0.02])
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    v_rad_s: np.ndarray
    tip_position_m: np.ndarray
    steps: np.ndarray
    rhs_evaluations: np.ndarray
    rejected_steps: np.ndarray
    method: str
    vectorised: bool
    cpu_time_s: float
    wall_time_s: float
    integrator: Integrator | None = None

    @property
    def n_designs(self) -> int:
        """Number of designs B."""
        return int(self.q_rad.shape[0])

    @property
    def tip_displacement_m(self) -> np.ndarray:
        """Tip positions minus each design's first sample, m, shape (B, s, 3)."""
        return self.tip_position_m - self.tip_position_m[:, :1]

    def design(self, index: int) -> Trajectory:
        """Return design ``index``'s response as a :class:`~prbdm_pin.Trajectory`.

        Its cost fields are the batch's shares (CPU and wall time divided by B).
        """
        b = int(index)
        if not -self.n_designs <= b < self.n_designs:
            from ..errors import BeamInputError

            raise BeamInputError(f"index = {index!r}: the batch has {self.n_designs} designs")
        B = self.n_designs
        return Trajectory(self.t_s, self.q_rad[b], self.v_rad_s[b], self.tip_position_m[b],
                          int(self.steps[b]), self.method, self.wall_time_s / B,
                          int(self.rhs_evaluations[b]), 0, self.cpu_time_s / B,
                          integrator=self.integrator)
