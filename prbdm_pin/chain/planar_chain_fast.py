"""One design's planar chain, for a member of one thickness, in one compiled call.

:func:`planar_chain_parts` returns what :func:`prbdm_pin.chain.sections.planar_sections`,
:func:`prbdm_pin.chain.stiffness.finite_segment_stiffness_unchecked`,
:func:`prbdm_pin.chain.planar_mass.chain_points` and
:func:`prbdm_pin.chain.planar_mass.planar_mass_matrices` return, the same numbers, from
:func:`.planar_chain_kernel.planar_chain` (a fit's inner loop); under a thickness or section
law it returns None and the caller takes those functions.
"""

from __future__ import annotations

import numpy as np

from ..member.geometry import Beam
from .compiled_entry import entry_point

__all__ = ["planar_chain_parts"]

_CHAIN = None


def planar_chain_parts(beam: Beam, lengths_m: np.ndarray, poses_rad: np.ndarray):
    """Return the sections, unit springs, mass matrices and points of one design, or None.

    Parameters
    ----------
    beam : Beam
        A member of one thickness (None is returned under a thickness or section law).
    lengths_m : ndarray (n+1,)
        Valid link lengths, m, float64.
    poses_rad : ndarray (m, n)
        Joint angles of the poses, rad, float64.

    Returns
    -------
    tuple or None
        ``(mass_kg, com_offset_m, inertia_yy_kg_m2, area_moment_m4)`` each (n+1,) as
        :func:`~prbdm_pin.chain.sections.planar_sections`; the finite-segment springs (n,),
        N m/rad; the mass matrices (m, n, n), kg m^2; ``(axes, joints, coms)`` as
        :func:`~prbdm_pin.chain.planar_mass.chain_points` of the design as a stack of one.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.chain.planar_chain_fast import planar_chain_parts
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> sec, K0, M, _ = planar_chain_parts(beam, np.array([0.2, 0.5, 0.3]), np.zeros((1, 2)))
    >>> K0.round(2)  # N m/rad: EI / span over [0, 0.45] and [0.45, 1]
    array([1898.15, 1553.03])
    >>> m, ell = float(sec[0][2]), 0.3  # kg, m: the tip link, alone on the last joint
    >>> round(float(M[0, 1, 1]), 6), round(m * (ell**2 / 3 + 0.01**2 / 12), 6)  # kg m^2
    (0.035335, 0.035335)
    """
    global _CHAIN
    if beam.section is not None or beam.thickness_law_m is not None:
        return None
    if _CHAIN is None:  # numba is imported on first use, not with the package
        from .planar_chain_kernel import planar_chain

        _CHAIN = entry_point(planar_chain)
    L = lengths_m[None]
    (m, n), nl = poses_rad.shape, lengths_m.size
    props = np.empty((12, 1, nl))
    K0 = np.empty((1, n))
    axes = np.empty((m, 2, nl))
    joints = np.empty((1, m, 2, n))
    coms = np.empty((1, m, 2, n))
    M = np.empty((1, m, n, n))
    t = beam.thickness_m
    _CHAIN(beam.x_m, beam.half_width_m, beam.length_m, beam.material.rho_kg_m3 * t,
           t**3 / 12.0, t * t / 12.0, beam.material.E_Pa * (2.0 * t**3 / 12.0), L, poses_rad,
           props, K0, axes, joints, coms, M)
    rows = props[:, 0]
    return (rows[3], rows[10], rows[11], rows[8]), K0[0], M[0], (axes, joints, coms)
