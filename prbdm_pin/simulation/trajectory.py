"""The simulated time response and the dense (quintic Hermite) output of a Gauss step."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..options.integrators import Integrator


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A simulated time response.

    Attributes
    ----------
    t_s : ndarray, shape (s,)
        Sample times, s.
    q_rad : ndarray, shape (s, n)
        Joint angles, rad.
    v_rad_s : ndarray, shape (s, n)
        Joint velocities, rad/s.
    tip_position_m : ndarray, shape (s, 3)
        Tip point in world coordinates, m.
    steps : int
        Integrator steps taken (accepted steps for solve_ivp, ``"compiled"`` and
        ``"exponential"``).
    method : str
        Integrator used, by name (``integrator.method``): under the default ``Auto()`` the
        one its rule picked (``"compiled"`` or ``"exponential"``), never ``"auto"``.
    wall_time_s : float
        Wall time of the whole call (set-up, integration, output), s.
    rhs_evaluations : int
        Dynamics evaluations (ABA for solve_ivp; RNEA residuals, plus one ABA per step when
        interpolating, for ``"gauss"`` and ``"trapezoidal"``; ABA and ABA derivatives for
        ``"exponential"``; the compiled kernel's forward dynamics for ``"compiled"``, three
        more per step that holds a sample).
    jacobian_updates : int
        Iteration matrices built (``"gauss"``) or eigen-decompositions of the Jacobian
        (``"exponential"``); 0 otherwise.
    cpu_time_s : float
        Process CPU time of the whole call, s.
    input_names, output_names : tuple of str
        The plant inputs and outputs recorded (``simulate``'s ``inputs`` and ``outputs``).
    input_units, output_units : tuple of str
    input_values : ndarray, shape (s, m)
        The inputs at each sample, in their units (a controller's evaluated at the sample's
        state).
    output_values : ndarray, shape (s, p)
        The outputs at each sample (values, not deviations), in their units.
    integrator : Integrator or None
        The integrator whole (``method`` is its name): its step, tolerances and caps.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.02, q0=[0.01, 0.0])
    >>> run.q_rad.shape[1], run.tip_position_m.shape[1], float(run.t_s[0])
    (2, 3, 0.0)
    """

    t_s: np.ndarray
    q_rad: np.ndarray
    v_rad_s: np.ndarray
    tip_position_m: np.ndarray
    steps: int
    method: str
    wall_time_s: float
    rhs_evaluations: int = 0
    jacobian_updates: int = 0
    cpu_time_s: float = float("nan")
    input_names: tuple[str, ...] = ()
    input_units: tuple[str, ...] = ()
    input_values: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    output_names: tuple[str, ...] = ()
    output_units: tuple[str, ...] = ()
    output_values: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    integrator: Integrator | None = None

    def input(self, name: str) -> np.ndarray:
        """Return the samples (s,) of the input ``name``."""
        return self.input_values[:, _index(self.input_names, name, "input")]

    def output(self, name: str) -> np.ndarray:
        """Return the samples (s,) of the output ``name``."""
        return self.output_values[:, _index(self.output_names, name, "output")]

    @property
    def tip_displacement_m(self) -> np.ndarray:
        """Tip position minus its position at the first sample, m, shape (s, 3)."""
        return self.tip_position_m - self.tip_position_m[0]


def _index(names: tuple[str, ...], name: str, kind: str) -> int:
    if name not in names:
        raise KeyError(f"{kind} {name!r} was not recorded; recorded: {', '.join(names) or 'none'}")
    return names.index(name)


def hermite_step(t_start: float, h: float, start: tuple, end: tuple, t_s: np.ndarray
                 ) -> np.ndarray:
    """Return the states (q, v) of one step at the times ``t_s`` by quintic Hermite interpolation.

    ``start`` and ``end`` are (q rad, v rad/s, a rad/s^2) at the step's ends, ``t_start`` (s)
    its start and ``h`` (s) the run's equal step; returns shape (len(t_s), 2n).

    Local error O(dt^6) in q and O(dt^5) in v: below the Gauss scheme's own O(dt^4) error.
    """
    s = ((t_s - t_start) / h)[:, None]
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5
    h1 = s - 6 * s3 + 8 * s4 - 3 * s5
    h2 = 0.5 * (s2 - 3 * s3 + 3 * s4 - s5)
    h3 = 0.5 * (s3 - 2 * s4 + s5)
    h4 = -4 * s3 + 7 * s4 - 3 * s5
    h5 = 10 * s3 - 15 * s4 + 6 * s5
    d0 = -30 * s2 + 60 * s3 - 30 * s4
    d1 = 1 - 18 * s2 + 32 * s3 - 15 * s4
    d2 = s - 4.5 * s2 + 6 * s3 - 2.5 * s4
    d3 = 1.5 * s2 - 4 * s3 + 2.5 * s4
    d4 = -12 * s2 + 28 * s3 - 15 * s4
    (q0, v0, a0), (q1, v1, a1) = start, end
    hh = h * h
    q = h0 * q0 + h5 * q1 + h * (h1 * v0 + h4 * v1) + hh * (h2 * a0 + h3 * a1)
    v = (d0 * (q0 - q1)) / h + d1 * v0 + d4 * v1 + h * (d2 * a0 + d3 * a1)
    return np.hstack((q, v))
