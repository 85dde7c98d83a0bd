"""Dynamics of a PRBDM chain on Pinocchio: free functions in Pinocchio's style f(model, data, ...).

``pin_model`` is a ``pinocchio.Model`` of a serial chain of revolute joints about y (the model
builder's output); ``data`` is its workspace (``pin_model.createData()``), created once and reused;
stiffness is the diagonal of K in N m/rad. Mass matrices come from CRBA, frequencies and modes
from :mod:`.eigen`, tip kinematics from the frame Jacobian. The closed forms of the same chain
(fit's inner loop) are in :mod:`.planar`, the statics in :mod:`.statics`.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from .eigen import eig_scaled, modes_from_mass, one_chain_unchecked

__all__ = [
    "mass_matrix",
    "mass_matrices",
    "checked_stiffness",
    "natural_frequencies",
    "natural_frequencies_batch",
    "scaled_frequencies",
    "modes",
    "modal_damping",
    "tip_position",
    "tip_jacobian",
    "tip_kinematics",
    "tip_pose",
    "planar_lengths",
]


_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_F8 = np.dtype(np.float64)


def _all_finite(arr: np.ndarray) -> bool:
    # a ufunc and a reduction cost microseconds, as much as a kinematics pass of a short chain;
    # a Python loop over a short vector is cheaper
    if arr.size <= 32:
        return all(map(math.isfinite, arr.tolist()))
    return bool(np.isfinite(arr).all())


def _q(pin_model: pin.Model, q: np.ndarray | None) -> np.ndarray:
    n = pin_model.nq
    if q is None:
        return np.zeros(n)
    arr = np.asarray(q, dtype=float)
    if arr.shape != (n,):
        raise BeamInputError(f"q has shape {arr.shape}: must be ({n},) joint angles (rad)")
    if not _all_finite(arr):
        raise BeamInputError(f"q = {arr.tolist()}: must be finite (rad)")
    return arr


def mass_matrix(pin_model: pin.Model, data: pin.Data, q: np.ndarray | None = None) -> np.ndarray:
    """Joint-space mass matrix M(q) by CRBA, kg m^2, shape (n, n), symmetric.

    Pinocchio's C++ CRBA fills only the upper triangle; the Python binding returns the
    symmetrised matrix (tests check that it stays so).
    """
    return pin.crba(pin_model, data, _q(pin_model, q))


def mass_matrices(pin_model: pin.Model, data: pin.Data, Q: np.ndarray) -> np.ndarray:
    """Mass matrices at the poses in the rows of ``Q`` (rad), kg m^2, shape (m, n, n)."""
    Q = _poses(pin_model, Q)
    out = np.empty((Q.shape[0], pin_model.nv, pin_model.nv))
    crba = pin.crba
    for i in range(Q.shape[0]):
        out[i] = crba(pin_model, data, Q[i])
    return out


def _poses(pin_model: pin.Model, Q: np.ndarray) -> np.ndarray:
    Q = np.asarray(Q, dtype=float)
    n = pin_model.nq
    if Q.ndim != 2 or Q.shape[1] != n:
        raise BeamInputError(f"Q has shape {Q.shape}: must be (m, {n}) joint angles (rad)")
    if not np.all(np.isfinite(Q)):
        raise BeamInputError("Q: every joint angle must be finite (rad)")
    return Q


def checked_stiffness(k: np.ndarray, n: int, m: int | None = None) -> np.ndarray:
    """Return joint springs ``k`` (N m/rad) as a float array of shape (n,), or (m, n) with ``m``.

    Raises BeamInputError unless every spring is finite, > 0 and a normal double.
    """
    k = np.asarray(k, dtype=float)
    ok_shapes = [(n,)] if m is None else [(n,), (m, n)]
    if k.shape not in ok_shapes:
        raise BeamInputError(
            f"stiffness has shape {k.shape}: must be one of {ok_shapes} (N m/rad)"
        )
    bad = ~(np.isfinite(k) & (k >= np.finfo(float).tiny))
    if np.any(bad):
        i = np.unravel_index(int(np.flatnonzero(bad)[0]), k.shape)
        raise BeamInputError(f"stiffness[{', '.join(map(str, i))}] = {k[i]}: must be finite, > 0 "
                             "and a normal double (>= 2.2e-308)")
    return k


def natural_frequencies(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    q: np.ndarray | None = None,
    squared: bool = False,
) -> np.ndarray:
    """Natural frequencies at pose ``q`` (rad; default straight), rad/s ascending, shape (n,).

    ``squared=True`` returns omega^2 (rad^2/s^2), the quantity the paper's code compares.
    """
    k = checked_stiffness(stiffness_Nm_per_rad, pin_model.nv)
    return scaled_frequencies(pin_model, data, 1.0 / np.sqrt(k), q, squared)


def scaled_frequencies(
    pin_model: pin.Model,
    data: pin.Data,
    s: np.ndarray,
    q: np.ndarray | None = None,
    squared: bool = False,
) -> np.ndarray:
    """Natural frequencies at pose ``q`` (rad; default straight) from s = K^(-1/2), rad/s.

    As :func:`natural_frequencies` with the springs already checked and scaled (a model's
    own, ``s`` an ndarray in (N m/rad)^(-1/2), shape (n,)): a float64 pose of the right shape
    goes to CRBA unchecked and the result of the compiled solve is returned when it passes;
    any other case (a pose to convert or check, a spectrum the guard questions) takes the
    checked path, which raises what it raises.
    """
    # crba returns float64 (n, n), n = nq = nv for these chains: the unchecked call's types
    if type(q) is np.ndarray and q.dtype is _F8 and s.dtype is _F8 and q.shape == s.shape:
        # the compiled call refuses a non-finite q: the checked path below then names it
        w = one_chain_unchecked(pin.crba(pin_model, data, q), s, q, squared)
        if w is not None:
            return w
    return eig_scaled(mass_matrix(pin_model, data, q), s, squared)


def natural_frequencies_batch(
    pin_model: pin.Model,
    data: pin.Data,
    Q: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    squared: bool = False,
) -> np.ndarray:
    """Natural frequencies at many poses, rad/s ascending per row, shape (m, n).

    One CRBA per pose, then a single stacked symmetric eigensolve. ``stiffness_Nm_per_rad`` is
    (n,) for all poses or (m, n), one row per pose (e.g. one SCF per pose).
    """
    M = mass_matrices(pin_model, data, Q)
    k = checked_stiffness(stiffness_Nm_per_rad, pin_model.nv, M.shape[0])
    return eig_scaled(M, 1.0 / np.sqrt(k), squared)


def modes(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    q: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (rad/s, ascending) and mass-normalised mode shapes (columns of Phi).

    Phi satisfies Phi^T M Phi = I and Phi^T K Phi = diag(omega^2).
    """
    k = checked_stiffness(stiffness_Nm_per_rad, pin_model.nv)
    omega, Phi = modes_from_mass(mass_matrix(pin_model, data, q)[None], k)
    return omega[0], Phi[0]



