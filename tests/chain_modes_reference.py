"""An independent reference of a chain's modes at its points: eigh and kinematics by hand.

The mass matrix is Pinocchio's CRBA of the chain at the straight pose (``pinocchio.crba``, not
the package's wrapper), the stiffness the diagonal of the springs; ``scipy.linalg.eigh`` solves
the pencil, mass-normalised. The points are the root, the nodes at s_j = l_0 + ... + l_{j-1}
and the tip at L; a rotation q_y about +y at node j moves a point at x > s_j by
(0, 0, -(x - s_j) q_y), one q_z about +z by (0, (x - s_j) q_z, 0), one q_x about the axis not
at all; the twist of the link from node p is the sum of the q_x at nodes 1..p.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import scipy.linalg


def reference_modes(model):
    """Return omega (rad/s, (k,)), displacement ((k, P, 3), m) and twist ((k, P), rad)."""
    M = pin.crba(model.pin_model, model.pin_model.createData(), np.zeros(model.pin_model.nq))
    M = np.triu(M) + np.triu(M, 1).T  # crba fills the upper triangle
    K = np.diag(np.asarray(model.stiffness_Nm_per_rad, dtype=float))
    w2, phi = scipy.linalg.eigh(K, M)
    lengths = np.asarray(model.lengths_m, dtype=float)
    n = lengths.size - 1
    s = np.cumsum(lengths)[:n]  # node stations, m
    x = np.r_[0.0, s, lengths.sum()]  # points: root, nodes, tip
    axes = list(model.spring_axes)
    disp = np.zeros((phi.shape[1], x.size, 3))
    twist = np.zeros((phi.shape[1], x.size))
    for c, a in enumerate(axes):
        node = c // len(model.axes.joint_order)
        arm = np.clip(x - s[node], 0.0, None)
        if a == "y":
            disp[:, :, 2] -= np.outer(phi[c], arm)
        elif a == "z":
            disp[:, :, 1] += np.outer(phi[c], arm)
        else:
            twist[:, node + 1:] += phi[c][:, None]
    return np.sqrt(w2), x, disp, twist


def same_up_to_sign(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return ``b`` with the sign that brings it closest to ``a`` (an eigenvector's is free)."""
    return b if np.sum((a - b) ** 2) <= np.sum((a + b) ** 2) else -b
