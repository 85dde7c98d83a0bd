"""The resultant about the root of the loads of :mod:`prbdm_pin.model.loads`, per unit input.

What the root reaction (:mod:`prbdm_pin.model.reaction`) subtracts for a follower tip moment, a
distributed force and a base acceleration, in world axes about the root point p0 (the caller
turns it into the base frame):

- follower moment about the tip frame's axis k: no force, the moment R_tip e_k;
- distributed force along world e (N/m): link i's share F_i and first moment Q_i about its
  start p_i (:func:`~prbdm_pin.model.loads.link_resultants`) give the force e sum F_i and the
  moment sum (p_i - p0) x e F_i + (ex_i Q_i) x e, ex_i the link's axis: exact for rigid links;
- base acceleration along world e_k (m/s^2): the d'Alembert load -m a of every link, the force
  -m_tot e_k at the member's centre of mass c, moment (c - p0) x (-m_tot e_k). The reaction then
  holds the inertia of the base's motion: the member is carried along with it.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .loads import BASE_ACCELS, DISTRIBUTED_FORCES, FOLLOWER_MOMENTS, _link_frames, link_resultants

__all__ = ["WRENCH_INPUTS", "wrench_column"]

WRENCH_INPUTS = (*FOLLOWER_MOMENTS, *DISTRIBUTED_FORCES, *BASE_ACCELS)


def wrench_column(model, q: np.ndarray, base: str, idx: int | None, spans: tuple,
                  p0: np.ndarray, data: pin.Data | None = None) -> np.ndarray:
    """Return the applied (force, moment) per unit input ``base`` about ``p0``, world, (6,).

    Parameters
    ----------
    model : PrbdmModel
    q : ndarray (nv,)
        Pose, rad.
    base : str
        One of ``WRENCH_INPUTS``.
    idx : int or None
        The DistributedLoad index of ``distributed_force_*[i]`` (None: the whole beam, uniform).
    spans : tuple of DistributedLoad
        The spans ``idx`` refers to.
    p0 : ndarray (3,)
        The root point, world, m.

    Returns
    -------
    ndarray (6,)
        N and N m per unit input (N m, N/m or m/s^2).
    """
    pm = model.pin_model
    d = model.new_data() if data is None else data
    W = np.zeros(6)
    if base in FOLLOWER_MOMENTS:
        pin.framesForwardKinematics(pm, d, q)
        W[3:] = d.oMf[model.tip_frame_id].rotation[:, FOLLOWER_MOMENTS[base] - 3]
        return W
    if base in DISTRIBUTED_FORCES:
        e = np.eye(3)[DISTRIBUTED_FORCES[base]]
        share, moment = link_resultants(model.lengths_m, None if idx is None else spans[idx])
        pin.framesForwardKinematics(pm, d, q)
        for fid, F, Q in zip(_link_frames(model), share, moment, strict=True):
            if F == 0.0 and Q == 0.0:
                continue
            M = d.oMf[fid]
            W[:3] += F * e
            W[3:] += np.cross(M.translation - p0, F * e) + np.cross(Q * M.rotation[:, 0], e)
        return W
    e = np.eye(3)[BASE_ACCELS[base]]
    # the first moment of every body, the one fixed to the world (link 0) included:
    # pin.centerOfMass leaves the universe's body out
    pin.forwardKinematics(pm, d, q)
    m = 0.0
    mc = np.zeros(3)
    for i, inertia in enumerate(pm.inertias):
        m += inertia.mass
        mc += inertia.mass * d.oMi[i].act(inertia.lever)
    W[:3] = -m * e
    W[3:] = np.cross(mc - m * p0, -e)
    return W