def modal_damping(M: np.ndarray, Phi: np.ndarray, omega_rad_s: np.ndarray, xi: np.ndarray | float):
    """Modal damping matrix C = M Phi diag(2 xi omega) Phi^T M, N m s/rad.

    With mass-normalised Phi each mode gets the damping ratio ``xi`` exactly.
    """
    d = 2.0 * np.broadcast_to(np.asarray(xi, dtype=float), omega_rad_s.shape) * omega_rad_s
    MP = M @ Phi
    return (MP * d[None, :]) @ MP.T


def tip_position(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> np.ndarray:
    """World position of the tip frame, m, shape (3,) (joint kinematics plus one frame update)."""
    pin.forwardKinematics(pin_model, data, _q(pin_model, q))
    return pin.updateFramePlacement(pin_model, data, tip_frame_id).translation.copy()


def tip_pose(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> tuple[np.ndarray, np.ndarray]:
    """World position (m, (3,)) and rotation matrix (world from tip frame, (3, 3)) of the tip.

    The rotation's columns are the tip frame's axes in the world: column 0 the link axis, so a
    twist of the tip about it is read from columns 1 and 2.
    """
    pin.forwardKinematics(pin_model, data, _q(pin_model, q))
    M = pin.updateFramePlacement(pin_model, data, tip_frame_id)
    return M.translation.copy(), M.rotation.copy()


def tip_jacobian(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> np.ndarray:
    """World-aligned linear Jacobian of the tip point, m/rad, shape (3, n)."""
    J = pin.computeFrameJacobian(pin_model, data, _q(pin_model, q), tip_frame_id, _LWA)
    # the binding hands a one-column matrix back as a vector: keep (3, n) for n = 1 too
    return J[:3].reshape(3, pin_model.nv).copy()


def tip_kinematics(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> tuple[np.ndarray, np.ndarray]:
    """Tip position (m, (3,)) and world-aligned linear Jacobian (m/rad, (3, n)) in one pass.

    What statics needs: the frame Jacobian's forward kinematics leaves the joint placements in
    ``data``, so the tip placement costs one frame update more (no second kinematics pass, one
    input check).
    """
    J = pin.computeFrameJacobian(pin_model, data, _q(pin_model, q), tip_frame_id, _LWA)
    p = pin.updateFramePlacement(pin_model, data, tip_frame_id).translation.copy()
    return p, J[:3].reshape(3, pin_model.nv).copy()


def planar_lengths(pin_model: pin.Model, tip_frame_id: int, hub_any_axis: bool = False
                   ) -> np.ndarray:
    """Link lengths (m) of a serial chain of y-revolute joints laid out along x, shape (n+1,).

    With ``hub_any_axis`` a first joint named ``hub`` may turn about x or z instead (a hub
    model's layout, as a file reader needs it; the planar formulas need every joint about y).

    Raises BeamInputError when the model is not such a chain (the planar statics need it).
    """
    n = pin_model.njoints - 1
    out = np.empty(n + 1)
    for j in range(1, n + 1):
        kind = pin_model.joints[j].shortname()
        if hub_any_axis and j == 1 and pin_model.names[1] == "hub" and kind != "JointModelRY":
            # a hub may turn about world x or z too: its placement is still the origin
            if kind not in ("JointModelRX", "JointModelRZ"):
                raise BeamInputError("joint 'hub': its axis must be world x, y or z")
        elif pin_model.parents[j] != j - 1 or kind != "JointModelRY":
            raise BeamInputError(f"joint {pin_model.names[j]!r}: must be a serial RY joint")
        out[j - 1] = _along_x(pin_model.jointPlacements[j], pin_model.names[j])
    frame = pin_model.frames[tip_frame_id]
    if frame.parentJoint != n:
        raise BeamInputError(f"frame {frame.name!r}: the tip frame must sit on the last joint")
    out[n] = _along_x(frame.placement, frame.name)
    return out


def _along_x(M: pin.SE3, name: str) -> float:
    p = M.translation
    if not (np.allclose(M.rotation, np.eye(3), atol=1e-12) and abs(p[1]) + abs(p[2]) <= 1e-12):
        raise BeamInputError(f"placement of {name!r} = {p.tolist()}: must be a pure x offset")
    return float(p[0])
