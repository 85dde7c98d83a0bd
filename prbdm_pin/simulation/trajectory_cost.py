"""Scalar costs of a simulated trajectory, with the partial derivatives a gradient needs.

A cost is J = integral over [0, T] of l(t, x, u, z) dt + phi(x(T), z(T)), with x = (q, v) the
state (rad, rad/s), u the plant inputs (their units) and z the tip's world height (m, the tip
displacement of a clamped chain straight along x). :func:`prbdm_pin.trajectory_gradient`
differentiates it; a user's cost is any object with the four methods of
:class:`TrajectoryCost`, and :class:`QuadraticCost` is the usual tip-plus-effort one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..options.checks import check_float

__all__ = ["TrajectoryCost", "QuadraticCost"]


class TrajectoryCost:
    """The interface of a trajectory cost: a running term l and a terminal term phi.

    Subclass it and override :meth:`running` and :meth:`running_partials` (and the terminal
    pair when there is one; the defaults are zero). Every value must be finite: a NaN or an
    infinity stops :func:`prbdm_pin.trajectory_gradient` with a BeamInputError naming the cost.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> class TipOnly(pp.TrajectoryCost):
    ...     def running(self, t, x, u, z):
    ...         return z * z
    ...     def running_partials(self, t, x, u, z):
    ...         return np.zeros_like(x), np.zeros_like(u), 2.0 * z
    >>> cost = TipOnly()
    >>> cost.running(0.0, np.zeros(4), np.zeros(0), 0.5), cost.terminal(np.zeros(4), 0.5)
    (0.25, 0.0)
    """

    def running(self, t: float, x: np.ndarray, u: np.ndarray, z: float) -> float:
        """Return l(t, x, u, z) at time ``t`` (s), state ``x``, inputs ``u`` and tip height ``z``.

        Units: the cost's own per second (J is its integral over time).
        """
        raise NotImplementedError("a TrajectoryCost defines running(t, x, u, z)")

    def running_partials(self, t: float, x: np.ndarray, u: np.ndarray, z: float
                         ) -> tuple[np.ndarray, np.ndarray, float]:
        """Return (dl/dx (2 nv,), dl/du (m,), dl/dz) at the same arguments as :meth:`running`."""
        raise NotImplementedError("a TrajectoryCost defines running_partials(t, x, u, z)")

    def running_with_partials(self, t: float, x: np.ndarray, u: np.ndarray, z: float
                              ) -> tuple[float, np.ndarray, np.ndarray, float]:
        """Return (l, dl/dx, dl/du, dl/dz) in one call (default: the two methods above).

        A gradient run calls this at every stage; override it when the value and its
        partials share work.
        """
        return (self.running(t, x, u, z), *self.running_partials(t, x, u, z))

    def terminal(self, x: np.ndarray, z: float) -> float:
        """Return phi(x(T), z(T)), the cost's terminal term (default 0)."""
        return 0.0

    def terminal_partials(self, x: np.ndarray, z: float) -> tuple[np.ndarray, float]:
        """Return (dphi/dx (2 nv,), dphi/dz) (default zero)."""
        return np.zeros_like(x), 0.0


