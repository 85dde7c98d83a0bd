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
from .eigen import _SAFE_SCALE, COND_LIMIT

__all__ = ["planar_chain_parts", "planar_chain_evaluation_parts"]

_CHAIN = _EVALUATION = None


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


def planar_chain_evaluation_parts(beam: Beam, lengths_m: np.ndarray, poses_rad: np.ndarray,
                                  factors: np.ndarray, forces_xz_N: np.ndarray,
                                  starts_rad: np.ndarray, rtol: float = 1e-10,
                                  max_iter: int = 60, max_step_rad: float = 0.5):
    """Return :func:`planar_chain_parts` at one pose with its frequencies and equilibria, or None.

    One compiled call (:func:`.planar_chain_kernel.planar_chain_evaluation`) for a member of
    one thickness at one pose (None otherwise: the caller takes the separate functions).

    Parameters
    ----------
    beam, lengths_m, poses_rad
        As :func:`planar_chain_parts`; ``poses_rad`` (1, n).
    factors : ndarray (n,)
        Factors on the finite-segment springs (dimensionless), float64.
    forces_xz_N : ndarray (c, 2)
        Each load case's dead tip force, x and z, N, float64.
    starts_rad : ndarray (c, n)
        Each case's start of the descent, rad, float64.
    rtol, max_iter, max_step_rad
        As :func:`prbdm_pin.chain.statics.static_deflection_planar`.

    Returns
    -------
    tuple or None
        ``(sections, K0, K, M, points, omega, solved)``: :func:`planar_chain_parts`' four with
        the springs K = factors K0 (n,), N m/rad, after K0; ``omega`` (1, n), rad/s,
        ascending, or None where the spectrum's fast guard did not pass (the caller's
        :func:`prbdm_pin.fitting.evaluate.chain_frequencies` then decides and raises);
        ``solved`` one ``(q rad (n,), tip m (3,))`` per case, or None where the compiled
        descent did not converge or the case has no in-plane force (the caller's
        :func:`.planar_statics_fast.static_tip_warm` then answers). The load guard
        (:func:`.statics_guard.check_load`) is the caller's to run on every solved case.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.chain.planar_chain_fast import planar_chain_evaluation_parts
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> L, Q = np.array([0.5, 0.5]), np.zeros((1, 1))  # m, rad
    >>> sec, K0, K, M, _, w, solved = planar_chain_evaluation_parts(
    ...     beam, L, Q, np.ones(1), np.array([[0.0, -1.0]]), np.zeros((1, 1)))
    >>> round(float(w[0, 0]), 4), round(float(np.sqrt(K[0] / M[0, 0, 0])), 4)  # rad/s
    (72.2662, 72.2662)
    >>> q, tip = solved[0]  # rad, m: k q = F l cos q about the joint at 0.5 m
    >>> round(float(K[0] * q[0] - 0.5 * np.cos(q[0])), 12)  # N m
    0.0
    >>> round(float(tip[2]), 9), round(float(-0.5 * np.sin(q[0])), 9)  # m: the tip's z
    (-0.000292683, -0.000292683)
    """
    global _EVALUATION
    if beam.section is not None or beam.thickness_law_m is not None or poses_rad.shape[0] != 1:
        return None
    if _EVALUATION is None:  # numba is imported on first use, not with the package
        from .planar_chain_kernel import planar_chain_evaluation

        _EVALUATION = entry_point(planar_chain_evaluation)
    n, nl, c = poses_rad.shape[1], lengths_m.size, forces_xz_N.shape[0]
    props = np.empty((12, 1, nl))
    K0 = np.empty((1, n))
    K = np.empty(n)
    axes = np.empty((1, 2, nl))
    joints = np.empty((1, 1, 2, n))
    coms = np.empty((1, 1, 2, n))
    M = np.empty((1, 1, n, n))
    omega = np.empty(n)
    q = np.empty((c, n))
    tips = np.empty((c, 3))
    ok = np.empty(1 + c, dtype=bool)
    t = beam.thickness_m
    _EVALUATION(beam.x_m, beam.half_width_m, beam.length_m, beam.material.rho_kg_m3 * t,
                t**3 / 12.0, t * t / 12.0, beam.material.E_Pa * (2.0 * t**3 / 12.0),
                lengths_m[None], poses_rad, factors, forces_xz_N, starts_rad, float(rtol),
                int(max_iter), float(max_step_rad), COND_LIMIT, _SAFE_SCALE, props, K0, K,
                axes, joints, coms, M, omega, q, tips, ok)
    rows = props[:, 0]
    solved = [(q[i], tips[i]) if ok[1 + i] else None for i in range(c)]
    return ((rows[3], rows[10], rows[11], rows[8]), K0[0], K, M[0],
            (axes, joints, coms), omega[None] if ok[0] else None, solved)
