"""The plant's equilibrium under a dead tip load and gravity, and the stiffness about it.

Static balance: K q + g(q) - J(q)^T F = tau_u, with g the generalized gravity (Pinocchio's
``computeGeneralizedGravity`` of the model with the given gravity) and F the dead tip force.
Linearised: the effective stiffness is K + dg/dq - d(J^T F)/dq. The dead-load term comes from
the closed-form planar chain (:func:`prbdm_pin.chain.planar.load_stiffness`); a hub model about y
is the planar chain whose first joint is the hub at the origin, reaching the first beam joint
over radius + L_0, so the same formula covers it (a hub about x or z takes the general serial
chain's tangent, :func:`prbdm_pin.chain.spatial_tangent.wrench_tangent`). A spatial chain (no
hub) takes the exact tangent of the general serial chain
(:func:`prbdm_pin.chain.spatial_tangent.residual_and_tangent`) and starts from its static deflection
(:meth:`PrbdmModel.static_deflection`); gravity enters through Pinocchio either way.

A hub model has no equilibrium of its own under a load that turns the hub: the hub is held at
angle 0 by a trim hub torque (returned), and the beam joints are balanced.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..chain.planar import force_and_load_stiffness
from ..chain.spatial_tangent import residual_and_tangent, wrench_tangent
from ..chain.statics import static_deflection_planar
from ..errors import BeamInputError, SolveError
from .spin import spin_terms

__all__ = ["check_vector", "planar_lengths_with_hub", "gravity_model", "static_terms",
           "equilibrium"]


def check_vector(field: str, value, unit: str) -> np.ndarray | None:
    """Return a world vector (3,) as floats, None for None; BeamInputError naming ``field``."""
    if value is None:
        return None
    try:
        v = np.array(value, dtype=float)
    except (TypeError, ValueError):
        v = np.array([np.nan])
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise BeamInputError(f"{field} = {value!r}: must be 3 finite numbers ({unit}, world)")
    return v


def planar_lengths_with_hub(model) -> np.ndarray:
    """Return the lengths (m) of the planar chain over every coordinate of ``model``.

    These are its link lengths, or (0, radius + L_0, L_1, ..., L_n) on a hub model.
    """
    L = np.asarray(model.lengths_m, dtype=float)
    if model.hub is None:
        return L
    return np.concatenate([[0.0, model.hub.radius_m + L[0]], L[1:]])


def gravity_model(model, gravity_m_s2: np.ndarray | None) -> pin.Model | None:
    """Return a copy of the Pinocchio model with the gravity (m/s^2, world); None without."""
    if gravity_m_s2 is None or not np.any(gravity_m_s2):
        return None
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.concatenate([gravity_m_s2, np.zeros(3)]))
    return pm


def static_terms(model, q: np.ndarray, load_N: np.ndarray, pm_g: pin.Model | None,
                 data_g: pin.Data | None, moment_Nm: np.ndarray | None = None,
                 extra=None) -> tuple[np.ndarray, np.ndarray]:
    """Return the static residual and its Jacobian at pose ``q`` (rad).

    The residual is K q + g(q) - J^T F - J_w^T M - tau_x(q) (N m, (nv,)), M a dead tip moment
    (N m, world; default none), tau_x the generalized force of further loads given as
    ``extra(q) -> (tau_x, d tau_x / dq)`` (default none); its Jacobian the effective stiffness
    (N m/rad, (nv, nv)).
    """
    moment = np.zeros(3) if moment_Nm is None else np.asarray(moment_Nm, dtype=float)
    if model.axes.spatial:
        # a dead force alone gives a symmetric tangent; a moment does not
        w = np.concatenate([load_N, moment])
        # the chain's data workspace: only the gravity copy's is passed in
        r, H = residual_and_tangent(model.pin_model, model.default_data,
                                    model.stiffness_Nm_per_rad, model.tip_frame_id, q, w)
    elif model.hub is not None and model.hub.axis != "y":
        # a hub about x or z leaves the plane of the beam joints: the general serial chain,
        # the hub joint without a spring
        w = np.concatenate([load_N, moment])
        K = model.stiffness_matrix()
        J = model.tip_frame_jacobian(q)
        r = K @ q - J.T @ w
        H = wrench_tangent(np.diag(K), J, w)
    else:
        K = model.stiffness_matrix()
        jtf, T = force_and_load_stiffness(planar_lengths_with_hub(model), q, load_N)
        # every coordinate of the planar chain (and its hub) turns about y: J_w^T M = M_y,
        # the same at every pose (no load stiffness)
        r = K @ q - jtf - moment[1]
        H = K - T
    if pm_g is not None:
        r = r + pin.computeGeneralizedGravity(pm_g, data_g, q)
        H = H + pin.computeGeneralizedGravityDerivatives(pm_g, data_g, q)
    if extra is not None:
        tau, dtau = extra(q)
        r, H = r - tau, H - dtau
    return r, H


def equilibrium(model, load_N: np.ndarray, pm_g: pin.Model | None, rtol: float = 1e-10,
                max_iter: int = 60, moment_Nm: np.ndarray | None = None, extra=None,
                q0: np.ndarray | None = None, spin_rad_s: float = 0.0
                ) -> tuple[np.ndarray, float]:
    """Return the equilibrium pose (rad, (nv,)) and the trim hub torque (N m).

    The pose is under the dead tip load (N), the dead tip moment ``moment_Nm`` (N m, world;
    default none), the gravity of ``pm_g`` and the loads ``extra`` (:func:`static_terms`;
    those start from ``q0``, default the pose under the others); the trim torque holds the hub
    at 0 (0.0 without a hub). With ``spin_rad_s`` (rad/s, a hub model) it is the relative
    equilibrium of the hub spinning at that rate: the centrifugal terms h(q, (Omega, 0...))
    join the static ones (:mod:`prbdm_pin.plant.spin`; the caller checks that the loads do not
    turn relative to the hub).

    Without gravity and hub this is :meth:`PrbdmModel.static_deflection`; otherwise damped
    Newton steps on the beam joints from the planar statics' pose.

    Raises
    ------
    SolveError
        If no equilibrium is found.
    """
    hub = model.hub is not None
    moment = None if moment_Nm is None or not np.any(moment_Nm) else moment_Nm
    if pm_g is None and not np.any(load_N) and moment is None and extra is None:
        return np.zeros(model.pin_model.nv), 0.0  # unloaded: the straight pose, no trim
    if pm_g is None and not hub and extra is None:
        return model.static_deflection(load_N, tip_moment_Nm=moment)[0], 0.0
    off = int(hub)
    q = np.zeros(model.pin_model.nv)
    if not hub and (model.axes.spatial or moment is not None):  # no hub on a spatial chain
        if np.any(load_N) or moment is not None:
            q = model.static_deflection(load_N, tip_moment_Nm=moment)[0]
    elif moment is None:
        q[off:] = static_deflection_planar(model.lengths_m, model.stiffness_Nm_per_rad, load_N)
    if q0 is not None:
        q = np.array(q0, dtype=float)
    data_g = None if pm_g is None else pm_g.createData()
    free = slice(off, None)

    k = model.stiffness_Nm_per_rad

    def norm(q: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        r, H = static_terms(model, q, load_N, pm_g, data_g, moment, extra)
        if spin_rad_s:
            h, dh_dq, _ = spin_terms(model, q, spin_rad_s)
            r, H = r + h, H + dh_dq
        return math.sqrt(float(r[free] @ r[free])), r, H

    def converged(q: np.ndarray, r: np.ndarray, rn: float, rel: float) -> bool:
        # relative to the larger of the spring and the load torques, as the planar statics
        kq = k * q[free]
        return rn <= rel * max(float(np.linalg.norm(kq)), float(np.linalg.norm(r[free] - kq)),
                               1e-300)

    rn, r, H = norm(q)
    for _ in range(max_iter):
        if converged(q, r, rn, rtol):
            return q, float(r[0]) if hub else 0.0
        try:
            d = -np.linalg.solve(H[free, free], r[free])
        except np.linalg.LinAlgError:
            break
        alpha = 1.0
        while alpha > 1e-6:
            qn = q.copy()
            qn[free] += alpha * d
            rn_new, r_new, H_new = norm(qn)
            if rn_new < rn:
                break
            alpha *= 0.5
        else:
            break
        q, rn, r, H = qn, rn_new, r_new, H_new
    # rounding can stall the last digits short of rtol: accept a residual near it
    if converged(q, r, rn, 100.0 * rtol):
        return q, float(r[0]) if hub else 0.0
    raise SolveError(f"plant equilibrium: no equilibrium under the load {load_N.tolist()} N "
                     f"and the gravity (residual {rn:.3g} N m)")
