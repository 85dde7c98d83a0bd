"""A spatial chain taken as its own truth, for the spatial fit's tests.

Its modes come from one eigensolve of the whole (M, K) pencil (not the fit's per-axis blocks)
and are labelled by the axis that holds most of their kinetic energy; their mass-normalised z
amplitudes at the tip points come from the point Jacobians. Imported as
``from chain_truth import ...`` (pytest puts this folder on ``sys.path``); not a test module.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from prbdm_pin.fitting.mode_shapes import ModeShapes, chain_shapes
from prbdm_pin.fitting.target import FitTarget

__all__ = ["LABELS", "pencil_modes", "self_target"]

LABELS = {"y": "bending", "x": "torsion", "z": "in-plane"}
POINTS = ("tip", "tip_corner_left", "tip_corner_right")


def pencil_modes(model) -> tuple[np.ndarray, tuple[str, ...], np.ndarray]:
    """Return the chain's frequencies (rad/s), their labels and mass-normalised shapes."""
    M = model.mass_matrix()
    w2, phi = scipy.linalg.eigh(model.stiffness_matrix(), M)  # phi^T M phi = 1
    MP = M @ phi
    share = {a: np.einsum("ij,ij->j", phi[model.axis_index(a)], MP[model.axis_index(a)])
             for a in model.axes.joint_order}
    labels = tuple(LABELS[max(share, key=lambda a: share[a][i])] for i in range(w2.size))
    return np.sqrt(w2), labels, phi


def self_target(model, gains: bool = False, shapes: bool = False) -> FitTarget:
    """Return the target of every mode of ``model`` by kind (and its tip amplitudes and its
    deflection and twist along the span)."""
    w, labels, phi = pencil_modes(model)
    point_gains = tuple((p, model.point_kinematics(p)[1][2] @ phi) for p in POINTS) \
        if gains else None
    mode_shapes = None
    if shapes:
        x = np.linspace(0.0, model.beam.length_m, 25)[1:]
        along = {a: (chain_shapes(model.lengths_m, model.axis_index(a), phi, x, a).T
                     if a in model.axes.joint_order else np.zeros((w.size, x.size)))
                 for a in "yx"}
        mode_shapes = ModeShapes(x, along["y"], along["x"])
    return FitTarget(w[:1], np.zeros(3), all_omega_rad_s=w, all_labels=labels,
                     source="a spatial chain", point_gains=point_gains, mode_shapes=mode_shapes)
