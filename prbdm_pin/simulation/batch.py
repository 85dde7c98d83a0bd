"""``simulate_batch``: many designs (or controller gains) over one duration, load and grid.

Planar clamped chains are integrated together (:mod:`.batch_rhs`, :mod:`.batch_rk`): one
Dormand-Prince 8(5,3) (``method="DOP853"``, the default) or 5(4) (``"RK45"``) run whole in
compiled code (:mod:`.batch_rk_kernel`) over blocks of designs side by side, each stage one
call of a compiled kernel on the block (:mod:`prbdm_pin.chain.planar_batch_kernel`: M(q), the
Coriolis/centrifugal forces and J^T F in closed form, a Cholesky solve, the designs as SIMD
lanes); a block's step is set by its design with the largest error (each design's error
measured against its own tolerances), and the designs are sorted by their highest natural
frequency into blocks so that designs of like stiffness share a step. Everything else,
spatial chains, hubs, free buses, a weight set on a ``pin_model``, another integrator
(``"exponential"`` ...), a ``Controller``, per-design functions of time, the pose
inputs (tip moments, corner and distributed forces, base accelerations), is run as a loop of
:func:`prbdm_pin.simulate` calls over the designs, with the same options: the same result,
without the batch's speed.
"""
from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..model.designs import check_designs, design_rows
from ..model.inputs import POSE_INPUTS, StrainActuator, parse_inputs
from ..options.integrators import ScipyIVP
from ..options.simulation import SimulationOptions
from .batch_rhs import BatchPlant, vectorised_plant
from .batch_rk import METHODS, integrate_batch
from .driver import simulate
from .inputs import Controller, StateFeedback
from .loop import check_grid
from .steps import output_times
from .trajectory_batch import TrajectoryBatch

__all__ = ["simulate_batch"]

_TOL_RANGE = (1e-14, 1e-1)  # outside it: below rounding, or no accuracy worth the name


