"""The target of a fit in gravity: the 1D beam truth under its own weight.

Its frequencies are the prestressed beam's (:func:`prbdm_pin.truth.beam_gravity.beam_gravity_modal`:
the axial weight stiffens a hanging member and softens a standing one; a transverse weight
leaves them as they are, to first order in the sag) and its tip is the elastica's under the
beam's tip force plus its distributed weight (:func:`prbdm_pin.truth.elastica.elastica_static`
with ``gravity_m_s2``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputTypeError
from ..member.geometry import Beam
from ..truth.self_weight import check_gravity
from .target import FitTarget

__all__ = ["gravity_target"]


def gravity_target(beam: Beam, gravity_m_s2, modes: int = 3,
                   n_elements: int = 200) -> FitTarget:
    """Return the FitTarget of ``beam`` in gravity (the 1D beam truth).

    Parameters
    ----------
    beam : Beam
        The member; its ``tip_force_N`` (N) is the load case, under the weight as well.
    gravity_m_s2 : array_like (3,)
        Gravity, m/s^2, member axes (x from root to tip, g_y = 0).
    modes : int
        Bending frequencies to compute (>= 1).
    n_elements : int
        Hermite elements of the modal solve.

    Returns
    -------
    FitTarget
        Frequencies (rad/s) about the sag, the elastica tip (m) under the tip force and the
        weight (no static case when neither moves the tip: a weight along the member and no
        tip force), ``gravity_m_s2`` set, no ``truth_request`` (``compute_truth`` has no
        gravity; the cache of a fit in gravity is not shared with it).

    Raises
    ------
    BeamInputError
        A bad gravity (naming it), or a member that buckles under its weight.
    """
    from ..truth.beam_gravity import beam_gravity_modal
    from ..truth.elastica import elastica_static

    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r:.60}: must be a prbdm_pin.Beam")
    g = check_gravity(gravity_m_s2)
    modal = beam_gravity_modal(beam, g, modes, n_elements)
    F = np.asarray(beam.tip_force_N, dtype=float)
    tip = elastica_static(beam, F, gravity_m_s2=g)
    moved = bool(np.linalg.norm(tip.tip_displacement_m) > 0.0)
    load = " and its tip force" if np.any(F) else ""
    return FitTarget(
        omega_truth_rad_s=modal.omega_rad_s,
        tip_force_N=F,
        tip_position_m=tip.tip_position_m if moved else None,
        tip_displacement_m=tip.tip_displacement_m if moved else None,
        source=(f"beam in gravity {g.tolist()} m/s^2: prestressed Hermite beam "
                f"({modal.mesh_level} elements), elastica under its weight{load}"),
        labels=("bending",) * modal.omega_rad_s.size,
        gravity_m_s2=g,
    )
