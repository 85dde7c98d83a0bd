"""The residual and exact tangent stiffness of a chain of revolute joints under a dead tip wrench.

The equilibrium of a serial chain of revolute joints (any of x, y, z at each node, springs
K = diag(k)) under a tip force f (N) and a tip moment m (N m), both fixed in the world::

    r(q) = K q - J(q)^T w = 0,    w = (f, m) at the tip point, world-aligned axes,

and its tangent stiffness T = K - d(J^T w)/dq (:mod:`.spatial_statics` solves it). The tangent
comes from the tip Jacobian alone: column i of J holds the joint axis a_i and the tip velocity
v_i = a_i x (p - r_i), and on a serial chain (joint j an ancestor of joint i for j <= i)

    d(J^T w)_i / dq_j = f . (a_j x v_i) + m . (a_j x a_i)   for j <= i,
                        f . (a_i x v_j)                     for j > i.

Under a force alone the load is conservative and T is the Hessian of
V = 1/2 q^T K q - f . p_tip (symmetric); a dead moment is not conservative in three dimensions
(a fixed-axis moment does no path-independent work on finite rotations) and makes T unsymmetric,
so a solver drives the residual to zero instead of minimising a potential. Under a pure moment
the derivative is strictly lower triangular (f = 0): T has the springs as its eigenvalues.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from .pin_dynamics import checked_stiffness
from .statics_guard import require_finite

__all__ = ["ChainLoad", "checked_wrench", "check_chain", "residual_and_tangent",
           "wrench_tangent"]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_REVOLUTE = ("JointModelRX", "JointModelRY", "JointModelRZ")


def checked_wrench(tip_force_N: np.ndarray, tip_moment_Nm: np.ndarray | None = None
                   ) -> np.ndarray:
    """Return the tip wrench (f, m), checked.

    Parameters
    ----------
    tip_force_N : array_like, shape (3,)
        Tip force, N, world axes.
    tip_moment_Nm : array_like, shape (3,), optional
        Tip moment, N m, world axes (None: no moment).

    Returns
    -------
    ndarray, shape (6,)
        f (N), then m (N m).

    Raises
    ------
    BeamInputError
        Naming ``tip_force`` or ``tip_moment`` unless each is 3 finite real numbers.
    """
    parts = []
    for name, v, unit in (("tip_force", tip_force_N, "N"), ("tip_moment", tip_moment_Nm, "N m")):
        try:
            a = np.zeros(3) if v is None else np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            a = np.full(1, np.nan)  # not real numbers
        if a.shape != (3,) or not np.all(np.isfinite(a)):
            raise BeamInputError(f"{name} = {v!r}: must be 3 finite real numbers "
                                 f"({unit}, world axes)")
        parts.append(a)
    return np.concatenate(parts)


def check_chain(pin_model: pin.Model, tip_frame_id: int) -> float:
    """Check that the model is a serial chain of 1-dof revolute joints; return its arm.

    Parameters
    ----------
    pin_model : pinocchio.Model
        The chain.
    tip_frame_id : int
        The tip frame, which must sit on the last joint.

    Returns
    -------
    float
        The summed joint-to-joint and last-joint-to-tip offsets, m: the largest lever a tip
        force can have about the first joint.

    Raises
    ------
    BeamInputError
        Naming the joint or frame that breaks the rule.
    """
    n = pin_model.njoints - 1
    if pin_model.nq != n or pin_model.nv != n:
        raise BeamInputError(f"pin_model: nq = {pin_model.nq}, nv = {pin_model.nv}, must both "
                             f"be its {n} joints (revolute joints only)")
    for j in range(1, n + 1):
        if pin_model.parents[j] != j - 1 or pin_model.joints[j].shortname() not in _REVOLUTE:
            raise BeamInputError(f"joint {pin_model.names[j]!r}: must be a serial revolute "
                                 "joint about x, y or z")
    frame = pin_model.frames[tip_frame_id]
    if frame.parentJoint != n:
        raise BeamInputError(f"frame {frame.name!r}: the tip frame must sit on the last joint")
    arm = sum(float(np.linalg.norm(pin_model.jointPlacements[j].translation))
              for j in range(2, n + 1))
    return arm + float(np.linalg.norm(frame.placement.translation))


def _jacobian(pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
              ) -> np.ndarray:
    J = pin.computeFrameJacobian(pin_model, data, q, tip_frame_id, _LWA)
    return J.reshape(6, pin_model.nv)  # the binding hands one column back as a vector


def _tangent(k: np.ndarray, J: np.ndarray, w: np.ndarray) -> np.ndarray:
    f, m = w[:3], w[3:]
    V, A = J[:3].T, J[3:].T  # rows v_i (m/rad) and a_i (1/rad)
    lower = np.cross(V, f) @ A.T + np.cross(A, m) @ A.T  # [i, j] = f.(a_j x v_i) + m.(a_j x a_i)
    upper = -np.cross(A, f) @ V.T  # [i, j] = f.(a_i x v_j)
    D = np.tril(lower) + np.triu(upper, 1)
    return np.diag(k) - D


def wrench_tangent(k: np.ndarray, J: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    """Return K - d(J^T w)/dq (N m/rad, (nv, nv)) of a serial revolute chain.

    ``k`` the springs (N m/rad, (nv,), 0 allowed: a free joint such as a hub), ``J`` the tip's
    world-aligned Jacobian (6, nv) at the pose, ``wrench`` the dead tip force and moment (6,).
    """
    return _tangent(np.asarray(k, dtype=float), J, np.asarray(wrench, dtype=float))


def residual_and_tangent(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    tip_frame_id: int,
    q: np.ndarray,
    wrench: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Residual r = K q - J(q)^T w (N m) and tangent stiffness dr/dq (N m/rad) at ``q``.

    Parameters
    ----------
    pin_model, data : pinocchio.Model, pinocchio.Data
        A serial chain of revolute joints (``nq == nv``) and its workspace.
    stiffness_Nm_per_rad : ndarray, shape (nv,)
        The joint springs, N m/rad.
    tip_frame_id : int
        The frame the wrench acts at (on the last joint).
    q : ndarray, shape (nv,)
        Joint angles, rad.
    wrench : ndarray, shape (6,)
        Dead tip force (N) and moment (N m), world axes (:func:`checked_wrench`).

    Returns
    -------
    r : ndarray, shape (nv,)
        Residual, N m.
    T : ndarray, shape (nv, nv)
        K - d(J^T w)/dq, N m/rad (symmetric when the moment is zero).
    """
    check_chain(pin_model, tip_frame_id)
    k = checked_stiffness(stiffness_Nm_per_rad, pin_model.nv)
    q = np.asarray(q, dtype=float)
    w = np.asarray(wrench, dtype=float)
    J = _jacobian(pin_model, data, q, tip_frame_id)
    return k * q - J.T @ w, _tangent(k, J, w)