def _weight(name: str, value) -> np.ndarray | None:
    """Return a weight: a number (alike on every entry), a diagonal or a symmetric matrix.

    A number stays 0-d and a diagonal becomes its matrix; the size is checked against the
    trajectory where the weight is used.
    """
    if value is None:
        return None
    try:
        raw = np.array(value)
    except (TypeError, ValueError):
        raw = np.array(None)
    if isinstance(value, (bool, str, bytes)) or raw.dtype.kind not in "iuf":
        raise InputTypeError(f"QuadraticCost {name} = {value!r:.60}: must be a real number, "
                             "a diagonal or a square matrix")
    a = raw.astype(float)
    if a.ndim == 1:
        a = np.diag(a)
    if a.ndim not in (0, 2) or (a.ndim == 2 and a.shape[0] != a.shape[1]) \
            or not np.all(np.isfinite(a)):
        raise BeamInputError(f"QuadraticCost {name} = {value!r:.60}: must be a finite number, "
                             f"diagonal or square matrix, not shape {a.shape}")
    if not np.array_equal(a, a.T) or (a.ndim == 0 and a < 0.0) or np.any(np.diagonal(
            np.atleast_2d(a)) < 0.0):
        raise BeamInputError(f"QuadraticCost {name}: must be symmetric with entries >= 0 on "
                             "its diagonal")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class QuadraticCost(TrajectoryCost):
    """l = w_z z^2 + x^T Q x + u^T R u, phi = w_zT z(T)^2 + x(T)^T Q_T x(T).

    Attributes
    ----------
    tip_weight_per_m2 : float
        w_z, per m^2 (of the tip height z, m), >= 0.
    state_weight : float, array (2 nv,) or (2 nv, 2 nv), optional
        Q: one number for every state, a diagonal or a symmetric matrix, per rad^2 and per
        (rad/s)^2 (the order of ``LinearModel.state_names``: angles, then rates).
    effort_weight : float, array (m,) or (m, m), optional
        R, per squared input unit.
    terminal_tip_weight_per_m2 : float
        w_zT, per m^2 (applied once, at T).
    terminal_state_weight : like ``state_weight``, optional
        Q_T.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> cost = pp.QuadraticCost(tip_weight_per_m2=1e4, effort_weight=0.5)
    >>> x, u = np.zeros(4), np.array([2.0])
    >>> float(cost.running(0.0, x, u, 0.01))  # 1e4 * 0.01^2 + 0.5 * 2^2
    3.0
    >>> cost.running_partials(0.0, x, u, 0.01)[1:]  # dl/du, dl/dz
    (array([2.]), 200.0)
    """

    tip_weight_per_m2: float = 0.0
    state_weight: object = None
    effort_weight: object = None
    terminal_tip_weight_per_m2: float = 0.0
    terminal_state_weight: object = None

    def __post_init__(self) -> None:
        """Check the weights: finite, the tip weights >= 0, the matrices symmetric."""
        for name in ("tip_weight_per_m2", "terminal_tip_weight_per_m2"):
            object.__setattr__(self, name, check_float(f"QuadraticCost {name}",
                                                       getattr(self, name), low=0.0,
                                                       unit="per m^2"))
        for name in ("state_weight", "effort_weight", "terminal_state_weight"):
            object.__setattr__(self, name, _weight(name, getattr(self, name)))

    @staticmethod
    def _quadratic(W: np.ndarray | None, a: np.ndarray) -> tuple[float, np.ndarray]:
        if W is None or a.size == 0:
            return 0.0, np.zeros_like(a)
        if W.ndim == 0:  # one number for every entry
            return float(W) * float(a @ a), 2.0 * float(W) * a
        if W.shape[0] != a.size:
            raise BeamInputError(f"QuadraticCost weight of shape {W.shape}: the trajectory "
                                 f"has {a.size} entries there")
        Wa = W @ a
        return float(a @ Wa), 2.0 * Wa

    def running(self, t: float, x: np.ndarray, u: np.ndarray, z: float) -> float:
        """Return w_z z^2 + x^T Q x + u^T R u."""
        return (self.tip_weight_per_m2 * z * z + self._quadratic(self.state_weight, x)[0]
                + self._quadratic(self.effort_weight, u)[0])

    def running_partials(self, t: float, x: np.ndarray, u: np.ndarray, z: float
                         ) -> tuple[np.ndarray, np.ndarray, float]:
        """Return (2 Q x, 2 R u, 2 w_z z)."""
        return (self._quadratic(self.state_weight, x)[1],
                self._quadratic(self.effort_weight, u)[1], 2.0 * self.tip_weight_per_m2 * z)

    def running_with_partials(self, t: float, x: np.ndarray, u: np.ndarray, z: float
                              ) -> tuple[float, np.ndarray, np.ndarray, float]:
        """Return (l, 2 Q x, 2 R u, 2 w_z z), each quadratic form evaluated once."""
        lq, gq = self._quadratic(self.state_weight, x)
        lu, gu = self._quadratic(self.effort_weight, u)
        w = self.tip_weight_per_m2
        return w * z * z + lq + lu, gq, gu, 2.0 * w * z

    def terminal(self, x: np.ndarray, z: float) -> float:
        """Return w_zT z^2 + x^T Q_T x."""
        return (self.terminal_tip_weight_per_m2 * z * z
                + self._quadratic(self.terminal_state_weight, x)[0])

    def terminal_partials(self, x: np.ndarray, z: float) -> tuple[np.ndarray, float]:
        """Return (2 Q_T x, 2 w_zT z)."""
        return (self._quadratic(self.terminal_state_weight, x)[1],
                2.0 * self.terminal_tip_weight_per_m2 * z)
