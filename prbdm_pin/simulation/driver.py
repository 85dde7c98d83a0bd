"""The public entry of a time response: ``simulate`` checks its inputs, assembles the system,
picks the default step and runs the chosen integrator."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ..choices import FIXED_STEP_METHODS
from ..damping import damping_ratios
from ..eigen import generalized_eigh
from ..errors import BeamInputError
from ..options import SimulationOptions
from . import exponential, gauss, ivp, newmark
from .schedule import StiffnessSchedule
from .steps import StepSettings
from .system import assemble_system, force_function, mass_matrix, tip_positions, vector
from .trajectory import Trajectory

_FIXED_STEP = {"gauss": gauss.integrate, "exponential": exponential.integrate,
               "trapezoidal": newmark.integrate}
# default steps per lowest natural period
_DEFAULT_SPP = {"gauss": 40.0, "exponential": 10.0, "trapezoidal": 100.0}


def simulate(
    model,
    duration_s: float,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    tip_force: np.ndarray | Callable[[float], np.ndarray] | None = None,
    options: SimulationOptions | None = None,
    *,
    stiffness_schedule: StiffnessSchedule | None = None,
    damping_pose: np.ndarray | None = None,
    **changes: Any,
) -> Trajectory:
    """Integrate the PRBDM's equations of motion from (q0, v0) over ``duration_s``.

    Parameters
    ----------
    model : PrbdmModel
        Provides ``pin_model``, ``tip_frame_id``, ``n_joints`` and ``stiffness_Nm_per_rad``.
    duration_s : float
        Simulated time, s.
    q0, v0 : ndarray, shape (n,), optional
        Initial joint angles (rad) and velocities (rad/s); default zero (straight, at rest).
    tip_force : ndarray (3,) or callable t -> (3,), optional
        World-frame force at the tip point, N (a constant array is a step load applied at t = 0).
    options : SimulationOptions, optional
        The integrator, its step and tolerances, and the damping (ratio and form); see
        :class:`prbdm_pin.options.SimulationOptions` and ``prbdm_pin.simulation`` for when to
        use which integrator.
    stiffness_schedule : StiffnessSchedule, optional
        Pose-dependent stiffness (paper parametrisation); default: the model's constant stiffness.
    damping_pose : ndarray (n,), optional
        Pose at which the damping matrix is computed and frozen (default: ``q0``).
    **changes
        Options by name, applied to ``options`` (``simulate(model, 1.0, method="gauss")``).

    Returns
    -------
    Trajectory
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    o = _options(options, changes)
    method, dt, output_dt = o.method, o.dt_s, o.output_dt_s
    if getattr(model, "hub", None) is not None:
        # the integrators assume one spring per coordinate; a hub adds a free one
        raise BeamInputError("model has a hub: simulate integrates the clamped chain only; "
                             "use prbdm_pin.linearize for the hub model's linear plant")
    n = int(model.n_joints)
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    q0 = vector("q0", q0, n)
    v0 = vector("v0", v0, n)
    force, constant_force = force_function(tip_force)
    xi = damping_ratios(np.asarray(o.damping_ratio, dtype=float) if isinstance(
        o.damping_ratio, tuple) else o.damping_ratio, n)
    if stiffness_schedule is not None and not isinstance(stiffness_schedule, StiffnessSchedule):
        raise BeamInputError("stiffness_schedule: must be a StiffnessSchedule")
    if stiffness_schedule is not None and stiffness_schedule.stiffness_Nm_per_rad.shape[1] != n:
        raise BeamInputError(f"stiffness_schedule: needs {n} joint stiffnesses per pose")
    for name, val in (("dt", dt), ("output_dt", output_dt)):
        if val is not None and not (math.isfinite(val) and 0.0 < val <= duration_s):
            raise BeamInputError(f"{name} = {val!r} s: must be in (0, duration]")
    system = assemble_system(model, q0, damping_ratios=xi, damping=o.damping,
                             schedule=stiffness_schedule, tip_force_N=force,
                             constant_force=constant_force, damping_pose=damping_pose)
    if method in FIXED_STEP_METHODS and dt is None:
        w2 = generalized_eigh(np.diag(system.springs(q0)),
                              mass_matrix(system.pin_model, system.data, q0), "step size",
                              vectors=False)
        spp = o.steps_per_period or _DEFAULT_SPP[method]
        dt = min(2.0 * math.pi / math.sqrt(max(w2[0], 1e-300)) / spp, duration_s)
    settings = StepSettings(duration_s, dt, output_dt, o.max_steps, o.refresh_rad, method,
                            o.rtol, o.atol)
    samples = _FIXED_STEP.get(method, ivp.integrate)(system, q0, v0, settings)
    tip = tip_positions(model, system.data, samples.q_rad, system.lengths_m)
    t, Q, V = samples.t_s, samples.q_rad, samples.v_rad_s
    for arr in (t, Q, V, tip):
        arr.setflags(write=False)
    return Trajectory(t, Q, V, tip, int(samples.steps), method, time.perf_counter() - wall0,
                      int(samples.rhs_evaluations), int(samples.jacobian_updates),
                      time.process_time() - cpu0)


def _options(options: SimulationOptions | None, changes: dict[str, Any]) -> SimulationOptions:
    if options is None:
        options = SimulationOptions()
    elif not isinstance(options, SimulationOptions):
        raise BeamInputError(f"options = {options!r:.80}: must be a SimulationOptions")
    return options.replace(**changes) if changes else options
