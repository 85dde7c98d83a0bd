"""PrbdmModel: a Pinocchio model of the link chain plus the joint springs it cannot hold.

``build_model`` is called inside optimisation loops, so it builds the ``pinocchio.Model`` by hand
through the Pinocchio API (:mod:`prbdm_pin.model.pin_chain`, no URDF rendering or parsing); the
hand-built model equals the one Pinocchio's URDF parser makes from ``model.urdf``, which is
rendered lazily on first access.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..chain import pin_dynamics as dyn
from ..chain.eigen import eig_scaled
from ..chain.sections import LinkSections
from ..chain.spatial_stiffness import spring_axes
from ..chain.stiffness import validate_stiffness
from ..errors import BeamInputError
from ..io.atomic import atomic_write_text
from ..member.geometry import Beam
from ..options.choices import Axes

# build_model lives in .build (it takes PrbdmModel lazily); re-exported for its many callers
from .build import build_model
from .hub import Hub, hub_frequencies, hub_modes
from .kinematics import ChainKinematics
from .supports import N_BASE, FreeBus, free_frequencies, free_modes
from .urdf import render_urdf

__all__ = ["PrbdmModel", "build_model", "validate_stiffness"]


@dataclass(frozen=True, eq=False)
class PrbdmModel(ChainKinematics):
    """A pseudo-rigid-body dynamic model: n + 1 rigid links, n revolute joints about y with springs.

    Attributes
    ----------
    beam : Beam or None
        The source beam (None for a model read from a URDF file).
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        Joint spring stiffness, N m/rad.
    sections : LinkSections
        Link rigid-body properties (from a URDF file: mass, COM and inertia as written there;
        ``area_moment_m4`` is NaN because a URDF does not carry it).
    pin_model : pinocchio.Model
        The chain; joint j + 1 of Pinocchio is our joint j. Gravity is zero (no gravity unless
        a user sets ``pin_model.gravity``).
    tip_frame_id : int
        The frame at the free end of link n.
    hub : Hub or None
        A rotating rigid hub at the root (:class:`prbdm_pin.model.hub.Hub`), or None for the
        clamped beam. With a hub, Pinocchio's velocity index 0 is the hub joint (no spring) and
        beam joint j is index j + 1: ``pin_model.nv == n_joints + 1``; :meth:`mass_matrix`,
        :meth:`stiffness_matrix`, the tip kinematics and the frequencies and modes cover all
        ``nv`` coordinates (frequencies: the hub's rigid mode, exactly 0, first). A hub model
        has no static equilibrium under a tip force (the hub would turn); its URDF carries
        the hub as the revolute joint ``hub``.
    actuators : tuple of StrainActuator
        The strain actuators the model's file records (:func:`load_urdf` reads them from the
        export record, :func:`prbdm_pin.read_model_json` from its fields); () otherwise. They
        are carried, not applied: pass them on, ``linearize(model, ...,
        actuators=model.actuators)``.
    bus : FreeBus or None
        A free-floating bus the root is clamped to (:mod:`prbdm_pin.model.supports`), or None.
        Its six base coordinates (x, y, z, yaw, pitch, roll; no springs) come first, the beam's
        springs follow: ``pin_model.nv == 6 + n_springs``; the frequencies start with the six
        rigid modes' exact zeros. :attr:`member` is the clamped chain: the member's kinematics
        relative to the bus.

    As in Pinocchio, the model describes and a ``pinocchio.Data`` holds the workspace: every
    method that computes takes ``data``. Without one it uses a built-in workspace made on first
    use, which is for one thread only; a thread or process of its own makes its workspace with
    :meth:`new_data` and passes it in (the fit and batch workers are processes that build their
    own models, so they share none).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> isinstance(model, pp.PrbdmModel)
    True
    >>> model.lengths_m, model.stiffness_Nm_per_rad
    (array([0.2, 0.5, 0.3]), array([2500., 1200.]))
    >>> round(float(model.sections.mass_kg.sum()), 4), round(beam.mass_kg, 4)  # kg
    (3.925, 3.925)
    """

    beam: Beam | None
    lengths_m: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    sections: LinkSections
    pin_model: pin.Model
    tip_frame_id: int
    hub: Hub | None = None
    actuators: tuple = ()
    axes: Axes = Axes.Y
    bus: FreeBus | None = None
    _cache: dict = field(default_factory=dict, init=False, repr=False)

    @property
    def n_joints(self) -> int:
        """Number of joint nodes n (the links less one); each has ``len(axes)`` springs."""
        return int(self.lengths_m.size) - 1

    @property
    def n_springs(self) -> int:
        """Number of spring coordinates (``pin_model.nv`` less the hub joint, if any).

        n for the planar chain, n times the number of axes for a spatial one (node-major:
        :meth:`spring_axes`).
        """
        return int(self.pin_model.nv) - self.n_free

    @property
    def n_free(self) -> int:
        """Number of coordinates without a spring: 1 with a hub, 6 with a free bus, else 0."""
        return (self.hub is not None) + N_BASE * (self.bus is not None)

    @property
    def member(self) -> PrbdmModel:
        """The member's clamped chain (itself without a bus): its kinematics on the bus."""
        return self if self.bus is None else self._cache["member"]

    @property
    def spring_axes(self) -> tuple[str, ...]:
        """The axis (``"y"``, ``"z"`` or ``"x"``) of every spring coordinate, node-major."""
        return spring_axes(self.axes, self.n_joints)

    def axis_index(self, axis: str) -> np.ndarray:
        """Return the indices of the springs about ``axis`` (one per node), int, shape (n,)."""
        return np.flatnonzero(np.array(self.spring_axes) == axis)

    @property
    def urdf(self) -> str:
        """The URDF string (rendered from ``urdf_templates/`` on first access, then cached)."""
        text = self._cache.get("urdf")
        if self.bus is not None:
            raise BeamInputError("urdf: a model on a free bus has no URDF export; export "
                                 "model.member (the clamped member)")
        if text is None:
            name = "prbdm" if self.beam is None else f"prbdm_{self.beam.name}"
            text = render_urdf(self.sections, self.lengths_m, self.stiffness_Nm_per_rad, name,
                               hub=self.hub, axes=self.axes)
            self._cache["urdf"] = text
        return text

    def write_urdf(self, path: str | os.PathLike) -> Path:
        """Write :attr:`urdf` to ``path`` atomically."""
        return atomic_write_text(path, self.urdf)

    def new_data(self) -> pin.Data:
        """Return a fresh Pinocchio workspace for this model."""
        return self.pin_model.createData()

    @property
    def default_data(self) -> pin.Data:
        """The built-in workspace the methods use when given no ``data`` (one thread only)."""
        d = self._cache.get("data")
        if d is None:
            d = self._cache["data"] = self.pin_model.createData()
        return d

    def _workspace(self, data: pin.Data | None) -> pin.Data:
        return self.default_data if data is None else data

    def _no_hub(self, what: str) -> None:
        if self.bus is not None:
            raise BeamInputError(f"bus = {self.bus!r:.60}: {what} is not defined for a model on "
                                 "a free bus; use model.member (the clamped member)")
        if self.hub is not None:
            raise BeamInputError(f"hub = {self.hub!r}: {what} is not defined for a model with "
                                 "a hub; build it without the hub")

    def stiffness_matrix(self) -> np.ndarray:
        """Return K = diag(stiffness), N m/rad, shape (nv, nv).

        With a hub the first row and column are zero (the hub joint has no spring), on a free
        bus the first six.
        """
        return np.diag(np.concatenate([np.zeros(self.n_free), self.stiffness_Nm_per_rad]))

    def mass_matrix(self, q: np.ndarray | None = None, data: pin.Data | None = None) -> np.ndarray:
        """M(q) by CRBA, kg m^2, shape (n, n) (default the straight pose)."""
        return dyn.mass_matrix(self.pin_model, self._workspace(data), q)

    @property
    def _s(self) -> np.ndarray:
        s = self._cache.get("s")
        if s is None:
            s = self._cache["s"] = 1.0 / np.sqrt(self.stiffness_Nm_per_rad)
        return s

    def natural_frequencies(
        self, q: np.ndarray | None = None, squared: bool = False, data: pin.Data | None = None
    ) -> np.ndarray:
        """Natural frequencies at pose ``q`` (rad), rad/s ascending (omega^2 if ``squared``)."""
        if self.bus is None and self.hub is None:  # the plain chain first: the common call
            return dyn.scaled_frequencies(self.pin_model, self._workspace(data), self._s, q,
                                          squared)
        if self.bus is not None:
            return free_frequencies(self.mass_matrix(q, data), self.stiffness_Nm_per_rad, squared)
        return hub_frequencies(self.mass_matrix(q, data), self.stiffness_Nm_per_rad, squared)

    def natural_frequencies_batch(
        self, Q: np.ndarray, stiffness: np.ndarray | None = None, squared: bool = False,
        data: pin.Data | None = None,
    ) -> np.ndarray:
        """Frequencies at the poses in the rows of ``Q`` (rad), rad/s, shape (m, n).

        ``stiffness`` (N m/rad) overrides the model's: (n,) for all poses or (m, n) per pose.
        """
        d = self._workspace(data)
        if self.bus is not None:
            raise BeamInputError("natural_frequencies_batch: not for a model on a free bus")
        if self.hub is not None:
            k = self.stiffness_Nm_per_rad if stiffness is None else \
                dyn.checked_stiffness(stiffness, self.n_joints, np.shape(Q)[0])
            return hub_frequencies(dyn.mass_matrices(self.pin_model, d, Q), k, squared)
        if stiffness is not None:
            return dyn.natural_frequencies_batch(self.pin_model, d, Q, stiffness, squared)
        return eig_scaled(dyn.mass_matrices(self.pin_model, d, Q), self._s, squared)

    def modes(
        self, q: np.ndarray | None = None, data: pin.Data | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (rad/s) and mass-normalised mode shapes (columns) at pose ``q``."""
        if self.bus is not None:
            return free_modes(self.mass_matrix(q, data), self.stiffness_Nm_per_rad)
        if self.hub is not None:
            return hub_modes(self.mass_matrix(q, data), self.stiffness_Nm_per_rad)
        return dyn.modes(self.pin_model, self._workspace(data), self.stiffness_Nm_per_rad, q)

    def with_stiffness(self, stiffness_Nm_per_rad: np.ndarray) -> PrbdmModel:
        """Return the same chain with other springs (shares ``pin_model``)."""
        k = validate_stiffness(stiffness_Nm_per_rad, self.n_springs)
        out = PrbdmModel(
            self.beam, self.lengths_m, k, self.sections, self.pin_model, self.tip_frame_id,
            self.hub, self.actuators, self.axes, self.bus,
        )
        if self.bus is not None:
            out._cache["member"] = self.member.with_stiffness(k)
        return out

