"""The public entry of a time response: ``simulate`` checks its inputs, assembles the system,
picks the default step and runs the chosen integrator."""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from ..damping import DAMPING_FORMS, damping_ratios
from ..eigen import generalized_eigh
from ..errors import BeamInputError
from . import exponential, gauss, ivp, newmark
from .ivp import IVP_METHODS
from .schedule import StiffnessSchedule
from .steps import StepSettings
from .system import assemble_system, force_function, mass_matrix, tip_positions, vector
from .trajectory import Trajectory

FIXED_STEP_METHODS = ("gauss", "exponential", "trapezoidal")
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
    damping_ratio: float | np.ndarray = 0.02,
    damping: str = "modal",
    stiffness_schedule: StiffnessSchedule | None = None,
    method: str = "exponential",
    rtol: float = 1e-9,
    atol: float | None = None,
    dt: float | None = None,
    output_dt: float | None = None,
    damping_pose: np.ndarray | None = None,
    max_steps: int = 10_000_000,
    steps_per_period: float | None = None,
    refresh_rad: float = 0.01,
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
    damping_ratio : float or ndarray (n,)
        Modal damping ratios xi_k (``"modal"``), per-joint factors (``"eq5c"``) or mode 1's
        ratio (``"stiffness"``, one value); 0 disables damping.
    damping : {"modal", "eq5c", "stiffness"}
        Damping form, see ``prbdm_pin.damping``.
    stiffness_schedule : StiffnessSchedule, optional
        Pose-dependent stiffness (paper parametrisation); default: the model's constant stiffness.
    method : str
        ``"exponential"`` (default), ``"gauss"`` (symplectic; long undamped runs) or
        ``"trapezoidal"``, all fixed step ``dt``, or a ``solve_ivp`` method (``rtol``,
        ``atol``). See ``prbdm_pin.simulation`` for when to use which.
    rtol, atol : float
        Tolerances for ``solve_ivp`` methods (atol defaults to rtol times a joint-angle scale).
    dt : float, optional
        Step of the fixed-step schemes, s (default: the lowest natural period at ``q0`` divided
        by ``steps_per_period``); for ``"exponential"`` the nominal and largest step, shortened
        by its step control where the motion needs it.
    output_dt : float, optional
        Sample interval of the returned trajectory, s (default: every step).
        ``"exponential"`` evaluates its continuous extension, ``"gauss"`` interpolates between
        its steps (quintic Hermite); ``"trapezoidal"`` shortens its step to divide
        ``output_dt``.
    damping_pose : ndarray (n,), optional
        Pose at which the damping matrix is computed and frozen (default: ``q0``).
    max_steps : int
        Refuse runs that would take more fixed steps.
    steps_per_period : float, optional
        Default-step rule: steps per lowest natural period (``"exponential"`` 10,
        ``"gauss"`` 40, ``"trapezoidal"`` 100).
    refresh_rad : float
        ``"exponential"``: rebuild the linearisation's eigen-decomposition when a joint angle
        has moved by more than this since the last one, rad (0 rebuilds every step).

    Returns
    -------
    Trajectory
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    n = int(model.n_joints)
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    q0 = vector("q0", q0, n)
    v0 = vector("v0", v0, n)
    force, constant_force = force_function(tip_force)
    xi = damping_ratios(damping_ratio, n)
    if damping not in DAMPING_FORMS:
        raise BeamInputError(f"damping = {damping!r}: must be one of {', '.join(DAMPING_FORMS)}")
    if stiffness_schedule is not None and not isinstance(stiffness_schedule, StiffnessSchedule):
        raise BeamInputError("stiffness_schedule: must be a StiffnessSchedule")
    if stiffness_schedule is not None and stiffness_schedule.stiffness_Nm_per_rad.shape[1] != n:
        raise BeamInputError(f"stiffness_schedule: needs {n} joint stiffnesses per pose")
    for name, val in (("dt", dt), ("output_dt", output_dt)):
        if val is not None and not (math.isfinite(val) and 0.0 < val <= duration_s):
            raise BeamInputError(f"{name} = {val!r} s: must be in (0, duration]")
    if not (isinstance(refresh_rad, (int, float, np.number)) and math.isfinite(refresh_rad)
            and refresh_rad >= 0.0):
        raise BeamInputError(f"refresh_rad = {refresh_rad!r}: must be a finite number >= 0")
    if method not in FIXED_STEP_METHODS and method not in IVP_METHODS:
        raise BeamInputError(
            f"method = {method!r}: must be one of {FIXED_STEP_METHODS + IVP_METHODS}"
        )
    if not (math.isfinite(rtol) and rtol > 0.0):
        raise BeamInputError(f"rtol = {rtol!r}: must be > 0")
    if steps_per_period is not None and not (
        math.isfinite(steps_per_period) and steps_per_period >= 1.0
    ):
        raise BeamInputError(f"steps_per_period = {steps_per_period!r}: must be >= 1")

    system = assemble_system(model, q0, damping_ratios=xi, damping=damping,
                             schedule=stiffness_schedule, tip_force_N=force,
                             constant_force=constant_force, damping_pose=damping_pose)
    if method in FIXED_STEP_METHODS and dt is None:
        w2 = generalized_eigh(np.diag(system.springs(q0)),
                              mass_matrix(system.pin_model, system.data, q0), "step size",
                              vectors=False)
        spp = steps_per_period or _DEFAULT_SPP[method]
        dt = min(2.0 * math.pi / math.sqrt(max(w2[0], 1e-300)) / spp, duration_s)
    settings = StepSettings(duration_s, dt, output_dt, max_steps, refresh_rad, method, rtol, atol)
    samples = _FIXED_STEP.get(method, ivp.integrate)(system, q0, v0, settings)
    tip = tip_positions(model, system.data, samples.q_rad, system.lengths_m)
    t, Q, V = samples.t_s, samples.q_rad, samples.v_rad_s
    for arr in (t, Q, V, tip):
        arr.setflags(write=False)
    return Trajectory(t, Q, V, tip, int(samples.steps), method, time.perf_counter() - wall0,
                      int(samples.rhs_evaluations), int(samples.jacobian_updates),
                      time.process_time() - cpu0)