class ChainLoad:
    """A chain's residual, its scale, tangent and tip under the load ``lam w`` (the solver's).

    ``k`` (N m/rad) and ``w`` (N, N m) checked; one Jacobian pass per evaluation.
    """

    def __init__(self, pin_model: pin.Model, data: pin.Data, k: np.ndarray, tip_frame_id: int,
                 w: np.ndarray) -> None:
        self.args = (pin_model, data)
        self.tip, self.k, self.w = tip_frame_id, k, w

    def eval(self, q: np.ndarray, lam: float, tangent: bool = True) -> tuple:
        """Return r (N m), ||r||, max(||K q||, ||J^T w||), T (or None) and J at ``q``, load lam."""
        J = _jacobian(*self.args, q, self.tip)
        kq, jw = self.k * q, J.T @ (lam * self.w)
        r = kq - jw
        rn, scale = math.sqrt(r @ r), max(math.sqrt(kq @ kq), math.sqrt(jw @ jw))
        require_finite(self.w[:3], rn, scale)
        return r, rn, scale, (_tangent(self.k, J, lam * self.w) if tangent else None), J

    def potential(self, q: np.ndarray, lam: float) -> float:
        """V = 1/2 q^T K q - lam f . p_tip (J), the force's potential (the moment has none)."""
        pin.forwardKinematics(*self.args, q)
        p = pin.updateFramePlacement(*self.args, self.tip).translation
        return 0.5 * float(q @ (self.k * q)) - lam * float(self.w[:3] @ p)
