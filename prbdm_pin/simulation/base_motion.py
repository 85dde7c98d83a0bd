"""Prescribed base motion: the clamp moved by a robot flange (``simulate(..., base_motion=)``).

The clamped chain is put on the six-coordinate kinematic base of
:mod:`prbdm_pin.model.supports` (prismatic x, y, z, then revolute yaw about z, pitch about y,
roll about x: orientation R = Rz(yaw) Ry(pitch) Rx(roll)), whose coordinates q_b(t), rates and
accelerations are imposed. The member's coordinates q_f (relative to the base) follow

    M_ff(q_f) a_f = tau_f - RNEA(q, v, [a_b, 0])_f,   q = [q_b(t), q_f], v = [v_b(t), v_f],

with tau_f the springs, damping and loads. The package's integrators step the clamped chain,
whose own RNEA at rest base is RNEA_c(q_f, v_f, 0) = M_ff a_f + h_c: so the base motion enters as
one more generalised force on it,

    tau_base = RNEA_c(q_f, v_f, 0) - RNEA(q, v, [a_b, 0])_f,

exact (M_ff of the member is the same on a fixed and on a moving base), with its derivatives in
q_f and v_f from Pinocchio's RNEA derivatives of the two models (the exponential integrator's
Jacobian). Gravity, when given, is in both models and in the world frame, so it acts on the
moving member correctly and cancels from the difference.

The member's coordinates, tip and outputs (``tip_z``, ...) are relative to the base: in the base
frame. :func:`world_tip_positions` gives the tip in the world frame.

Samples (``BaseMotion.from_samples``, ``prbdm simulate --base-motion FILE.csv``) are
interpolated by a cubic spline (scipy ``CubicSpline``, not-a-knot ends) per coordinate; its
first and second derivatives are the base's rates and accelerations, so the acceleration is
continuous and piecewise linear between samples.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from scipy.interpolate import CubicSpline

from ..errors import BeamInputError, InputTypeError
from ..model.pin_chain import TIP_FRAME
from ..model.supports import N_BASE, base_chain

__all__ = ["BaseMotion", "BaseForce", "world_tip_positions"]

# user order (x, y, z, roll, pitch, yaw) -> base coordinates (x, y, z, yaw, pitch, roll)
_TO_BASE = [0, 1, 2, 5, 4, 3]
# the forcing's time rate by a central difference of this step, s: its truncation error
# (step^2 / 6 times the third derivative) and rounding (EPS / step) are both ~1e-10 relative
# on motions slower than ~1 kHz
_RATE_STEP_S = 1e-5


@dataclass(frozen=True, eq=False)
class BaseMotion:
    """A prescribed motion of the clamp: position and roll-pitch-yaw as functions of time.

    Attributes
    ----------
    pose : callable t (s) -> (6,)
        (x, y, z) in m and (roll, pitch, yaw) in rad, world frame (R = Rz(yaw) Ry(pitch)
        Rx(roll)).
    rate : callable t -> (6,)
        Their time derivatives, m/s and rad/s.
    acceleration : callable t -> (6,)
        Their second time derivatives, m/s^2 and rad/s^2.
    span_s : tuple of float or None
        The time span the motion is defined on (samples' first and last time), s; None for
        functions defined at every time.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> shake = pp.BaseMotion(pose=lambda t: np.array([0, 0, 1e-3 * np.sin(50 * t), 0, 0, 0]),
    ...                       rate=lambda t: np.array([0, 0, 5e-2 * np.cos(50 * t), 0, 0, 0]),
    ...                       acceleration=lambda t: np.array([0, 0, -2.5 * np.sin(50 * t),
    ...                                                        0, 0, 0]))
    >>> shake.pose(0.0).shape  # x, y, z (m), roll, pitch, yaw (rad)
    (6,)
    """

    pose: Callable[[float], np.ndarray]
    rate: Callable[[float], np.ndarray]
    acceleration: Callable[[float], np.ndarray]
    span_s: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        """Check that the three are callables returning six finite numbers at t = 0."""
        for name in ("pose", "rate", "acceleration"):
            f = getattr(self, name)
            if not callable(f):
                raise InputTypeError(f"BaseMotion {name} = {f!r:.60}: must be a callable of "
                                     "time (s) returning 6 numbers")
        t0 = 0.0 if self.span_s is None else self.span_s[0]
        self.coordinates(t0)

    @classmethod
    def from_samples(cls, t_s, position_m, angles_rad=None) -> BaseMotion:
        """Return the motion through samples, a cubic spline per coordinate.

        Parameters
        ----------
        t_s : array_like (s,)
            Sample times, s, strictly increasing, at least 2.
        position_m : array_like (s, 3)
            x, y, z, m.
        angles_rad : array_like (s, 3), optional
            roll, pitch, yaw, rad (default zero: a pure translation).
        """
        t = _array("t_s", t_s, 1)
        if t.size < 2:
            raise BeamInputError(f"t_s has {t.size} samples: needs at least 2")
        bad = np.flatnonzero(np.diff(t) <= 0.0)
        if bad.size:
            i = int(bad[0]) + 1
            raise BeamInputError(f"t_s[{i}] = {t[i]:g} s: times must increase (previous "
                                 f"{t[i - 1]:g} s)")
        p = _array("position_m", position_m, 2, (t.size, 3))
        a = np.zeros_like(p) if angles_rad is None else _array("angles_rad", angles_rad, 2,
                                                               (t.size, 3))
        spline = CubicSpline(t, np.hstack([p, a]), axis=0)
        d1, d2 = spline.derivative(1), spline.derivative(2)
        return cls(spline, d1, d2, (float(t[0]), float(t[-1])))

    def coordinates(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Return the base coordinates, rates and accelerations at ``t`` (s), Pinocchio order.

        (x, y, z, yaw, pitch, roll) and their derivatives; BeamInputError if not 6 finite each.
        """
        out = []
        for name in ("pose", "rate", "acceleration"):
            v = np.asarray(getattr(self, name)(t), dtype=float).reshape(-1)
            if v.size != 6 or not np.all(np.isfinite(v)):
                raise BeamInputError(f"BaseMotion {name}({t:g}) = {v!r:.80}: must be 6 finite "
                                     "numbers (x, y, z m; roll, pitch, yaw rad, and rates)")
            out.append(v[_TO_BASE])
        return out[0], out[1], out[2]

    def check_span(self, duration_s: float) -> None:
        """Raise BeamInputError unless the samples cover [0, ``duration_s``] (s)."""
        if self.span_s is None:
            return
        t0, t1 = self.span_s
        # a sample grid that ends on the duration up to rounding covers it
        if t0 > 0.0 or t1 < duration_s * (1.0 - 1e-12):
            raise BeamInputError(f"base_motion: samples span {t0:g} s to {t1:g} s; they must "
                                 f"cover the run, 0 to {duration_s:g} s")


def _array(name: str, value, ndim: int, shape: tuple | None = None) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} = {value!r:.60}: must be numbers") from None
    if a.ndim != ndim or (shape is not None and a.shape != shape):
        want = shape if shape is not None else f"{ndim}-d"
        raise BeamInputError(f"{name} has shape {a.shape}: must be {want}")
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        raise BeamInputError(f"{name}{list(bad[0])} = {a[tuple(bad[0])]}: must be finite")
    return a


