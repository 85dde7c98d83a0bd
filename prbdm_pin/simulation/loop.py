"""The one driver loop every integrator runs under: step, sample, count, cap, assemble.

As PyElastica's ``integrate(stepper, system, ...)`` drives any of its time steppers, ``integrate``
here drives any stepper: the integrator (``options.integrators``) says which scheme and with
what settings; ``start`` builds its stepper on the system, one module per scheme. A stepper
has the interface of ``scipy.integrate.OdeSolver``, which the ``ScipyIVP`` stepper wraps:

- ``step()`` takes one accepted step (it redoes rejected trial steps itself, and raises
  SolveError when it cannot go on);
- ``t_old``, ``t`` and ``y``: the step's start and end time (s) and the state (q, v) at its end,
  a fresh array per step; ``done`` once ``t`` is the end of the run;
- ``dense_output()``: the last step's interpolant, times (m,) s -> states (m, 2n), valid over
  [t_old, t];
- ``steps``, ``rhs_evaluations``, ``jacobian_updates``: what it has cost so far;
- optionally ``step_samples()``: the times and states of every step the last ``step()`` took,
  for a stepper whose ``step()`` takes many (``"compiled"`` runs the whole run in one call);
  with no ``output_dt`` the loop samples those instead of the end state alone.

The loop owns what is common to all: the samples (every step, or every ``output_dt_s`` from
each step's interpolant), the step cap, the progress report and the raw trajectory.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..errors import BeamInputError
from ..options.integrators import Compiled, Exponential, Gauss, Integrator, ScipyIVP, Trapezoidal
from ..options.limits import check_cap
from .compiled import CompiledStepper
from .exponential import ExponentialStepper
from .gauss import GaussStepper
from .ivp import ScipyStepper
from .newmark import TrapezoidalStepper
from .steps import Samples, output_times
from .system import System


def check_grid(duration_s: float, dt_s: float | None, output_dt_s: float | None,
               max_steps: int) -> None:
    """Refuse a step or a sample interval the run cannot hold, before anything is allocated.

    Parameters
    ----------
    duration_s : float
        Simulated time, s.
    dt_s, output_dt_s : float or None
        The step and the sample interval asked for, s.
    max_steps : int
        The step cap.
    """
    for name, val in (("dt", dt_s), ("output_dt", output_dt_s)):
        if val is not None and not (math.isfinite(val) and 0.0 < val <= duration_s):
            raise BeamInputError(f"{name} = {val!r} s: must be in (0, duration]")
    # counted before anything is allocated (a subnormal step gives an infinite count)
    if dt_s is not None and not duration_s / dt_s <= max_steps:
        raise BeamInputError(f"dt = {dt_s!r} s: {duration_s / dt_s:.3g} steps exceed max_steps = "
                             f"{max_steps}")
    if output_dt_s is not None:
        check_cap(f"output_dt = {output_dt_s!r} s: output samples", duration_s / output_dt_s,
                  "max_output_samples")


def start(integrator: Integrator, system: System, t0: float, y0: np.ndarray, t_bound: float,
          *, dt_s: float | None, output_dt_s: float | None, max_steps: int):
    """Return the stepper of ``integrator`` on ``system`` from (t0 s, y0) to ``t_bound`` (s).

    ``dt_s`` is the nominal step of a scheme that has one (s), ``output_dt_s`` the sample
    interval (s; None: every step); a step count above ``max_steps`` is refused up front.
    """
    if isinstance(integrator, Exponential):
        return ExponentialStepper(integrator, system, t0, y0, t_bound, dt_s=dt_s,
                                  max_steps=max_steps)
    if isinstance(integrator, Gauss):
        return GaussStepper(integrator, system, t0, y0, t_bound, dt_s=dt_s,
                            max_steps=max_steps, dense=output_dt_s is not None)
    if isinstance(integrator, Trapezoidal):
        return TrapezoidalStepper(integrator, system, t0, y0, t_bound, dt_s=dt_s,
                                  output_dt_s=output_dt_s, max_steps=max_steps)
    if isinstance(integrator, ScipyIVP):
        return ScipyStepper(integrator, system, t0, y0, t_bound)
    if isinstance(integrator, Compiled):
        return CompiledStepper(integrator, system, t0, y0, t_bound, output_dt_s=output_dt_s,
                               max_steps=max_steps)
    raise BeamInputError(f"integrator = {integrator!r:.80}: not one simulate knows")


def integrate(stepper, output_dt_s: float | None, max_steps: int,
              progress: Callable[[float], None] | None = None) -> Samples:
    """Step ``stepper`` to its end and return the samples.

    Parameters
    ----------
    stepper
        A stepper from :func:`start` (at its start).
    output_dt_s : float or None
        Sample interval, s: samples at t0 + k output_dt_s up to the end (a rounding slack of
        1e-9), from each step's interpolant; None: a sample at every step.
    max_steps : int
        Refuse to take more steps (BeamInputError).
    progress : callable or None
        Called with the time reached (s) after every step.

    Returns
    -------
    Samples
    """
    n = stepper.y.size // 2
    t0, name = stepper.t, stepper.settings.method
    if output_dt_s is None:
        ts, ys = [t0], [stepper.y]
    else:
        t_out = t0 + output_times(stepper.t_bound - t0, output_dt_s)
        Y = np.empty((len(t_out), 2 * n))
        k = 0  # the next sample
    while not stepper.done:
        stepper.step()
        if stepper.steps > max_steps:
            raise BeamInputError(f"the {name} integrator took more than max_steps = "
                                 f"{max_steps} steps")
        if output_dt_s is None:
            if hasattr(stepper, "step_samples"):
                step_t, step_y = stepper.step_samples()
                ts.extend(step_t)
                ys.extend(step_y)
            else:
                ts.append(stepper.t)
                ys.append(stepper.y)
        else:
            # every step's interpolant is made, as solve_ivp makes it (DOP853's costs
            # evaluations, which the counts keep); a step samples the times in [t_old, t),
            # the last step also the end and its rounding slack beyond
            sample = stepper.dense_output()
            end = len(t_out) if stepper.done else int(np.searchsorted(t_out, stepper.t))
            if end > k:
                Y[k:end] = sample(t_out[k:end])
                k = end
        if progress is not None:
            progress(stepper.t)
    if output_dt_s is None:
        t_out, Y = np.array(ts), np.array(ys)
    return Samples(t_out, Y[:, :n].copy(), Y[:, n:].copy(), int(stepper.steps),
                   int(stepper.rhs_evaluations), int(stepper.jacobian_updates))


def progress_bar(duration_s: float, enabled: bool):
    """Return (a callback for ``integrate``'s ``progress``, a function closing the bar).

    A tqdm bar over the simulated time (s); (None, a no-op) when not ``enabled``.
    """
    if not enabled:
        return None, lambda: None
    from ..io.progress import progress_bar

    bar = progress_bar(duration_s, desc="simulate", unit="s",
                       bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")

    def update(t_s: float) -> None:
        bar.update(t_s - bar.n)

    return update, bar.close