def simulate_batch(
    models,
    duration_s: float,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    tip_force: np.ndarray | None = None,
    options: SimulationOptions | None = None,
    *,
    inputs: Sequence[str] = (),
    u: Any = None,
    actuators: Sequence[StrainActuator] = (),
    **changes: Any,
) -> TrajectoryBatch:
    """Simulate B designs over the same duration, load and output grid.

    Parameters
    ----------
    models : PrbdmModel or sequence of PrbdmModel
        The designs: the same joint count and support (clamped, hub or free bus; planar or
        the same spatial axes). One model with a sequence ``u`` of B feedback laws runs that
        model under each.
    duration_s : float
        Simulated time, s.
    q0, v0 : array_like, shape (nv,) or (B, nv), optional
        Initial joint angles (rad) and rates (rad/s), shared or one row per design; default 0.
    tip_force : array_like (3,) or (B, 3), or callable t -> (3,), optional
        World-frame tip force, N: a step load from t = 0 (shared or one per design), or a
        shared function of time (s).
    options : SimulationOptions, optional
        As :func:`prbdm_pin.simulate` takes them; default ``method="DOP853"`` (the vectorised
        integrator) with the options' other defaults (``rtol`` 1e-9, modal damping 0.02).
    inputs : sequence of str
        Plant inputs by name, as :func:`prbdm_pin.simulate` takes them.
    u : input signal, or sequence of B of them, optional
        What drives the inputs: one for every design (an array (m,), a function of time, a
        :class:`~prbdm_pin.StateFeedback`, a :class:`~prbdm_pin.Controller`) or one per
        design (e.g. B ``StateFeedback`` gains, u = -G_b x).
    actuators : sequence of StrainActuator
        The strain actuators ``strain[i]`` refers to.
    **changes
        Options by name (``rtol=1e-6``, ``output_dt_s=1e-3``, ``damping_ratio=0.0``, ...).

    Returns
    -------
    TrajectoryBatch
        The vectorised run samples every ``output_dt_s``, or with none every accepted step
        (then all designs share one step); the loop needs ``output_dt_s`` (each design steps
        on its own).

    Raises
    ------
    BeamInputError
        An empty batch, designs of mixed joint counts or supports (naming ``models[i]``),
        initial states, forces or gains of the wrong shape, a tolerance outside (1e-14, 1e-1).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> gains = [pp.StateFeedback(np.array([[0.0, 0.0, g, 0.0]])) for g in (0.0, 5.0)]
    >>> runs = pp.simulate_batch(model, 0.2, q0=[0.01, 0.0], inputs=("joint_torque[0]",),
    ...                          u=gains, damping_ratio=0.0, rtol=1e-6, output_dt_s=0.1)
    >>> runs.vectorised, runs.q_rad.shape
    (True, (2, 3, 2))
    >>> one = pp.simulate(model, 0.2, q0=[0.01, 0.0], inputs=("joint_torque[0]",), u=gains[1],
    ...                   damping_ratio=0.0, method="DOP853", rtol=1e-6, output_dt_s=0.1)
    >>> bool(np.allclose(runs.q_rad[1], one.q_rad, atol=1e-7))
    True
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    signals = _signals(u)
    models = check_designs(models, None if signals is None else len(signals))
    B = len(models)
    signals = [u] * B if signals is None else signals
    o = _options(options, changes)
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not math.isfinite(duration_s) or duration_s <= 0.0:
        raise BeamInputError(f"duration = {duration_s!r} s: must be a finite number > 0")
    duration_s = float(duration_s)
    check_grid(duration_s, None, o.output_dt_s, o.max_steps)
    nv = int(models[0].pin_model.nv)
    Q0, V0 = design_rows("q0", q0, B, nv), design_rows("v0", v0, B, nv)
    force = tip_force if callable(tip_force) else (
        None if tip_force is None else design_rows("tip_force", tip_force, B, 3))
    acts = tuple(actuators)
    m0 = models[0]
    if m0.bus is None and (isinstance(inputs, (str, bytes)) or inputs):
        # refused here, as simulate refuses them (a bare name too), before any run
        parse_inputs(inputs, m0.n_springs, len(acts), m0.hub is not None, 0)
    plant = None
    if _vectorisable(models, o, inputs, signals, acts):
        plant = vectorised_plant(models, Q0, o, tuple(inputs), signals, acts, force)
    if plant is None:
        return _loop(models, duration_s, Q0, V0, tip_force, o, inputs, signals, acts,
                     wall0, cpu0)
    return _run(plant, duration_s, Q0, V0, o, wall0, cpu0)


def _run(plant: BatchPlant, duration_s: float, Q0: np.ndarray, V0: np.ndarray,
         o: SimulationOptions, wall0: float, cpu0: float) -> TrajectoryBatch:
    integ = o.integrator
    B, n = Q0.shape
    rtol = float(integ.rtol)
    # simulate's default: rtol times the largest initial angle, at least 1e-6 rad, per design
    atol = (np.full((B, 1), float(integ.atol)) if integ.atol is not None else
            rtol * np.maximum(np.max(np.abs(Q0), axis=1, keepdims=True), 1e-6))
    t_out = None if o.output_dt_s is None else output_times(duration_s, o.output_dt_s)
    s = integrate_batch(plant, np.hstack((Q0, V0)), duration_s, rtol, atol, t_out,
                        o.max_steps, integ.method)
    Q, V = s.y[:, :, :n], s.y[:, :, n:]
    tip = s.tip_m
    for arr in (s.t_s, Q, V, tip):
        arr.setflags(write=False)
    ones = np.ones(B, dtype=int)
    return TrajectoryBatch(s.t_s, Q, V, tip, s.steps * ones, s.rhs_evaluations * ones,
                           s.rejected_steps * ones, integ.method, True,
                           time.process_time() - cpu0, time.perf_counter() - wall0, integ)


def _loop(models, duration_s, Q0, V0, tip_force, o, inputs, signals, acts, wall0, cpu0
          ) -> TrajectoryBatch:
    """Run the designs one by one through ``simulate`` (what cannot be vectorised)."""
    if o.output_dt_s is None:
        raise BeamInputError("output_dt_s: these designs are simulated one by one (each on "
                             "its own steps); give output_dt_s, the shared sample interval")
    runs = []
    for b, model in enumerate(models):
        f = tip_force if tip_force is None or callable(tip_force) else \
            design_rows("tip_force", tip_force, len(models), 3)[b]
        runs.append(simulate(model, duration_s, Q0[b], V0[b], f, o, inputs=tuple(inputs),
                             u=signals[b], actuators=acts))
    stack = [np.stack([getattr(r, a) for r in runs]) for a in ("q_rad", "v_rad_s",
                                                               "tip_position_m")]
    for arr in stack:
        arr.setflags(write=False)
    counts = [np.array([getattr(r, a) for r in runs], dtype=int) for a in ("steps",
                                                                          "rhs_evaluations")]
    # the integrator the runs used (the default "auto" picks per design: kept when they differ)
    used = {r.integrator for r in runs}
    integ = runs[0].integrator if len(used) == 1 else o.integrator
    return TrajectoryBatch(runs[0].t_s, *stack, *counts, np.zeros(len(runs), dtype=int),
                           integ.method, False, time.process_time() - cpu0,
                           time.perf_counter() - wall0, integ)


def _signals(u) -> list | None:
    """Return the per-design signals when ``u`` is a sequence of them, else None."""
    if isinstance(u, (list, tuple)) and u and all(
            isinstance(x, (StateFeedback, Controller)) or callable(x) or np.ndim(x) == 1
            for x in u) and not all(np.isscalar(x) for x in u):
        return list(u)
    return None


def _options(options, changes: dict) -> SimulationOptions:
    if options is None:
        options = SimulationOptions(method=changes.pop("method", "DOP853"))
    elif not isinstance(options, SimulationOptions):
        raise InputTypeError(f"options = {options!r:.80}: must be a SimulationOptions")
    o = options.replace(**changes) if changes else options
    integ = o.integrator
    for name in ("rtol", "atol"):
        tol = getattr(integ, name, None)
        if tol is not None and not _TOL_RANGE[0] < tol < _TOL_RANGE[1]:
            raise BeamInputError(f"{name} = {tol!r}: must be in ({_TOL_RANGE[0]:g}, "
                                 f"{_TOL_RANGE[1]:g})")
    return o


def _vectorisable(models, o: SimulationOptions, inputs, signals, acts: tuple) -> bool:
    """Whether the batch runs vectorised (see the module's docstring for what does not)."""
    m0 = models[0]
    if not isinstance(o.integrator, ScipyIVP) or o.integrator.method not in METHODS:
        return False
    if m0.hub is not None or m0.bus is not None or m0.axes.spatial:
        return False
    if any(np.any(m.pin_model.gravity.linear) for m in models):
        return False
    if inputs and any(b in POSE_INPUTS for _, b, _ in parse_inputs(
            inputs, m0.n_springs, len(acts), False, 0)):
        return False
    shared_time = [s for s in signals if callable(s) and not isinstance(
        s, (Controller, StateFeedback))]
    if any(isinstance(s, Controller) for s in signals):
        return False
    if shared_time and (len(shared_time) != len(signals) or any(
            s is not shared_time[0] for s in shared_time)):
        return False
    return not any(isinstance(s, StateFeedback) and callable(s.u_ref) for s in signals)