class BaseForce:
    """The base motion's generalised force on the clamped chain, with the inputs' force.

    The same interface as :class:`~prbdm_pin.simulation.inputs.InputForce` (``values``,
    ``torque``, ``jacobians``, ``time_rate``, ``names``, ``units``), so every integrator that
    takes inputs takes it; ``inner`` is the plant inputs' force (None without inputs).
    """

    def __init__(self, motion: BaseMotion, chain: pin.Model, inner=None):
        self.motion = motion
        self.chain = chain  # the clamped chain, with the run's gravity
        self.full = base_chain(chain, None, chain.name + "_on_base")
        self._cd, self._fd = chain.createData(), self.full.createData()
        self.inner = inner
        self.names = () if inner is None else inner.names
        self.units = () if inner is None else inner.units
        self.time_varying = True

    def values(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return the plant inputs u at (t s, q rad, v rad/s); empty without inputs."""
        return np.zeros(0) if self.inner is None else self.inner.values(t, q, v)

    def _full_state(self, t, q, v):
        qb, vb, ab = self.motion.coordinates(t)
        return (np.concatenate([qb, q]), np.concatenate([vb, v]),
                np.concatenate([ab, np.zeros_like(q)]))

    def base_torque(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return tau_base (nv,), N m: the base motion's force on the member (module notes)."""
        Q, V, A = self._full_state(t, q, v)
        moving = pin.rnea(self.full, self._fd, Q, V, A)[N_BASE:]
        return pin.rnea(self.chain, self._cd, q, v, np.zeros_like(q)) - moving

    def torque(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return the generalised force of the base motion and the inputs (nv,), N m."""
        tau = self.base_torque(t, q, v)
        return tau if self.inner is None else tau + self.inner.torque(t, q, v)

    def jacobians(self, t: float, q: np.ndarray, v: np.ndarray
                  ) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Return d tau / dq and d tau / dv (nv, nv), from Pinocchio's RNEA derivatives."""
        Q, V, A = self._full_state(t, q, v)
        fq, fv, _ = pin.computeRNEADerivatives(self.full, self._fd, Q, V, A)
        cq, cv, _ = pin.computeRNEADerivatives(self.chain, self._cd, q, v, np.zeros_like(q))
        dq = cq - fq[N_BASE:, N_BASE:]
        dv = cv - fv[N_BASE:, N_BASE:]
        if self.inner is not None:
            iq, iv = self.inner.jacobians(t, q, v)
            dq = dq if iq is None else dq + iq
            dv = dv if iv is None else dv + iv
        return dq, dv

    def time_rate(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return d tau / dt at a fixed state, N m/s (the base force's by a central difference)."""
        h = _RATE_STEP_S
        lo = max(t - h, 0.0 if self.motion.span_s is None else self.motion.span_s[0])
        rate = (self.base_torque(t + h, q, v) - self.base_torque(lo, q, v)) / (t + h - lo)
        inner = None if self.inner is None else self.inner.time_rate(t, q, v)
        return rate if inner is None else rate + inner


def world_tip_positions(model, motion: BaseMotion, t_s: np.ndarray, Q: np.ndarray
                        ) -> np.ndarray:
    """Return the tip in the world frame (s, 3), m, of a run under ``motion``.

    ``model`` is the clamped model, ``Q`` its coordinates (s, nv) at the times ``t_s`` (s).
    """
    full = base_chain(model.pin_model, None, "tip_on_base")
    data = full.createData()
    fid = full.getFrameId(TIP_FRAME)
    out = np.empty((len(Q), 3))
    for i, (t, q) in enumerate(zip(t_s, Q, strict=True)):
        qb = motion.coordinates(float(t))[0]
        pin.framesForwardKinematics(full, data, np.concatenate([qb, q]))
        out[i] = data.oMf[fid].translation
    return out
