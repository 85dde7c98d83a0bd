"""The kinematics and statics of a PRBDM's chain: tip, named points, static equilibrium.

A mixin of :class:`~prbdm_pin.model.prbdm_model.PrbdmModel`, which supplies ``pin_model``,
``tip_frame_id``, ``beam``, ``axes``, ``lengths_m``, ``stiffness_Nm_per_rad`` and the
workspace (``_workspace``, ``_no_hub``): every method takes an optional Pinocchio ``data``.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain import pin_dynamics as dyn
from ..chain.points import (
    point_frame,
    point_kinematics,
    point_offset_m,
    twist_angle,
    twist_jacobian,
)
from ..chain.spatial_statics import checked_wrench, spatial_static_deflection
from ..chain.statics import static_deflection_planar
from ..errors import BeamInputError

__all__ = ["ChainKinematics"]


class ChainKinematics:
    """Tip and point kinematics and the static equilibrium of a chain model."""

    def tip_position(self, q: np.ndarray | None = None, data: pin.Data | None = None
                     ) -> np.ndarray:
        """World position of the tip, m, shape (3,)."""
        return dyn.tip_position(self.pin_model, self._workspace(data), q, self.tip_frame_id)

    def tip_pose(self, q: np.ndarray | None = None, data: pin.Data | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
        """World position (m, (3,)) and rotation (world from tip frame, (3, 3)) of the tip."""
        return dyn.tip_pose(self.pin_model, self._workspace(data), q, self.tip_frame_id)

    def point_kinematics(self, point: str, q: np.ndarray | None = None,
                         data: pin.Data | None = None) -> tuple[np.ndarray, np.ndarray]:
        """World position (m, (3,)) and linear Jacobian (m/rad, (3, nv)) of a named point.

        ``point``: ``tip`` (the centre of the free end), ``tip_corner_left`` or
        ``tip_corner_right`` (at +/- the tip half-width along the tip link's y axis;
        :mod:`prbdm_pin.chain.points`). A model read from a URDF has no beam: its corners are
        refused.
        """
        if self.beam is None and point != "tip":
            raise BeamInputError(f"point = {point!r}: this model carries no beam, so no width")
        # the corners need a width: a section table has none and refuses by name
        w = 0.0 if self.beam is None or point == "tip" else float(
            self.beam.half_width_at(self.beam.length_m))
        qv = np.zeros(self.pin_model.nq) if q is None else np.asarray(q, dtype=float)
        return point_kinematics(self.pin_model, self._workspace(data), qv, self.tip_frame_id,
                                point_offset_m(point, w))

    def tip_jacobian(self, q: np.ndarray | None = None, data: pin.Data | None = None
                     ) -> np.ndarray:
        """World-aligned linear Jacobian of the tip point, m/rad, shape (3, n)."""
        return dyn.tip_jacobian(self.pin_model, self._workspace(data), q, self.tip_frame_id)

    def tip_frame_jacobian(self, q: np.ndarray | None = None, data: pin.Data | None = None
                           ) -> np.ndarray:
        """World-aligned Jacobian of the tip frame, shape (6, nv): linear (m/rad), angular (1).

        Rows 3..5 are the tip's angular velocity about the world x, y, z axes per joint rate.
        """
        qv = np.zeros(self.pin_model.nq) if q is None else np.asarray(q, dtype=float)
        J = pin.computeFrameJacobian(self.pin_model, self._workspace(data), qv,
                                     self.tip_frame_id, pin.LOCAL_WORLD_ALIGNED)
        return J.reshape(6, -1)  # the binding hands one column back as a vector

    def tip_twist(self, q: np.ndarray | None = None, data: pin.Data | None = None
                  ) -> tuple[float, np.ndarray]:
        """Return the tip twist (rad) and its gradient (rad/rad, (nv,)) at pose ``q``.

        The twist is the roll of the tip frame about the tip link's own axis
        (:func:`prbdm_pin.chain.points.twist_angle`): 0 on a planar chain.
        """
        d = self._workspace(data)
        J = self.tip_frame_jacobian(q, d)  # forward kinematics at q in d
        R = pin.updateFramePlacement(self.pin_model, d, self.tip_frame_id).rotation
        return twist_angle(R), twist_jacobian(R, J[3:])

    def tip_kinematics(
        self, q: np.ndarray | None = None, data: pin.Data | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Tip position (m, (3,)) and its linear Jacobian (m/rad, (3, n)), one kinematics pass."""
        return dyn.tip_kinematics(self.pin_model, self._workspace(data), q, self.tip_frame_id)

    def static_deflection(
        self, tip_force_N: np.ndarray, q0: np.ndarray | None = None, data: pin.Data | None = None,
        tip_moment_Nm: np.ndarray | None = None, point: str = "tip",
    ) -> tuple[np.ndarray, np.ndarray]:
        """Equilibrium under a dead force (N) at a tip point and a dead tip moment (N m).

        Returns the joint angles (rad) and the tip position (m); :meth:`tip_pose` of the angles
        gives the tip's rotation too. The force acts at ``point`` (``tip``, the centre of the
        free end, or a tip corner, :meth:`point_kinematics`), both in world axes. The planar
        chain under a force alone at the tip is solved in its plane
        (:func:`~prbdm_pin.chain.statics.static_deflection_planar`), a spatial chain, a moment
        or a corner by :func:`~prbdm_pin.chain.spatial_statics.spatial_static_deflection`.
        Raises SolveError when no equilibrium is found, BeamInputError for a bad load or point
        or a hub model (the hub would turn; :func:`prbdm_pin.linearize` holds it with a trim
        torque).
        """
        self._no_hub("a static equilibrium under a tip force alone")
        if tip_moment_Nm is not None:
            checked_wrench(tip_force_N, tip_moment_Nm)  # names tip_force or tip_moment
        if point != "tip":
            pm, pd, fid = self._point_model(point)
            q = spatial_static_deflection(pm, pd, self.stiffness_Nm_per_rad, fid, tip_force_N,
                                          tip_moment_Nm, q0)
            return q, self.tip_position(q, data)
        if self.axes.spatial or (tip_moment_Nm is not None and np.any(tip_moment_Nm)):
            d = self._workspace(data)
            q = spatial_static_deflection(self.pin_model, d, self.stiffness_Nm_per_rad,
                                          self.tip_frame_id, tip_force_N, tip_moment_Nm, q0)
            return q, self.tip_position(q, d)
        q = static_deflection_planar(
            self.lengths_m, self.stiffness_Nm_per_rad, tip_force_N, q0=q0
        )
        return q, self.tip_position(q, data)

    def _point_model(self, point: str) -> tuple[pin.Model, pin.Data, int]:
        """Return the model with a frame at ``point`` (built once), its workspace, the frame id."""
        key = ("point", point)
        if key not in self._cache:
            if self.beam is None:
                raise BeamInputError(f"point = {point!r}: this model carries no beam, so no "
                                     "width")
            off = point_offset_m(point, 0.0 if point == "tip" else float(
                self.beam.half_width_at(self.beam.length_m)))
            pm, fid = point_frame(self.pin_model, self.tip_frame_id, off)
            self._cache[key] = (pm, pm.createData(), fid)
        return self._cache[key]
