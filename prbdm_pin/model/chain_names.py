"""The names of a chain's joints and links, as the URDF, the MJCF and Pinocchio spell them."""

from __future__ import annotations

from ..options.choices import Axes

__all__ = ["joint_names", "node_links"]


def joint_names(n_joints: int, axes: Axes = Axes.Y) -> list[str]:
    """Return the spring joints' names in coordinate order: ``joint_j`` or ``joint_j_a``.

    A spatial node j has one revolute joint per axis a of :attr:`Axes.joint_order` (y, z, x).
    """
    if not axes.spatial:
        return [f"joint_{j}" for j in range(1, n_joints + 1)]
    return [f"joint_{j}_{a}" for j in range(1, n_joints + 1) for a in axes.joint_order]


def node_links(j: int, axes: Axes = Axes.Y) -> list[str]:
    """Return the child links of node j's joints: massless ``link_j_a`` ..., then ``link_j``.

    Successive revolute joints at one point need a link between them; those carry no inertia,
    so the mass matrix is the composite joint's.
    """
    order = axes.joint_order
    return [f"link_{j}_{a}" for a in order[:-1]] + [f"link_{j}"]
