"""Pose-dependent joint stiffness: the paper parametrisation's springs in a time response."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError


@dataclass(frozen=True, eq=False)
class StiffnessSchedule:
    """Pose-dependent joint stiffness of the paper's parametrisation (equation 14: an SCF per pose).

    The pose sweep (Eqs. 10-11) puts every joint at the same angle theta_i; a general pose q is
    mapped to the mean absolute joint angle, and each joint's stiffness is interpolated linearly
    in it (held constant beyond the first and last pose). The spring torque is -K(q) q.

    Attributes
    ----------
    pose_angle_rad : ndarray, shape (m,)
        Joint angle theta_i of each sweep pose, strictly increasing, rad.
    stiffness_Nm_per_rad : ndarray, shape (m, n)
        Joint stiffness at each pose, N m/rad.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> schedule = pp.StiffnessSchedule(pose_angle_rad=[0.0, 0.5],
    ...                                 stiffness_Nm_per_rad=[[2500.0, 1200.0], [2600.0, 1250.0]])
    >>> schedule.stiffness_Nm_per_rad.shape  # (poses, joints)
    (2, 2)
    """

    pose_angle_rad: np.ndarray
    stiffness_Nm_per_rad: np.ndarray

    def __post_init__(self) -> None:
        """Check the shapes and values of the table (BeamInputError naming the field)."""
        th = np.asarray(self.pose_angle_rad, dtype=float).reshape(-1)
        k = np.asarray(self.stiffness_Nm_per_rad, dtype=float)
        if k.ndim != 2 or k.shape[0] != th.size or th.size < 1:
            raise BeamInputError(
                f"stiffness_schedule: stiffness shape {k.shape} must be (poses={th.size}, n)"
            )
        if not (np.all(np.isfinite(th)) and np.all(np.diff(th) > 0.0)):
            raise BeamInputError("stiffness_schedule.pose_angle_rad: must be finite and increasing")
        if not (np.all(np.isfinite(k)) and np.all(k > 0.0)):
            raise BeamInputError("stiffness_schedule.stiffness_Nm_per_rad: must be finite and > 0")
        object.__setattr__(self, "pose_angle_rad", th)
        object.__setattr__(self, "stiffness_Nm_per_rad", k)

    def at(self, q: np.ndarray) -> np.ndarray:
        """Joint stiffness (n,) at pose ``q``, N m/rad."""
        s = float(np.mean(np.abs(q)))
        th = self.pose_angle_rad
        if th.size == 1 or s <= th[0]:
            return self.stiffness_Nm_per_rad[0]
        if s >= th[-1]:
            return self.stiffness_Nm_per_rad[-1]
        i = int(np.searchsorted(th, s)) - 1
        w = (s - th[i]) / (th[i + 1] - th[i])
        return (1.0 - w) * self.stiffness_Nm_per_rad[i] + w * self.stiffness_Nm_per_rad[i + 1]
