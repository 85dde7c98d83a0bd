"""The ``"compiled"`` integrator's stepper: scipy's DOP853 run whole inside the chain kernel.

``Compiled(rtol, atol)`` integrates y = (q, v), y' = (v, M(q)^-1 (-K q - C v + J^T f - h)) with
the Dormand-Prince 8(5,3) pair exactly as ``ScipyIVP("DOP853")`` does (:mod:`.dop853`: the
same coefficients, error norm, step control, initial step and dense output, so the same steps
and the same accuracy for the same tolerances), but the whole run is one numba call on the
compiled kernel (:mod:`prbdm_pin.kernel`): the mass matrix by CRBA, the bias forces by RNEA and
the accelerations by Cholesky, with no Python per step or per stage.

It serves what the kernel evaluates: constant springs, the frozen damping matrix, a constant
world tip force (a step load), gravity, a release from a bent pose, an initial velocity (a
spinning hub), on planar, spatial, hub and free-bus chains. It refuses, naming the option, what
would need Python inside the run: a callable ``tip_force``, a ``stiffness_schedule`` and plant
``inputs`` (and so a ``base_motion``, which enters as an input force); use ``"DOP853"`` there.

Under the shared loop the first ``step()`` takes every step: ``dense_output()`` then returns the
samples at ``output_dt`` it made inside the run (the three extra stages of the interpolant are
evaluated only for a step that holds a sample, and counted), and with no ``output_dt``
``step_samples()`` returns every step's state. The counts are the run's: accepted steps and
right-hand side evaluations (each a CRBA, an RNEA and a Cholesky solve). The progress bar
moves once, at the end.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, SolveError
from ..kernel import chain_kernel
from ..options.integrators import Compiled
from .ivp import default_atol
from .steps import output_times
from .system import System

_EPS = float(np.finfo(float).eps)


class CompiledStepper:
    """The whole DOP853 run in one compiled call (the stepper of ``Compiled``).

    Parameters
    ----------
    settings : Compiled
    system : System
    t0, t_bound : float
        Start and end time, s.
    y0 : ndarray, shape (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    output_dt_s : float or None
        Sample interval, s (None: every step).
    max_steps : int
        The step cap.
    """

    def __init__(self, settings: Compiled, system: System, t0: float, y0: np.ndarray,
                 t_bound: float, *, output_dt_s: float | None, max_steps: int):
        if system.schedule is not None:
            raise BeamInputError("stiffness_schedule: the 'compiled' integrator takes constant "
                                 "springs; use method='DOP853'")
        if system.inputs is not None:
            raise BeamInputError("inputs: the 'compiled' integrator takes a constant tip force "
                                 "only; use method='DOP853'")
        if system.tip_force_N is not None and not system.constant_force:
            raise BeamInputError("tip_force: a force that varies in time needs Python inside "
                                 "the run; the 'compiled' integrator takes a constant one (use "
                                 "method='DOP853')")
        self.settings, self.system, self.t_bound = settings, system, t_bound
        self._kernel = chain_kernel(system.pin_model, system.tip_frame_id)
        self._y0 = np.ascontiguousarray(y0, dtype=float)
        self._t0, self._max_steps = float(t0), int(max_steps)
        self._t_out = None if output_dt_s is None else t0 + output_times(t_bound - t0,
                                                                          output_dt_s)
        # scipy raises a tolerance under 100 EPS to that (validate_tol)
        self._rtol = max(settings.rtol, 100 * _EPS)
        self._atol = default_atol(settings, self._y0)
        self.t = self.t_old = t0
        self.y = self._y0
        self.done = not t_bound > t0
        self.steps = self.rhs_evaluations = self.jacobian_updates = 0
        self._samples = None

    def step(self) -> None:
        """Run every step to ``t_bound``; SolveError when it cannot go on."""
        from .dop853 import COEFFICIENTS, dop853_run

        sy, n = self.system, self._kernel.n
        k = np.ascontiguousarray(sy.stiffness_Nm_per_rad, dtype=float)
        damped = sy.damping_Nms_per_rad is not None
        C = np.ascontiguousarray(sy.damping_Nms_per_rad if damped else np.zeros((n, n)))
        forced = sy.tip_force_N is not None
        f = np.ascontiguousarray(sy.tip_force_N(0.0) if forced else np.zeros(3), dtype=float)
        every = self._t_out is None
        t_out = np.zeros(0) if every else self._t_out
        Y = np.empty((t_out.size, 2 * n))
        status, steps, nfev, t, ts, ys = dop853_run(
            self._kernel.arrays(), self._kernel.new_data().arrays(), k, C, damped, f, forced,
            self._t0, self._y0, float(self.t_bound), self._rtol, float(self._atol), t_out,
            every, self._max_steps, *COEFFICIENTS, Y)
        self.steps, self.rhs_evaluations = int(steps), int(nfev)
        if status == 2:
            return  # the loop refuses a run over max_steps, naming it
        if status == 1:
            raise SolveError(f"compiled DOP853: the step size fell below scipy's minimum at "
                             f"t = {t:.6g} s")
        if status == 3:
            raise SolveError(f"compiled DOP853: the mass matrix is not positive definite or "
                             f"the state not finite at t = {t:.6g} s")
        self.t_old, self.t, self.done = self._t0, float(self.t_bound), True
        if every:
            self._samples = (ts[1:], ys[1:])
            self.y = ys[-1].copy()
        else:
            self._samples = Y
            self.y = Y[-1].copy()  # the end's sample (within the samples' rounding slack)

    def step_samples(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the times (s) and states (q, v) of every step the last ``step()`` took."""
        return self._samples

    def dense_output(self):
        """Return the run's samples as an interpolant of the sample times: (m,) s -> (m, 2n)."""
        t_out, Y = self._t_out, self._samples
        return lambda t_s: Y[np.searchsorted(t_out, t_s)]
