"""The target of a fit in gravity: the 1D beam truth under its own weight.

Its frequencies are the member's about its sag under its weight
(:func:`prbdm_pin.truth.elastica_modes.elastica_gravity_modes`: the axial weight stiffens a
hanging member and softens a standing one, as in the prestressed beam; a transverse weight moves
them only as the sag grows) and its tip is the elastica's under the beam's tip force plus its
distributed weight (:func:`prbdm_pin.truth.elastica.elastica_static` with ``gravity_m_s2``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputTypeError
from ..member.geometry import Beam
from ..truth.self_weight import check_gravity
from .target import FitTarget

__all__ = ["gravity_target"]


def gravity_target(beam: Beam, gravity_m_s2, modes: int = 3,
                   n_elements: int = 100) -> FitTarget:
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
        Elements of the modal solve about the sag.

    Returns
    -------
    FitTarget
        Frequencies (rad/s) about the sag under the weight alone, the elastica tip (m) under
        the tip force and the weight (no static case when neither moves the tip: a weight
        along the member and no tip force), ``gravity_m_s2`` set, no ``truth_request``
        (``compute_truth`` has no gravity; the cache of a fit in gravity is not shared with
        it).

    Raises
    ------
    BeamInputError
        A bad gravity (naming it), or a member that buckles under its weight.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> target = pp.gravity_target(beam, [0.0, 0.0, -9.81], modes=2)
    >>> target.omega_truth_rad_s.shape, target.gravity_m_s2
    ((2,), array([ 0.  ,  0.  , -9.81]))
    """
    from ..truth.elastica import elastica_static
    from ..truth.elastica_modes import elastica_gravity_modes

    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r:.60}: must be a prbdm_pin.Beam")
    g = check_gravity(gravity_m_s2)
    omega, sag = elastica_gravity_modes(beam, g, None, modes, n_elements)
    F = np.asarray(beam.tip_force_N, dtype=float)
    tip = elastica_static(beam, F, gravity_m_s2=g)
    moved = bool(np.linalg.norm(tip.tip_displacement_m) > 0.0)
    load = " and its tip force" if np.any(F) else ""
    return FitTarget(
        omega_truth_rad_s=omega,
        tip_force_N=F,
        tip_position_m=tip.tip_position_m if moved else None,
        tip_displacement_m=tip.tip_displacement_m if moved else None,
        source=(f"beam in gravity {g.tolist()} m/s^2: modes about its sag of "
                f"{np.linalg.norm(sag.tip_displacement_m) / beam.length_m:.3g} L "
                f"({n_elements} elements), elastica under its weight{load}"),
        labels=("bending",) * omega.size,
        gravity_m_s2=g,
    )
