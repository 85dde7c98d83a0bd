"""Damping of the plant: the package's damping forms, and their hub-model versions.

The damping matrix is built from M at the linearisation pose and the joint springs, as
:func:`prbdm_pin.simulate` builds it (the load and gravity stiffness do not enter it). Without a
hub it is :func:`prbdm_pin.simulation.damping.damping_matrix` itself. With a hub, the hub joint has
no spring
and the chain has a rigid mode at omega = 0; the ratios ``damping_ratio`` (one, or one per
flexible mode) go to the n flexible modes only and the rigid mode stays undamped:

- ``"modal"``: C = M Phi_f diag(2 xi_k omega_k) Phi_f^T M over the flexible modes Phi_f (the
  rigid mode is taken out exactly, :mod:`.hub`, so nothing divides by its zero frequency);
- ``"stiffness"``: C = beta K with beta = 2 xi_1 / omega_1, omega_1 the lowest flexible
  frequency; K's hub row is zero, so the rigid mode is undamped here too;
- ``"modal_fit"``: the diagonal beam-joint damping fitted to the flexible modes' ratios
  (:mod:`.modal_fit`), the hub's or bus's coordinates undamped;
- ``"eq5c"`` is per beam joint and has no hub version: refused.

A free bus (:mod:`prbdm_pin.model.supports`) is handled alike with its six rigid modes.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..model.hub import hub_modes
from ..model.supports import free_modes
from .damping import DAMPING_FORMS, damping_matrix, damping_ratios, spring_modal_damping

__all__ = ["plant_damping"]


def plant_damping(model, M: np.ndarray, damping_ratio: float | np.ndarray, kind: str
                  ) -> np.ndarray:
    """Return the damping matrix (N m s/rad, (nv, nv)) of ``model``.

    ``M`` is the mass matrix (kg m^2) at the linearisation pose; ``kind`` the form ("modal",
    "stiffness", "eq5c").
    """
    if kind not in DAMPING_FORMS:
        raise BeamInputError(f"damping = {kind!r}: must be one of {', '.join(DAMPING_FORMS)}")
    bus = getattr(model, "bus", None) is not None  # six free base coordinates, no spring
    if model.hub is None and not bus:
        if kind == "modal":  # the model's springs are checked positive: modal_damping's path
            return spring_modal_damping(M, model.stiffness_Nm_per_rad,
                                        damping_ratios(damping_ratio, model.n_springs))
        return damping_matrix(M, model.stiffness_matrix(), damping_ratio, kind)
    if kind == "eq5c":
        raise BeamInputError("damping = 'eq5c': the paper's per-joint form has no hub version; "
                             "use 'modal', 'stiffness' or 'modal_fit' with a hub")
    n, nf = model.n_springs, model.n_free
    xi = damping_ratios(damping_ratio, n)
    if kind == "modal_fit":
        from .modal_fit import modal_fit_damping

        return np.diag(modal_fit_damping(M, model.stiffness_Nm_per_rad, xi, nf)
                       .joint_damping_Nms_per_rad)
    omega, Phi = (free_modes if bus else hub_modes)(M, model.stiffness_Nm_per_rad)
    if kind == "stiffness":
        if np.any(xi != xi[0]):
            raise BeamInputError(f"damping_ratio = {xi.tolist()}: the stiffness form takes one "
                                 "ratio (the lowest flexible mode's)")
        return (2.0 * xi[0] / omega[nf]) * model.stiffness_matrix()
    MP = M @ Phi[:, nf:]
    C = (MP * (2.0 * xi * omega[nf:])) @ MP.T
    return 0.5 * (C + C.T)
