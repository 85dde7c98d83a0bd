"""A PRBDM's static equilibrium under tip loads, a distributed load and gravity.

    K q + g(q) - J(q)^T F - J_w(q)^T M - J_l(q)^T M_f - B_q(q) q_d = 0

with g Pinocchio's generalized gravity of the model under the given gravity, J and J_w the
tip's linear and angular Jacobians in world axes, J_l the tip's angular Jacobian in its own
frame (the follower moment M_f about the tip link's axes) and B_q the virtual-work map of the
distributed load q_d (N/m, world; :mod:`prbdm_pin.model.loads`). With a follower moment or a
distributed load: damped Newton on the full residual, their load stiffness by central
differences of their generalized force (it steers Newton only: the residual is exact), the
loads stepped up in tenths when the whole load in one go finds no equilibrium.

Otherwise, without gravity the equilibrium is
:meth:`PrbdmModel.static_deflection` (closed-form planar statics, or Newton on the exact tangent
of the general chain with load stepping); with gravity, damped Newton on the full residual from
that pose (:func:`prbdm_pin.plant.equilibrium.equilibrium`). What ``prbdm statics`` writes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError, SolveError
from ..model.inputs import input_map
from ..model.loads import DISTRIBUTED_FORCES, FOLLOWER_MOMENTS, DistributedLoad, check_load
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
    tip_moment_follower_Nm : ndarray (3,)
        The follower tip moment, N m, about the tip link's own axes (zeros where absent).
    distributed_N_m : ndarray (3,)
        The distributed load's intensity, N/m, world (zeros where absent).
    distributed_span_m : tuple (2,)
        Its span, m from the root (the whole beam by default).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> eq = pp.statics(model, tip_force_N=[0.0, 0.0, -1.0])
    >>> isinstance(eq, pp.StaticEquilibrium), eq.q_rad.shape
    (True, (2,))
    >>> round(float(eq.tip_force_N[2]), 1)
    -1.0
    """

    q_rad: np.ndarray
    tip_position_m: np.ndarray
    tip_displacement_m: np.ndarray
    tip_rotation: np.ndarray
    spring_torque_Nm: np.ndarray
    tip_force_N: np.ndarray
    tip_moment_Nm: np.ndarray
    gravity_m_s2: np.ndarray
    tip_moment_follower_Nm: np.ndarray | None = None
    distributed_N_m: np.ndarray | None = None
    distributed_span_m: tuple = ()

    def to_dict(self) -> dict:
        """Return the JSON record ``prbdm statics`` writes (``statics.json``)."""
        return {"tip_position_m": self.tip_position_m.tolist(),
                "q_rad": self.q_rad.tolist(),
                "tip_displacement_m": self.tip_displacement_m.tolist(),
                "tip_rotation": self.tip_rotation.tolist(),
                "spring_torque_Nm": self.spring_torque_Nm.tolist(),
                "tip_force_N": self.tip_force_N.tolist(),
                "tip_moment_Nm": self.tip_moment_Nm.tolist(),
                "gravity_m_s2": self.gravity_m_s2.tolist(),
                "tip_moment_follower_Nm": _listed(self.tip_moment_follower_Nm),
                "distributed_N_m": _listed(self.distributed_N_m),
                "distributed_span_m": list(self.distributed_span_m)}


def _listed(v: np.ndarray | None) -> list[float]:
    return [0.0, 0.0, 0.0] if v is None else v.tolist()


