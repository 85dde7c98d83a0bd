"""The public entry of a time response: ``simulate``.

It checks its inputs, assembles the system, picks the default step, starts the chosen
integrator's stepper and runs it under the shared loop (``loop``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..chain.eigen import generalized_eigh
from ..chain.pin_dynamics import planar_lengths
from ..errors import BeamInputError, InputTypeError
from ..model.checks import check_model
from ..model.hub import hub_frequencies
from ..model.inputs import StrainActuator
from ..model.supports import N_BASE, free_frequencies
from ..options.checks import check_float
from ..options.integrators import Auto, Exponential, Integrator
from ..options.simulation import SimulationOptions
from .base_motion import BaseForce, BaseMotion
from .damping import damping_ratios
from .default_rule import default_integrator
from .loop import check_grid, integrate, progress_bar, start
from .schedule import StiffnessSchedule
from .signals import plant_signals, recorded
from .system import assemble_system, force_function, mass_matrix, tip_positions, vector
from .trajectory import Trajectory


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
    inputs: Sequence[str] = (),
    u: Any = None,
    actuators: Sequence[StrainActuator] = (),
    loads: Sequence = (),
    outputs: Sequence[str] = (),
    gravity_m_s2: np.ndarray | None = None,
    integrator: Integrator | None = None,
    base_motion: BaseMotion | None = None,
    progress: bool = False,
    spin_rad_s: float | None = None,
    **changes: Any,
) -> Trajectory:
    """Integrate the PRBDM's equations of motion from (q0, v0) over ``duration_s``.

    Parameters
    ----------
    model : PrbdmModel
        Provides ``pin_model``, ``tip_frame_id``, ``n_joints`` and ``stiffness_Nm_per_rad``;
        clamped, on a hub or on a free bus (``build_model(..., support=FreeBus(...))``; no
        stiffness schedule there).
    duration_s : float
        Simulated time, s.
    q0, v0 : ndarray, shape (nv,), optional
        Initial joint angles (rad) and velocities (rad/s), the hub's first on a hub model,
        the bus's six coordinates first on a free-bus model (x, y, z m; yaw, pitch, roll rad:
        :mod:`prbdm_pin.model.supports`); default zero (straight, at rest). Under a
        ``base_motion`` they are the member's, relative to the base.
    tip_force : ndarray (3,) or callable t -> (3,), optional
        World-frame force at the tip point, N (a constant array is a step load applied at t = 0).
    options : SimulationOptions, optional
        The integrator, the sampling, the step cap and the damping (ratio and form); see
        :class:`prbdm_pin.SimulationOptions` and ``prbdm_pin.simulation`` for when to use which
        integrator.
    stiffness_schedule : StiffnessSchedule, optional
        Pose-dependent stiffness (paper parametrisation); default: the model's constant stiffness.
    damping_pose : ndarray (nv,), optional
        Pose at which the damping matrix is computed and frozen (default: ``q0``).
    inputs : sequence of str
        Plant inputs by name, as :func:`prbdm_pin.linearize` takes them (``hub_torque``,
        ``joint_torque[j]``, ``strain[i]``, ``tip_force_z``, ``tip_force_x``,
        ``tip_force_y``, ``tip_moment_x``, ``tip_moment_y``, ``tip_moment_z``,
        ``corner_force_z_left``, ``corner_force_z_right``;
        the moment and the corner forces are dead loads, about world x and along world z;
        ``tip_moment_follower_x``/``_y``/``_z`` (N m, about the tip link's own axes),
        ``distributed_force_x``/``_y``/``_z`` (N/m, world, over the whole beam, or with
        ``[i]`` over ``loads[i]``), ``base_accel_x``/``_y``/``_z`` (m/s^2, the base's
        acceleration: the motion and outputs are then relative to the base), see
        :mod:`prbdm_pin.model.loads`).
    u : array (m,), callable t -> (m,), Controller or StateFeedback, optional
        What drives the inputs (see :mod:`prbdm_pin.simulation.inputs`); default zero.
    actuators : sequence of StrainActuator
        The strain actuators ``strain[i]`` refers to.
    loads : sequence of DistributedLoad
        The spans ``distributed_force_z[i]`` (and ``_x``, ``_y``) refer to.
    gravity_m_s2 : array_like (3,), optional
        Gravity, m/s^2, world (default none): the chain's weight through Pinocchio's dynamics
        (its generalized gravity and their derivatives), as ``linearize`` and ``statics`` take
        it.
    outputs : sequence of str
        Plant outputs to record by name (``tip_z``, ``tip_z_rate``, ``hub_angle``, ``q[j]``,
        the sensors ``slope@X``, ``twist@X``, ``point_z@X:Y``, ``strain@X``,
        ``root_force_z``, ``root_moment_y``, ...: see :mod:`prbdm_pin.model.outputs`; on a
        free bus also ``bus_attitude_x|y|z``, ``bus_rate_x|y|z``, ``bus_position_x|y|z``:
        :mod:`prbdm_pin.model.bus_outputs`); the trajectory records them and the inputs. The
        strain and the root reaction read each sample's acceleration (Pinocchio's ABA of the
        run's forces) and applied loads.
    integrator : Integrator, optional
        The integrator and its settings (``Auto(...)``, the default, ``Exponential(...)``,
        ``Gauss(...)``, ``Trapezoidal(...)``, ``ScipyIVP(...)``, ``Compiled(...)`` from
        :mod:`prbdm_pin.options.integrators`),
        applied to ``options``; ``method="gauss"`` with ``dt_s``, ``rtol`` ... spells the same.
        ``Auto`` is replaced by the integrator the stated rule picks for the assembled scene
        (:func:`prbdm_pin.simulation.default_rule.default_integrator`); the trajectory
        records the one used.
    base_motion : BaseMotion, optional
        A prescribed motion of the clamp (a robot flange; clamped models only, not with
        ``method="gauss"``): :mod:`prbdm_pin.simulation.base_motion`. The member's
        coordinates, tip and outputs are then relative to the base, in the base frame
        (:func:`~prbdm_pin.simulation.base_motion.world_tip_positions` gives the world tip);
        ``tip_force`` and the tip and corner inputs act in the base frame too, gravity in the
        world frame.
        On a model with a free bus the tip and the member's outputs are relative to the bus
        too, in the clamp frame (the bus frame moved to ``FreeBus.root_m``).
    progress : bool
        Show a progress bar over the simulated time.
    spin_rad_s : float, optional
        Hub models: start from the hub's steady spin at this rate, rad/s: it is added to the
        hub's entry of ``v0`` (which is then the deviation from the spin, as the states of
        ``linearize(..., spin_rad_s=...)``). The hub stays free: with no ``hub_torque`` it keeps
        spinning (the straight pose is the spinning chain's relative equilibrium), and a
        ``hub_torque`` input changes its rate. Needs ``method="auto"`` (the default),
        ``"compiled"``, ``"gauss"`` or a solve_ivp method: the exponential integrator is
        refused (its step control takes its smallest steps on a spinning hub).
    **changes
        Options by name, applied to ``options`` (``simulate(model, 1.0, method="gauss")``).

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.5, tip_force=[0.0, 0.0, -1.0], damping_ratio=0.3)
    >>> round(float(run.tip_displacement_m[-1, 2]) * 1e3, 3)  # mm, settled
    -0.331
    >>> eq = pp.statics(model, tip_force_N=[0.0, 0.0, -1.0])
    >>> round(float(eq.tip_displacement_m[2]) * 1e3, 3)  # mm, the static equilibrium
    -0.331
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    check_model(model)
    if integrator is not None:
        changes["integrator"] = integrator
    o = _options(options, changes)
    integ, dt, output_dt = o.integrator, o.dt_s, o.output_dt_s
    hub = getattr(model, "hub", None) is not None
    bus = getattr(model, "bus", None) is not None
    n = int(model.pin_model.nv)
    # spring coordinates: a spatial chain has one per axis and node (n_springs)
    n_springs = int(getattr(model, "n_springs", model.n_joints))
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    q0 = vector("q0", q0, n)
    v0 = vector("v0", v0, n)
    spin = check_float("spin_rad_s", spin_rad_s, optional=True, unit="rad/s")
    if spin:
        if not hub:
            raise BeamInputError(f"spin_rad_s = {spin!r}: needs a hub to spin (a model built "
                                 "with hub=Hub(...))")
        if integ.method == "exponential":
            # its step control measures the correction against the panel's motion, and the
            # weak spring its linearisation puts on the free hub makes a correction that grows
            # with the hub's rate: from a steady spin (the panel straight) it takes its
            # smallest steps
            raise BeamInputError(f"spin_rad_s = {spin!r}: the exponential integrator cannot "
                                 "follow a spinning hub efficiently; use method='gauss' (or "
                                 "a solve_ivp method such as 'DOP853')")
        v0 = v0.copy()
        v0[0] += spin
    force, constant_force = force_function(tip_force)
    xi = damping_ratios(np.asarray(o.damping_ratio, dtype=float) if isinstance(
        o.damping_ratio, tuple) else o.damping_ratio, n_springs)
    if stiffness_schedule is not None and not isinstance(stiffness_schedule, StiffnessSchedule):
        raise BeamInputError("stiffness_schedule: must be a StiffnessSchedule")
    if stiffness_schedule is not None and bus:
        raise BeamInputError("stiffness_schedule: not with a free bus")
    if base_motion is not None:
        _check_base_motion(base_motion, hub or bus, integ, duration_s)
    if stiffness_schedule is not None and hub:
        raise BeamInputError("stiffness_schedule: not with a hub (the schedule holds the beam "
                             "joints' springs of a clamped chain)")
    plant = plant_signals(model, inputs, u, actuators, outputs, integ, loads)
    if stiffness_schedule is not None and stiffness_schedule.stiffness_Nm_per_rad.shape[1] != n:
        raise BeamInputError(f"stiffness_schedule: needs {n} joint stiffnesses per pose")
    # the options' dt_s, whether or not the integrator has a step (as always)
    check_grid(duration_s, dt, output_dt, o.max_steps)
    g = vector("gravity_m_s2", gravity_m_s2, 3)  # m/s^2, world; zeros: none
    system = assemble_system(model, q0, damping_ratios=xi, damping=o.damping,
                             schedule=stiffness_schedule, tip_force_N=force,
                             constant_force=constant_force, damping_pose=damping_pose,
                             inputs=plant[0], gravity_m_s2=g)
    if base_motion is not None:
        system = dataclasses.replace(system, inputs=BaseForce(base_motion, system.pin_model,
                                                              system.inputs))
    if isinstance(integ, Auto):  # the rule's pick for this scene (default_rule)
        integ = default_integrator(system, np.concatenate((q0, v0)), duration_s, integ,
                                   spinning=bool(spin))
        if isinstance(integ, Exponential):  # the step the options spell, as it always took
            integ = integ.replace(dt_s=o.dt_s, steps_per_period=o.steps_per_period,
                                  refresh_rad=o.refresh_rad)
    if integ.default_steps_per_period is not None and dt is None:
        spp = integ.steps_per_period or integ.default_steps_per_period
        dt = min(2.0 * math.pi / _lowest_frequency(system, q0, N_BASE if bus else int(hub))
                 / spp, duration_s)
    stepper = start(integ, system, 0.0, np.concatenate((q0, v0)), duration_s, dt_s=dt,
                    output_dt_s=output_dt, max_steps=o.max_steps)
    report, close = progress_bar(duration_s, progress)
    try:
        samples = integrate(stepper, output_dt, o.max_steps, report)
    finally:
        close()
    if bus:  # the member's tip relative to the bus, in the clamp frame
        member = model.member
        tip = tip_positions(member, member.new_data(), samples.q_rad[:, N_BASE:],
                            _planar_lengths(member))
    else:
        tip = tip_positions(model, system.data, samples.q_rad, system.lengths_m)
    t, Q, V = samples.t_s, samples.q_rad, samples.v_rad_s
    signals = recorded(model, system, plant[1], t, Q, V, tip, force, g, tuple(loads))
    for arr in (t, Q, V, tip, signals[2], signals[5]):
        arr.setflags(write=False)
    return Trajectory(t, Q, V, tip, int(samples.steps), integ.method,
                      time.perf_counter() - wall0, int(samples.rhs_evaluations),
                      int(samples.jacobian_updates), time.process_time() - cpu0, *signals,
                      integrator=integ)


