"""Trajectory gradients: dJ/dp of a scalar cost of a simulated run, by forward sensitivities.

J = integral over [0, T] of l(t, x, u, z) dt + phi(x(T), z(T)) (:mod:`.trajectory_cost`) of
the closed loop of :mod:`.sensitivity_field`, with respect to the joint springs, the joint
stations (the link lengths), the damping (beta, per-joint dampers), a state-feedback gain and
the start state.

The sensitivities S = dx/dp obey S' = (df/dx) S + df/dp beside the state, and the cost's
gradient g' = (dl/dx + dl/du du/dx + dl/dz dz/dx) S + dl/dp. All are stepped by one classic
fourth-order Runge-Kutta scheme at a fixed step, the state, the cost and the sensitivities in
one vector: an explicit Runge-Kutta scheme applied to the variational equations is the exact
derivative of the same scheme's discrete trajectory (the stages are differentiated stage by
stage), so the gradient is that of the J the run computes, to rounding (and to the stations'
central difference of the vector field), at any step. A fixed step keeps J a smooth function
of the design; an error-controlled pair would change its step sequence with p and make J
piecewise smooth, with a gradient that a central difference of J would not confirm. The step is
set from the eigenvalues lambda of the closed loop linearised at the start: the fastest
oscillation gets ``steps_per_period`` steps, h <= 2 pi / (max |Im lambda| ``steps_per_period``),
and every mode stays inside RK4's stability region, h <= 2 / max abs(lambda) (an overdamped mode
decays whatever its accuracy); RK4's error in J falls as h^4.

The chain is a clamped planar one (no hub or bus), the inputs those with a constant map
(``joint_torque[j]``, ``strain[i]``), the tip force a constant.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..model.checks import check_model
from ..model.inputs import StrainActuator
from ..options.checks import check_float
from ..options.validate import real_vector
from .inputs import InputForce, StateFeedback, input_force
from .sensitivity_field import Chain, Field, FieldDesign, station_variants
from .sensitivity_parameters import parameter_groups, parameter_names
from .sensitivity_run import rk4_run
from .system import vector
from .trajectory import Trajectory

__all__ = ["TrajectoryGradient", "trajectory_gradient"]

MAX_STEPS = 1_000_000


@dataclass(frozen=True, eq=False)
class TrajectoryGradient:
    """A trajectory cost J and its gradient with respect to named design parameters.

    Attributes
    ----------
    cost : float
        J, the cost's units times s (the running term's integral) plus its terminal term.
    gradient : ndarray, shape (P,)
        dJ/dp, J's units per each parameter's unit.
    parameter_names : tuple of str
        ``k[j]`` (springs), ``x[j]`` (joint stations, j = 1..n), ``beta``, ``c[j]``
        (dampers), ``G[input,state]`` (gain), ``q0[j]``, ``v0[j]`` (the start state), in
        column order.
    parameter_units : tuple of str
        Each parameter's unit (``N m/rad``, ``m``, ``s``, ``N m s/rad``, an input's unit per rad
        or per rad/s, ``rad``, ``rad/s``).
    trajectory : Trajectory
        The run, sampled at every step (``method`` "rk4").
    dt_s : float
        The fixed step, s.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> cost = pp.QuadraticCost(tip_weight_per_m2=1e6)  # the tip's squared height, per mm^2
    >>> step = dict(tip_force=[0.0, 0.0, -1.0], parameters=("springs",))  # N, from rest
    >>> g = pp.trajectory_gradient(model, 0.1, cost, **step)
    >>> g.parameter_names, g.parameter_units
    (('k[0]', 'k[1]'), ('N m/rad', 'N m/rad'))
    >>> round(g.of("k[0]") * 1e6, 3)  # per N m/rad, x 1e6: a stiffer root, less tip motion
    -13.736
    >>> J = [pp.trajectory_gradient(model.with_stiffness([2500.0 + h, 1200.0]), 0.1, cost,
    ...                             tip_force=[0.0, 0.0, -1.0], parameters=(),
    ...                             dt_s=g.dt_s).cost for h in (1.0, -1.0)]
    >>> round((J[0] - J[1]) / 2.0 * 1e6, 3)  # a central difference over two whole runs
    -13.736
    """

    cost: float
    gradient: np.ndarray
    parameter_names: tuple[str, ...]
    parameter_units: tuple[str, ...]
    trajectory: Trajectory
    dt_s: float

    def of(self, name: str) -> float:
        """Return dJ/d(``name``) (J's units per the parameter's unit)."""
        if name not in self.parameter_names:
            raise BeamInputError(f"parameter {name!r}: not among the gradient's "
                                 f"{', '.join(self.parameter_names) or 'none'}")
        return float(self.gradient[self.parameter_names.index(name)])

    def as_dict(self) -> dict[str, float]:
        """Return {parameter name: dJ/dp}."""
        return {n: float(g) for n, g in zip(self.parameter_names, self.gradient, strict=True)}


def _check_cost(cost) -> None:
    for name in ("running", "running_partials"):
        if not callable(getattr(cost, name, None)):
            raise InputTypeError(f"cost = {cost!r:.80}: must define {name}(t, x, u, z) (a "
                                 "prbdm_pin.TrajectoryCost)")


def _check_chain(model) -> None:
    check_model(model)
    if model.hub is not None or getattr(model, "bus", None) is not None \
            or model.axes.spatial:
        raise BeamInputError("model: trajectory_gradient takes a clamped planar chain (no hub, "
                             "no bus, axes='y')")


def trajectory_gradient(model, duration_s: float, cost, *, q0=None, v0=None, tip_force=None,
                        inputs: Sequence[str] = (), feedback: StateFeedback | None = None,
                        actuators: Sequence[StrainActuator] = (), beta_s: float = 0.0,
                        joint_damping_Nms_per_rad=None,
                        parameters: Sequence[str] = ("springs",), dt_s: float | None = None,
                        steps_per_period: float = 40.0) -> TrajectoryGradient:
    """Return a trajectory cost and its gradient by forward sensitivities (fixed-step RK4).

    Parameters
    ----------
    model : PrbdmModel
        A clamped planar chain (``build_model(beam, lengths, springs)``).
    duration_s : float
        T, s.
    cost : TrajectoryCost
        l and phi with their partial derivatives (:class:`~prbdm_pin.QuadraticCost`, or a
        user's object with the same methods); a NaN or infinity from it is refused.
    q0, v0 : array_like (n,), optional
        Initial joint angles (rad) and rates (rad/s); default zero.
    tip_force : array_like (3,), optional
        Constant world tip force, N (a step load from t = 0).
    inputs : sequence of str
        Inputs with a constant map (``joint_torque[j]``, ``strain[i]``).
    feedback : StateFeedback, optional
        u = u_ref - G (x - x_ref) on ``inputs`` (G: m x 2 n); default u = 0.
    actuators : sequence of StrainActuator
        The patches ``strain[i]`` names.
    beta_s : float
        Stiffness-proportional damping, C = beta K + diag(c), s (>= 0).
    joint_damping_Nms_per_rad : array_like (n,), optional
        Per-joint dampers c, N m s/rad (>= 0); default zero.
    parameters : sequence of str
        The groups to differentiate by, among ``springs``, ``stations`` (the joint stations
        x_j = L_0 + ... + L_(j-1), m: the lengths with the beam's length fixed; needs the
        model's beam), ``beta``, ``dampers``, ``gain``, ``initial`` (q0 and v0: a start
        that depends on the design chains through them); () gives J alone.
    dt_s : float, optional
        The fixed step, s; default from ``steps_per_period``.
    steps_per_period : float
        Steps per period of the fastest oscillation of the closed loop linearised at the
        start (>= 8); the step also stays within RK4's stability, 2 / max abs(lambda).

    Returns
    -------
    TrajectoryGradient

    Raises
    ------
    BeamInputError
        An unknown parameter group, a gain of the wrong shape, a cost returning NaN or
        infinity, a model other than a clamped planar chain, more than 1e6 steps.
    InputTypeError
        ``model``, ``cost``, ``feedback`` or ``parameters`` of the wrong type.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> law = pp.StateFeedback(np.array([[0.0, 0.0, 2.0, 0.0]]))  # N m s/rad on joint 0
    >>> g = pp.trajectory_gradient(model, 0.1, pp.QuadraticCost(tip_weight_per_m2=1e4),
    ...                            q0=[0.01, 0.0], inputs=("joint_torque[0]",), feedback=law,
    ...                            parameters=("gain",))
    >>> g.parameter_names[2]
    'G[joint_torque[0],v[0]]'
    >>> bool(g.of("G[joint_torque[0],v[0]]") < 0.0)  # more rate feedback, less tip motion
    True
    """
    cpu0, wall0 = time.process_time(), time.perf_counter()
    _check_chain(model)
    _check_cost(cost)
    groups = parameter_groups(parameters)
    n = model.n_joints
    T = check_float("duration_s", duration_s, low=0.0, low_open=True, unit="s")
    x0 = np.concatenate((vector("q0", q0, n), vector("v0", v0, n)))
    force = vector("tip_force", tip_force, 3)
    beta = check_float("beta_s", beta_s, low=0.0, unit="s")
    c = np.zeros(n) if joint_damping_Nms_per_rad is None else real_vector(
        "joint_damping_Nms_per_rad", joint_damping_Nms_per_rad, "N m s/rad", n)
    if np.any(c < 0.0):
        raise BeamInputError(f"joint_damping_Nms_per_rad = {c.tolist()}: must be >= 0")
    if feedback is not None and not isinstance(feedback, StateFeedback):
        raise InputTypeError(f"feedback = {feedback!r:.80}: must be a prbdm_pin.StateFeedback")
    if "gain" in groups and feedback is None:
        raise BeamInputError("parameters: 'gain' needs a feedback (a StateFeedback on inputs)")
    if "stations" in groups and model.beam is None:
        raise BeamInputError("parameters: 'stations' needs the model's beam (build_model); "
                             "this model was read from a file")
    actuators = tuple(actuators)
    plant = _plant(model, inputs, feedback, actuators)
    m = len(plant.names)
    gain = plant.gain if plant.gain is not None else np.zeros((m, 2 * n))
    x_ref = np.zeros(2 * n) if feedback is None or feedback.x_ref is None else np.asarray(
        feedback.x_ref, dtype=float)
    design = FieldDesign(np.asarray(model.stiffness_Nm_per_rad, dtype=float), beta, c, gain,
                         x_ref, plant.signal, groups, n, m)

    def input_map(chain_model):
        if not m:
            return plant.b0
        return input_force(chain_model, plant.names, None, actuators, None).b0

    variants = station_variants(model, design.k, input_map) if "stations" in groups else []
    field = Field(Chain(model, plant.b0), variants, design, force)
    dt = _step(field, x0, T, dt_s, steps_per_period)
    steps = max(1, math.ceil(T / dt - 1e-9))
    if steps > MAX_STEPS:
        raise BeamInputError(f"dt_s = {dt:.3g} s: {steps} steps over {T:g} s, more than "
                             f"{MAX_STEPS}")
    run = rk4_run(field, cost, x0, T, steps)
    names, units = parameter_names(groups, n, plant.names, plant.units)
    tip = run.tip
    for a in (run.t, run.x, run.u, tip, run.gradient):
        a.setflags(write=False)
    traj = Trajectory(run.t, run.x[:, :n], run.x[:, n:], tip, steps, "rk4",
                      time.perf_counter() - wall0, field.evaluations, 0,
                      time.process_time() - cpu0, plant.names, plant.units, run.u)
    return TrajectoryGradient(run.cost, run.gradient, names, units, traj, T / steps)


def _plant(model, inputs, feedback, actuators) -> InputForce:
    """Return the inputs' map and feedback law (no inputs: a map of no columns)."""
    if isinstance(inputs, str) or not isinstance(inputs, Sequence):
        raise InputTypeError(f"inputs = {inputs!r:.80}: must be a sequence of input names")
    if not inputs:
        if feedback is not None:
            raise BeamInputError("feedback: given without inputs to drive")
        n = model.n_joints
        return InputForce((), (), np.zeros((n, 0)), (), lambda t, q, v: np.zeros(0), None,
                          False, False, None)
    plant = input_force(model, tuple(inputs), feedback, actuators, None)
    if plant.tip_rows or plant.pose_cols:
        raise BeamInputError(f"inputs = {list(inputs)}: trajectory_gradient takes inputs with a "
                             "constant map only (joint_torque[j], strain[i])")
    return plant


def _step(field: Field, x0: np.ndarray, T: float, dt_s, steps_per_period) -> float:
    """Return the fixed step, s: ``dt_s`` or the eigenvalues' rule (the module's docstring)."""
    if dt_s is not None:
        return min(check_float("dt_s", dt_s, low=0.0, low_open=True, unit="s"), T)
    spp = check_float("steps_per_period", steps_per_period, low=8.0, unit="steps")
    n = field.d.n
    A = field.state_jacobian(0.0, x0)
    full = np.zeros((2 * n, 2 * n))
    full[:n, n:] = np.eye(n)
    full[n:] = A
    lam = np.linalg.eigvals(full)
    # accuracy on the fastest oscillation, stability on every mode (RK4's region reaches 2.6
    # to 2.8 from the origin into the left half-plane; 2 keeps a margin)
    h = T
    w = float(np.max(np.abs(lam.imag)))
    if w > 0.0:
        h = min(h, 2.0 * math.pi / (w * spp))
    r = float(np.max(np.abs(lam)))
    if r > 0.0:
        h = min(h, 2.0 / r)
    return h