def statics(model, tip_force_N=None, tip_moment_Nm=None, gravity_m_s2=None, *,
            tip_moment_follower_Nm=None, distributed_N_m=None,
            distributed_load: DistributedLoad | None = None) -> StaticEquilibrium:
    """Return the static equilibrium of ``model`` under tip loads, a distributed load, gravity.

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
    tip_moment_follower_Nm : array_like (3,), optional
        Follower moment on the tip link, N m, about its own x, y, z axes (default none): it
        turns with the tip. About y on a planar chain it is the dead moment about y.
    distributed_N_m : array_like (3,), optional
        A force per unit length, N/m, world (dead; default none), uniform over the whole beam
        or over the span and with the profile of ``distributed_load`` (the intensity at each
        station is this times the load's weight there).
    distributed_load : DistributedLoad, optional
        The span and profile of ``distributed_N_m`` (default: uniform over the beam).

    Returns
    -------
    StaticEquilibrium

    Raises
    ------
    BeamInputError
        A load that is not 3 finite numbers (naming it), or a hub model. SolveError when no
        equilibrium is found.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> one_r = pp.build_model(beam, [0.2, 0.8], [2500.0])  # one joint, 0.8 m from the tip
    >>> eq = pp.statics(one_r, tip_force_N=[0.0, 0.0, -1.0])
    >>> round(float(eq.tip_displacement_m[2]) * 1e3, 4)  # mm
    -0.256
    >>> round(-1.0 * 0.8**2 / 2500.0 * 1e3, 4)  # mm, small angles: F a^2 / k
    -0.256
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
    Mf = check_vector("tip_moment_follower_Nm", tip_moment_follower_Nm, "N m, tip frame")
    qd = check_vector("distributed_N_m", distributed_N_m, "N/m")
    if distributed_load is not None:
        check_load(model.lengths_m, distributed_load, "distributed_load")
    if model.hub is not None:
        raise BeamInputError("model: has a hub, which turns under a static load; statics "
                             "needs a clamped model (linearize holds a hub with a trim torque)")
    F = np.zeros(3) if F is None else F
    M = np.zeros(3) if M is None else M
    g = np.zeros(3) if g is None else g
    Mf = np.zeros(3) if Mf is None else Mf
    qd = np.zeros(3) if qd is None else qd
    pm_g = gravity_model(model, g)
    extra = _extra_loads(model, Mf, qd, distributed_load)
    if extra is None:
        q, _ = equilibrium(model, F, pm_g, moment_Nm=M)
    else:
        try:
            q, _ = equilibrium(model, F, pm_g, moment_Nm=M, extra=extra(1.0))
        except SolveError:
            q = None
            for lam in np.linspace(0.1, 1.0, 10):  # the loads stepped up from the dead pose
                try:
                    q, _ = equilibrium(model, F, pm_g, moment_Nm=M, extra=extra(lam), q0=q)
                except SolveError:
                    raise SolveError(
                        f"statics: no equilibrium under the follower tip moment {Mf.tolist()} "
                        f"N m and the distributed load {qd.tolist()} N/m (with the other "
                        f"loads), stepped up in tenths: none at {lam:.1f} of them") from None
    p, R = model.tip_pose(q)
    span = () if distributed_load is None else (distributed_load.x_start_m,
                                                distributed_load.x_end_m)
    out = StaticEquilibrium(q, p, p - model.tip_position(), R,
                            model.stiffness_Nm_per_rad * q, F, M, g, Mf, qd, span)
    for a in (out.q_rad, out.tip_position_m, out.tip_displacement_m, out.tip_rotation,
              out.spring_torque_Nm, F, M, g, Mf, qd):
        a.setflags(write=False)
    return out


def _extra_loads(model, follower_Nm: np.ndarray, distributed_N_m: np.ndarray,
                 load: DistributedLoad | None):
    """Return lam -> extra(q) -> (tau, d tau / dq) of the follower moment and distributed load.

    None without them. The derivative is by central differences (step ~ EPS^(1/3): truncation
    and rounding balanced); it steers Newton only.
    """
    names = [n for n, v in zip(FOLLOWER_MOMENTS, follower_Nm, strict=True) if v != 0.0]
    u = [float(v) for v in follower_Nm if v != 0.0]
    dist = [n if load is None else f"{n}[0]" for n in DISTRIBUTED_FORCES]
    names += [n for n, v in zip(dist, distributed_N_m, strict=True) if v != 0.0]
    u += [float(v) for v in distributed_N_m if v != 0.0]
    if not names:
        return None
    loads = () if load is None else (load,)
    u = np.array(u)

    def tau(q):
        return input_map(model, q, names, loads=loads) @ u

    def scaled(lam: float):
        def extra(q):
            h = 6e-6 * max(1.0, float(np.abs(q).max()))
            d = np.empty((q.size, q.size))
            for j in range(q.size):
                e = np.zeros(q.size)
                e[j] = h
                d[:, j] = (tau(q + e) - tau(q - e)) / (2.0 * h)
            return lam * tau(q), lam * d
        return extra
    return scaled
