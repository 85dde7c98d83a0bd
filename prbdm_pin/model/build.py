"""``build_model``: a PRBDM of a beam from its link lengths and springs, on its support.

Validates the lengths and springs against the beam, builds the link sections and the
``pinocchio.Model`` of the chain (clamped, on a hub, or on a free-floating bus) and returns the
:class:`~prbdm_pin.model.prbdm_model.PrbdmModel`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..chain.layout import validate_lengths
from ..chain.sections import link_sections_unchecked
from ..chain.spring_checks import check_spatial_springs, check_springs
from ..chain.stiffness import validate_stiffness
from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.choices import MIN_FRACTION, Axes
from ..options.validate import check_axes, check_joints, check_type
from .hub import Hub, hub_chain
from .hub_check import warn_light_hub
from .pin_chain import pin_chain
from .supports import FreeBus, base_chain

if TYPE_CHECKING:
    from .prbdm_model import PrbdmModel

__all__ = ["build_model"]


def build_model(
    beam: Beam,
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    *,
    min_fraction: float = MIN_FRACTION,
    hub: Hub | None = None,
    axes: Axes | str = Axes.Y,
    support: Hub | FreeBus | None = None,
) -> PrbdmModel:
    """Build a PRBDM of ``beam`` with the given link lengths and joint springs.

    Parameters
    ----------
    beam : Beam
    lengths_m : array_like, shape (n+1,)
        Link lengths in m, n >= 1: summing to the beam length (relative 1e-9), each in
        [0.02 L, 0.98 L].
    stiffness_Nm_per_rad : array_like
        Joint spring stiffness, N m/rad (finite, > 0), one per joint and axis (n of them for
        the planar chain, n times the number of axes for a spatial one), node-major: node 1's
        springs in the order y, z, x (those in ``axes``), then node 2's, ...
        (``PrbdmModel.spring_axes``).
    min_fraction : float
        Lower bound on each link as a fraction of L (Eq. 15's 0.02). Fine reference chains
        (e.g. 32 equal segments with half segments at the ends) need a smaller value.
    hub : Hub, optional
        A rotating rigid hub the root is clamped to (see :class:`PrbdmModel`); default None,
        the beam clamped to the world.
    support : Hub or FreeBus, optional
        What holds the root: a Hub (as ``hub=``) or a :class:`~prbdm_pin.FreeBus`, a rigid bus
        floating freely (:mod:`prbdm_pin.model.supports`); default None, the clamp. Not with
        ``hub``.
    axes : {"y", "xy", "yz", "xyz"}
        The joint axes at each node (default ``"y"``: the planar chain, bending out of the
        plane). ``x`` adds torsion about the link axis, ``z`` bending in the plane; each axis
        has its own spring. A spatial node is successive revolute joints at one point, joined
        by massless links (:func:`prbdm_pin.model.pin_chain.node_links`).

    Returns
    -------
    PrbdmModel
        The chain with its springs (and hub).

    Raises
    ------
    BeamInputError
        Naming the offending field and value: lengths off the beam, more joints than the cap
        ``limits().max_joints`` (``PRBDM_MAX_JOINTS``), springs more than a factor 1e6 beyond
        the finite-segment springs E I / l the beam can have
        (:func:`prbdm_pin.validate_args.check_springs`).
    InputTypeError
        ``beam`` not a Beam, ``hub`` not a Hub, ``support`` not a Hub or FreeBus, lengths or
        springs not real numbers.

    Warns
    -----
    LightHubWarning
        A hub so light that it moves mode 1 by more than 25 % toward the pinned-free beam,
        where a model fitted to the clamped truth loses accuracy
        (:mod:`prbdm_pin.plant.hub_check` says how it is estimated).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])  # m, N m/rad
    >>> model.n_joints
    2
    >>> model.natural_frequencies().round(1)  # rad/s
    array([ 59. , 320.9])
    """
    check_type("beam", beam, Beam)
    if support is not None:
        check_type("support", support, (Hub, FreeBus), "a prbdm_pin.Hub, FreeBus or None")
        if hub is not None:
            raise BeamInputError("support: given with hub; pass one of them")
        if isinstance(support, Hub):
            hub, support = support, None
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    lengths.setflags(write=False)
    check_joints(lengths.size - 1)  # the command line's --joints cap (PRBDM_MAX_JOINTS)
    axes = check_axes(axes)
    n_axes = len(axes.joint_order)
    k = validate_stiffness(stiffness_Nm_per_rad, (lengths.size - 1) * n_axes)
    if axes.spatial:
        check_spatial_springs(beam, k, axes)
    else:
        check_springs(beam, k)  # within a factor 1e6 of what the beam's sections can give
    if hub is not None:
        check_type("hub", hub, Hub, "a prbdm_pin.Hub or None")
        if axes.spatial:
            raise BeamInputError(f"axes = {axes.value!r}: a hub carries the planar chain only "
                                 "(axes='y')")
    from .prbdm_model import PrbdmModel  # the class imports this module for its callers

    sections = link_sections_unchecked(beam, lengths)
    if hub is None:
        model, tip = pin_chain(sections, lengths, f"prbdm_{beam.name}", axes)
        clamped = PrbdmModel(beam, lengths, k, sections, model, tip, axes=axes)
        if support is None:
            return clamped
        full = base_chain(model, support, f"prbdm_{beam.name}_bus")
        out = PrbdmModel(beam, lengths, k, sections, full, full.getFrameId("tip"), axes=axes,
                         bus=support)
        out._cache["member"] = clamped
        return out
    model, tip = hub_chain(sections, lengths, hub, f"prbdm_{beam.name}_hub")
    out = PrbdmModel(beam, lengths, k, sections, model, tip, hub)
    warn_light_hub(out)  # mode 1 moved > 25 % toward the pinned-free beam
    return out
