"""Where a chain's nodes are, and how its modes move them: the points every view draws.

A chain's points are its root (the frame ``link_0``), its nodes (the frames ``link_j`` at each
node's joints) and its tip: n + 2 points, joined by the rigid links. A mode's shape at those
points is the linear displacement per unit modal coordinate (Pinocchio's frame Jacobians at the
straight pose times the mode) and the twist of the link that starts at each point (the angular
Jacobian's world-x row: rotation about the link axis; the tip carries link n's).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from ..options.validate import check_type

__all__ = ["ChainModes", "check_model", "chain_frames", "chain_points", "chain_modes", "mode_kinds"]

AXIS_KINDS = {"y": "bending", "z": "in-plane", "x": "torsion"}


@dataclass(frozen=True, eq=False)
class ChainModes:
    """A chain's modes at its points (root, nodes, tip), at the straight pose.

    Attributes
    ----------
    omega_rad_s : ndarray, shape (k,)
        Natural frequencies, rad/s, ascending (a hub's rigid mode left out).
    points_m : ndarray, shape (P, 3)
        The points at the straight pose, m, world (P = n + 2).
    displacement_m : ndarray, shape (k, P, 3)
        Each mode's displacement of the points, m per unit modal coordinate (mass-normalised
        modes, kg^-1/2 m^-1 ... : q = phi eta with phi^T M phi = 1).
    twist_rad : ndarray, shape (k, P)
        Each mode's rotation about world x of the link starting at each point (the tip: link
        n's), rad per unit modal coordinate.
    kinds : tuple of str
        Each mode's kind by where its strain energy lies: ``"bending"`` (springs about y),
        ``"in-plane"`` (about z) or ``"torsion"`` (about x).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> modes = pp.chain_modes(model)
    >>> isinstance(modes, pp.ChainModes), modes.displacement_m.shape, modes.twist_rad.shape
    (True, (2, 4, 3), (2, 4))
    >>> modes.points_m[:, 0]  # m: the root, the two joints and the tip
    array([0. , 0.2, 0.7, 1. ])
    >>> modes.kinds, bool(np.allclose(modes.twist_rad, 0.0))  # a planar chain does not twist
    (('bending', 'bending'), True)
    """

    omega_rad_s: np.ndarray
    points_m: np.ndarray
    displacement_m: np.ndarray
    twist_rad: np.ndarray
    kinds: tuple[str, ...]

    @property
    def stations_m(self) -> np.ndarray:
        """The points' x, m (the distance along the span on a clamped chain)."""
        return self.points_m[:, 0]


def check_model(model) -> None:
    """Refuse anything but a PrbdmModel (InputTypeError naming ``model``)."""
    from ..model.prbdm_model import PrbdmModel

    check_type("model", model, PrbdmModel, "a prbdm_pin.PrbdmModel")


def chain_frames(model) -> list[int]:
    """Return the frame ids of the root, each node and the tip of ``model`` (n + 2 of them).

    Raises
    ------
    BeamInputError
        A model on a free bus (its member is ``model.member``).
    """
    check_model(model)
    if model.bus is not None:
        raise BeamInputError("model: on a free bus; pass model.member (the clamped member)")
    pm = model.pin_model
    return ([pm.getFrameId("link_0")]
            + [pm.getFrameId(f"link_{j}") for j in range(1, model.n_joints + 1)]
            + [model.tip_frame_id])


def chain_points(model, q: np.ndarray | None = None, data=None) -> np.ndarray:
    """Return the root, node and tip positions of ``model`` at pose ``q`` (rad), m, (P, 3).

    ``q`` may be (nq,) or a stack (s, nq) of poses, giving (s, P, 3).
    """
    frames = chain_frames(model)
    pm = model.pin_model
    d = pm.createData() if data is None else data
    Q = np.zeros(pm.nq) if q is None else np.asarray(q, dtype=float)
    if Q.ndim == 2:
        return np.stack([chain_points(model, row, d) for row in Q])
    pin.framesForwardKinematics(pm, d, Q)
    return np.array([d.oMf[f].translation for f in frames])


def mode_kinds(model, phi: np.ndarray) -> tuple[str, ...]:
    """Return each mode's kind (column of ``phi``): the axis holding most of its spring energy.

    A hub's coordinate has no spring; its share is not counted.
    """
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    springs = phi[model.n_free:]
    energy = k[:, None] * springs ** 2  # (n_springs, k)
    axes = np.array(model.spring_axes)
    out = []
    for col in energy.T:
        share = {a: float(col[axes == a].sum()) for a in set(model.spring_axes)}
        out.append(AXIS_KINDS[max(share, key=share.get)])
    return tuple(out)


def chain_modes(model, n_modes: int | None = None) -> ChainModes:
    """Return the first ``n_modes`` flexible modes of ``model`` at its points.

    Each mode's sign is chosen so that the largest value of what its kind moves (the z
    displacement of a bending mode, the y displacement of an in-plane one, the twist of a
    torsion mode) is positive: a drawing and a file agree on it.

    Parameters
    ----------
    model : PrbdmModel
        Clamped or on a hub (the hub's rigid mode is left out).
    n_modes : int, optional
        How many (default all).

    Returns
    -------
    ChainModes

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> modes = pp.chain_modes(model, n_modes=2)
    >>> modes.omega_rad_s.round(2), model.natural_frequencies().round(2)  # rad/s
    (array([ 58.96, 320.89]), array([ 58.96, 320.89]))
    >>> w = modes.displacement_m[:, :, 2]  # z at the root, joints and tip, m per modal unit
    >>> w[:, 0], bool(np.all(np.abs(w).argmax(axis=1) == 3))  # clamped root; largest at the tip
    (array([0., 0.]), True)
    >>> bool(np.all(w[:, 3] > 0))  # the sign: each bending mode's largest z positive
    True
    """
    frames = chain_frames(model)
    pm = model.pin_model
    d = pm.createData()
    omega, phi = model.modes()
    rigid = int(model.hub is not None)  # the hub's rigid mode, exactly 0 rad/s, first
    omega, phi = omega[rigid:], phi[:, rigid:]
    if n_modes is not None:
        if not (isinstance(n_modes, int) and 1 <= n_modes <= omega.size):
            raise BeamInputError(f"n_modes = {n_modes!r}: must be an integer in 1..{omega.size} "
                                 "(the chain's flexible modes)")
        omega, phi = omega[:n_modes], phi[:, :n_modes]
    q0 = np.zeros(pm.nq)
    pin.computeJointJacobians(pm, d, q0)
    pin.updateFramePlacements(pm, d)
    J = np.array([pin.getFrameJacobian(pm, d, f, pin.LOCAL_WORLD_ALIGNED) for f in frames])
    disp = np.einsum("pij,jk->kpi", J[:, :3, :], phi)  # (k, P, 3)
    twist = np.einsum("pj,jk->kp", J[:, 3, :], phi)  # (k, P)
    kinds = mode_kinds(model, phi)
    for m, kind in enumerate(kinds):
        # the quantity the kind moves (a torsion mode's points move by rounding only)
        ref = {"bending": disp[m, :, 2], "in-plane": disp[m, :, 1]}.get(kind, twist[m])
        if ref[np.argmax(np.abs(ref))] < 0.0:
            disp[m] *= -1.0
            twist[m] *= -1.0
    points = np.array([d.oMf[f].translation for f in frames])
    return ChainModes(omega, points, disp, twist, kinds)