def _planar_lengths(model) -> np.ndarray | None:
    """Return the planar chain's lengths (m) for the closed-form tip, or None if not planar."""
    try:
        return planar_lengths(model.pin_model, model.tip_frame_id)
    except BeamInputError:
        return None


def _check_base_motion(motion, free: bool, integ: Integrator, duration_s: float) -> None:
    if not isinstance(motion, BaseMotion):
        raise InputTypeError(f"base_motion = {motion!r:.60}: must be a "
                             "prbdm_pin.BaseMotion")
    if free:
        raise BeamInputError("base_motion: moves the clamp of a clamped model; this model "
                             "has a hub or a free bus")
    if not integ.takes_inputs:
        raise BeamInputError(f"base_motion: method {integ.method!r} takes a tip force only; "
                             "use 'auto' (default), 'exponential', 'trapezoidal' or a "
                             "solve_ivp method")
    motion.check_span(duration_s)


def _lowest_frequency(system, q0: np.ndarray, n_free: int) -> float:
    """Return the lowest natural frequency at ``q0``, rad/s.

    The lowest flexible one on a hub or a free bus (``n_free`` coordinates without a spring).
    """
    M = mass_matrix(system.pin_model, system.data, q0)
    if n_free > 1:
        return float(free_frequencies(M, system.springs(q0)[n_free:], n_free=n_free)[n_free])
    if n_free:
        return float(hub_frequencies(M, system.springs(q0)[1:])[1])
    w2 = generalized_eigh(np.diag(system.springs(q0)), M, "step size", vectors=False)
    return math.sqrt(max(w2[0], 1e-300))


def _options(options: SimulationOptions | None, changes: dict[str, Any]) -> SimulationOptions:
    if options is None:
        options = SimulationOptions()
    elif not isinstance(options, SimulationOptions):
        raise InputTypeError(f"options = {options!r:.80}: must be a SimulationOptions")
    return options.replace(**changes) if changes else options
