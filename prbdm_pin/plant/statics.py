"""A PRBDM's static equilibrium under a dead tip force, a dead tip moment and gravity.

    K q + g(q) - J(q)^T F - J_w(q)^T M = 0

with g Pinocchio's generalized gravity of the model under the given gravity, J and J_w the
tip's linear and angular Jacobians in world axes. Without gravity the equilibrium is
:meth:`PrbdmModel.static_deflection` (closed-form planar statics, or Newton on the exact tangent
of the general chain with load stepping); with gravity, damped Newton on the full residual from
that pose (:func:`prbdm_pin.plant.equilibrium.equilibrium`). What ``prbdm statics`` writes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from .equilibrium import check_vector, equilibrium, gravity_model

__all__ = ["StaticEquilibrium", "statics"]


@dataclass(frozen=True, eq=False)
class StaticEquilibrium:
    """The equilibrium of a PRBDM under its static loads.

    Attributes
    ----------
    q_rad : ndarray (n,)
        Joint angles, rad (every spring coordinate of a spatial chain).
    tip_position_m : ndarray (3,)
        The tip's position, m, world.
    tip_displacement_m : ndarray (3,)
        Its displacement from the straight pose, m.
    tip_rotation : ndarray (3, 3)
        The tip frame's orientation in the world.
    spring_torque_Nm : ndarray (n,)
        K q, N m: what each spring carries.
    tip_force_N, tip_moment_Nm, gravity_m_s2 : ndarray (3,)
        The loads, world (zeros where absent).
    """

    q_rad: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray
    tip_rotation: np.ndarray
    spring_torque_Nm: np.ndarray
    tip_force_N: np.ndarray
    tip_moment_Nm: np.ndarray
    gravity_m_s2: np.ndarray

    def to_dict(self) -> dict:
        """Return the JSON record ``prbdm statics`` writes (``statics.json``)."""
        return {"tip_position_m": self.tip_position_m.tolist(),
                "q_rad": self.q_rad.tolist(),
                "tip_displacement_m": self.tip_displacement_m.tolist(),
                "tip_rotation": self.tip_rotation.tolist(),
                "spring_torque_Nm": self.spring_torque_Nm.tolist(),
                "tip_force_N": self.tip_force_N.tolist(),
                "tip_moment_Nm": self.tip_moment_Nm.tolist(),
                "gravity_m_s2": self.gravity_m_s2.tolist()}


def statics(model, tip_force_N=None, tip_moment_Nm=None, gravity_m_s2=None
            ) -> StaticEquilibrium:
    """Return the static equilibrium of ``model`` under dead tip loads and gravity.

    Parameters
    ----------
    model : PrbdmModel
        Clamped (a hub would turn under the load: :func:`prbdm_pin.linearize` holds it with a
        trim torque); planar or spatial.
    tip_force_N : array_like (3,), optional
        Dead force at the tip, N, world (default none).
    tip_moment_Nm : array_like (3,), optional
        Dead moment on the tip link, N m, world (default none). About y it bends the planar
        chain (M = 2 pi E I / L rolls a uniform member into a circle).
    gravity_m_s2 : array_like (3,), optional
        Gravity, m/s^2, world (default none; e.g. ``(0, 0, -9.81)``).

    Returns
    -------
    StaticEquilibrium

    Raises
    ------
    BeamInputError
        A load that is not 3 finite numbers (naming it), or a hub model. SolveError when no
        equilibrium is found.
    """
    from ..model.prbdm_model import PrbdmModel

    if not isinstance(model, PrbdmModel):
        raise InputTypeError(f"model = {model!r:.60}: must be a PrbdmModel")
    F = check_vector("tip_force_N", tip_force_N, "N")
    M = check_vector("tip_moment_Nm", tip_moment_Nm, "N m")
    g = check_vector("gravity_m_s2", gravity_m_s2, "m/s^2")
    if model.bus is not None:
        raise BeamInputError("model: has a free bus, which drifts under a static load; statics "
                             "needs a clamped model (model.member)")
    if model.hub is not None:
        raise BeamInputError("model: has a hub, which turns under a static load; statics "
                             "needs a clamped model (linearize holds a hub with a trim torque)")
    F = np.zeros(3) if F is None else F
    M = np.zeros(3) if M is None else M
    g = np.zeros(3) if g is None else g
    q, _ = equilibrium(model, F, gravity_model(model, g), moment_Nm=M)
    p, R = model.tip_pose(q)
    out = StaticEquilibrium(q, p, p - model.tip_position(), R,
                            model.stiffness_Nm_per_rad * q, F, M, g)
    for a in (out.q_rad, out.tip_position_m, out.tip_displacement_m, out.tip_rotation,
              out.spring_torque_Nm, F, M, g):
        a.setflags(write=False)
    return out
