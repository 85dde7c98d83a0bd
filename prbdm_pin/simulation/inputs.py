"""Plant inputs in a time response: what drives them and the generalized force they make.

They are driven by a constant, a function of time, a controller of the state or a
state-feedback gain.

The inputs are named as in :func:`prbdm_pin.linearize` (``tip_force_z``, ``tip_force_x``,
``tip_force_y``, ``tip_moment_x``, ``tip_moment_y``, ``tip_moment_z``, ``corner_force_z_left``,
``corner_force_z_right``, ``joint_torque[j]``, ``strain[i]``, ``hub_torque``, and the loads of
:mod:`prbdm_pin.model.loads`: ``tip_moment_follower_x`` ..., ``distributed_force_z`` ...,
``base_accel_z`` ...). Torques, patch
moments and the hub torque act through a constant map B_0
(:func:`prbdm_pin.model.inputs.input_map`); tip forces act through the tip Jacobian,
J(q)^T F(u), as the ``tip_force`` argument of ``simulate`` does; the tip moments (dead, about
world x, y, z) and the corner forces (dead, world z) through the pose's own columns of that
map, B_p(q) u_p: the rows of the tip's angular Jacobian and the corners' z rows; so do the
follower moments, the distributed forces and the base accelerations.
Their load stiffness d(B_p(q) u_p)/dq is taken by forward differences of B_p (it only steers
the exponential integrator's linearisation, not the accuracy of the response).

The signal ``u`` is one of

- an array (m,): constant inputs, applied from t = 0;
- a callable ``u(t)`` -> (m,): open-loop inputs of time (s);
- :class:`Controller` ``(function)``: u = function(t, q, v), any feedback law of the state;
- :class:`StateFeedback` ``(gain, ...)``: u = u_ref(t) - K (x - x_ref), x = (q, v).

A state-feedback gain is linear in the state: the exponential integrator takes its Jacobian
into its linearisation exactly, so the closed loop's linear modes, however fast, are propagated
exactly. A general controller's gain enters the linearisation by forward differences (2 nv more
controller calls per step), which does the same for its linear part.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..model.inputs import (
    POSE_INPUTS,
    StrainActuator,
    input_map,
    input_unit,
    parse_inputs,
)

__all__ = ["Controller", "StateFeedback", "InputForce", "input_force"]

_TIP = {"tip_force_x": 0, "tip_force_y": 1, "tip_force_z": 2}


@dataclass(frozen=True)
class Controller:
    """A feedback law u = function(t, q, v).

    It maps time (s), joint angles (rad, the hub angle first on a hub model) and rates (rad/s)
    to the inputs (m,) in their units.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> damper = pp.Controller(lambda t, q, v: -5.0 * v[:1])  # N m on joint 0
    >>> run = pp.simulate(model, 0.2, q0=[0.01, 0.0], inputs=("joint_torque[0]",), u=damper,
    ...                   damping_ratio=0.0)
    >>> bool(abs(run.q_rad[-1, 0]) < 0.5 * 0.01)  # the rate feedback damps the swing
    True
    """

    function: Callable[[float, np.ndarray, np.ndarray], np.ndarray]

    def __post_init__(self) -> None:
        """Check that ``function`` is callable (InputTypeError otherwise)."""
        if not callable(self.function):
            raise InputTypeError(f"Controller function = {self.function!r}: must be callable "
                                 "u(t, q, v)")


@dataclass(frozen=True, eq=False)
class StateFeedback:
    """u = u_ref(t) - K (x - x_ref) with x = (q, v) the state (rad, rad/s).

    Attributes
    ----------
    gain : ndarray (m, 2 nv)
        K, input units per rad and per rad/s (the order of ``LinearModel.state_names``; the
        gain from ``control.lqr`` on ``linearize(...).to_control()`` fits as it is).
    x_ref : ndarray (2 nv,), optional
        Reference state (default zero, e.g. the hub angle to slew to).
    u_ref : ndarray (m,) or callable t -> (m,), optional
        Feed-forward inputs (default zero).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> law = pp.StateFeedback(np.array([[0.0, 0.0, 5.0, 0.0]]))  # N m s/rad on joint 0
    >>> same = pp.Controller(lambda t, q, v: -5.0 * v[:1])
    >>> runs = [pp.simulate(model, 0.2, q0=[0.01, 0.0], inputs=("joint_torque[0]",), u=u,
    ...                     damping_ratio=0.0) for u in (law, same)]
    >>> bool(np.allclose(runs[0].q_rad[-1], runs[1].q_rad[-1], atol=1e-6))
    True
    """

    gain: np.ndarray
    x_ref: np.ndarray | None = None
    u_ref: np.ndarray | Callable[[float], np.ndarray] | None = field(default=None)

    def __post_init__(self) -> None:
        """Check that the gain is a finite real matrix and the references finite real vectors.

        Their sizes are checked against the model where the feedback is used.
        """
        from ..options.validate import real_vector

        g = np.asarray(self.gain)
        if g.dtype.kind not in "iuf" or g.ndim != 2:
            raise InputTypeError(f"StateFeedback gain = {self.gain!r:.80}: must be a matrix "
                                 "(inputs x states) of real numbers")
        bad = np.argwhere(~np.isfinite(g))
        if bad.size:
            i, j = (int(v) for v in bad[0])
            raise BeamInputError(f"StateFeedback gain[{i}, {j}] = {g[i, j]}: must be finite")
        if self.x_ref is not None:
            real_vector("StateFeedback x_ref", self.x_ref, "rad, rad/s")
        if self.u_ref is not None and not callable(self.u_ref):
            real_vector("StateFeedback u_ref", self.u_ref, "input units")


def _finite(name: str, value, shape: tuple[int, ...]) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        a = np.full(1, np.nan)
    if a.shape != shape and a.size == int(np.prod(shape)):
        a = a.reshape(shape)
    if a.shape != shape or not np.all(np.isfinite(a)):
        dims = " x ".join(str(s) for s in shape)
        raise BeamInputError(f"{name} = {value!r:.80}: must be {dims} finite numbers")
    return a


@dataclass(frozen=True, eq=False)
class InputForce:
    """The inputs' generalized force in the equations of motion, with its derivatives.

    ``values(t, q, v)`` gives u (m,); ``torque(t, q, v)`` the generalized force (nv,), N m;
    ``jacobians(t, q, v)`` its derivatives with respect to q and v (nv, nv) where they are known
    exactly (None otherwise); ``time_rate(t, q, v)`` its rate at a fixed state (None when the
    signal does not depend on time).
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    b0: np.ndarray  # (nv, m): torques, patch moments, hub torque per unit input
    tip_rows: tuple[tuple[int, int], ...]  # (input column, world axis) of the tip forces
    signal: Callable[[float, np.ndarray, np.ndarray], np.ndarray]
    gain: np.ndarray | None  # K of a state feedback
    time_varying: bool
    feedback: bool  # a controller of the state (its gain by differences)
    tip_terms: Callable | None  # (q, F) -> (J^T F, d(J^T F)/dq)
    pose_cols: tuple[int, ...] = ()  # input columns of the tip moment and the corner forces
    pose_map: Callable | None = None  # q -> B_p(q) (nv, len(pose_cols))

    def values(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return the inputs u (m,) at time t (s) and state (q rad, v rad/s)."""
        return self.signal(t, q, v)

    def _force(self, u: np.ndarray) -> np.ndarray:
        F = np.zeros(3)
        for col, axis in self.tip_rows:
            F[axis] = u[col]
        return F

    def torque(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Generalized force of the inputs (nv,), N m."""
        u = self.values(t, q, v)
        tau = self.b0 @ u
        if self.tip_rows:
            tau = tau + self.tip_terms(q, self._force(u))[0]
        if self.pose_cols:
            tau = tau + self.pose_map(q) @ u[list(self.pose_cols)]
        return tau

    def _pose_stiffness(self, q: np.ndarray, u: np.ndarray) -> np.ndarray:
        """d(B_p(q) u_p)/dq (nv, nv) by forward differences, N m/rad."""
        up = u[list(self.pose_cols)]
        base = self.pose_map(q) @ up
        eps = 1e-7 * max(1.0, float(np.abs(q).max()))  # ~sqrt(EPS): truncation ~ rounding
        out = np.empty((q.size, q.size))
        for j in range(q.size):
            qj = q.copy()
            qj[j] += eps
            out[:, j] = (self.pose_map(qj) @ up - base) / eps
        return out

    def jacobians(self, t: float, q: np.ndarray, v: np.ndarray
                  ) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Return d tau / dq and d tau / dv (nv, nv); None for what is not known in closed form."""
        nv = q.size
        # the load stiffness of the tip forces (and moment, corner forces) at their present value
        u = self.values(t, q, v)
        dq = self.tip_terms(q, self._force(u))[1] if self.tip_rows else None
        if self.pose_cols and np.any(u[list(self.pose_cols)]):
            dp = self._pose_stiffness(q, u)
            dq = dp if dq is None else dq + dp
        gain = self.gain if self.gain is not None else (
            self._difference_gain(t, q, v) if self.feedback else None)
        if gain is None:
            return dq, None
        # tau = B(q) u with du/dx = -K: B(q) (-K), B(q) = b0 + J^T columns of the tip forces
        B = self.b0.copy()
        if self.tip_rows:
            for col, axis in self.tip_rows:
                e = np.zeros(3)
                e[axis] = 1.0
                B[:, col] += self.tip_terms(q, e)[0]
        if self.pose_cols:
            B[:, list(self.pose_cols)] += self.pose_map(q)
        BK = -B @ gain
        dq = BK[:, :nv] if dq is None else dq + BK[:, :nv]
        return dq, BK[:, nv:]

    def _difference_gain(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """-du/dx of a controller at (t, q, v) by forward differences, (m, 2 nv)."""
        x = np.concatenate((q, v))
        nv = q.size
        u0 = self.values(t, q, v)
        K = np.empty((u0.size, x.size))
        for i in range(x.size):
            xi = x.copy()
            step = 1e-7 * max(1.0, abs(x[i]))
            xi[i] += step
            K[:, i] = (u0 - self.values(t, xi[:nv], xi[nv:])) / step
        return K

    def time_rate(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray | None:
        """Return d tau / dt at a fixed state (nv,), N m/s, by a short forward difference.

        None when the signal does not depend on time.
        """
        if not self.time_varying:
            return None
        delta = 1e-6 * max(1e-3, abs(t)) if t else 1e-9
        return (self.torque(t + delta, q, v) - self.torque(t, q, v)) / delta


def _signal(u, m: int, nv: int):
    """(signal(t, q, v), gain or None, depends on time)."""
    if u is None:
        zero = np.zeros(m)
        return (lambda t, q, v: zero), None, False
    if isinstance(u, Controller):
        f = u.function

        def controller(t, q, v):
            val = np.asarray(f(t, q, v), dtype=float).reshape(-1)
            if val.size != m or not np.all(np.isfinite(val)):
                raise BeamInputError(f"controller(t = {t:.6g}) = {val!r:.80}: must return {m} "
                                     "finite inputs")
            return val
        return controller, None, True
    if isinstance(u, StateFeedback):
        K = _finite("StateFeedback gain", u.gain, (m, 2 * nv))
        x_ref = np.zeros(2 * nv) if u.x_ref is None else _finite("StateFeedback x_ref",
                                                                 u.x_ref, (2 * nv,))
        ref_fn, _, varying = _signal(u.u_ref, m, nv) if u.u_ref is not None else (
            lambda t, q, v: np.zeros(m), None, False)
        if isinstance(u.u_ref, (Controller, StateFeedback)):
            raise BeamInputError("StateFeedback u_ref: must be inputs or a function of time")

        def feedback(t, q, v):
            return ref_fn(t, q, v) - K @ (np.concatenate((q, v)) - x_ref)
        return feedback, K, varying
    if callable(u):
        def of_time(t, q, v):
            val = np.asarray(u(t), dtype=float).reshape(-1)
            if val.size != m or not np.all(np.isfinite(val)):
                raise BeamInputError(f"u({t:.6g}) = {val!r:.80}: must return {m} finite inputs")
            return val
        return of_time, None, True
    const = _finite("u", u, (m,))
    return (lambda t, q, v: const), None, False


def input_force(model, names, u, actuators: tuple[StrainActuator, ...], tip_terms,
                loads: tuple = ()) -> InputForce:
    """Return the :class:`InputForce` of the inputs ``names`` driven by ``u`` on ``model``.

    The tip forces' generalized force and load stiffness come from ``tip_terms(q, F)``;
    ``distributed_force_z[i]`` ... act over ``loads[i]`` (DistributedLoad).
    """
    hub = model.hub is not None
    n_springs = int(getattr(model, "n_springs", model.n_joints))  # spatial: per axis and node
    parsed = parse_inputs(names, n_springs, len(actuators), hub, len(loads))
    names = tuple(n for n, _, _ in parsed)
    nv = model.pin_model.nv
    m = len(names)
    tip_rows = tuple((c, _TIP[b]) for c, (_, b, _) in enumerate(parsed) if b in _TIP)
    pose_cols = tuple(c for c, (_, b, _) in enumerate(parsed) if b in POSE_INPUTS)
    pose_names = tuple(parsed[c][0] for c in pose_cols)
    const_cols = [c for c, (_, b, _) in enumerate(parsed)
                  if b not in _TIP and b not in POSE_INPUTS]
    b0 = np.zeros((nv, m))
    if const_cols:
        b0[:, const_cols] = input_map(model, np.zeros(model.pin_model.nq),
                                      [parsed[c][0] for c in const_cols], actuators)
    pose_map = (lambda q: input_map(model, q, pose_names, loads=loads)) if pose_cols else None
    signal, gain, varying = _signal(u, m, nv)
    signal(0.0, np.zeros(nv), np.zeros(nv))  # a bad signal is refused before any step
    return InputForce(names, tuple(input_unit(s) for s in names), b0, tip_rows, signal, gain,
                      varying, isinstance(u, Controller), tip_terms, pose_cols, pose_map)
