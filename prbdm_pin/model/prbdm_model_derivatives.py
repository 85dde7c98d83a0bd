"""The PRBDM's natural frequencies and their design derivatives at fixed link lengths.

They are the model's direct dependence on the planform, thickness and material.

The links' sections move with the design (:mod:`.section_design_gradients`) and change the
modes' kinetic energy (:func:`mode_energy.section_frequency_gradients`); springs that follow the
design too (the finite-segment law, ``finite_segment_design_gradient``) add
``phi_jk^2 dk_j/dp``.
"""

from __future__ import annotations

import numpy as np

from ..chain.mode_energy import section_frequency_gradients
from ..chain.sections_design_derivatives import SectionDesignGradient, section_design_gradient
from ..chain.stiffness import validate_stiffness
from ..errors import BeamInputError
from ..member.design import Design
from ..member.geometry import Beam
from ..options.choices import MIN_FRACTION

__all__ = ["frequency_design_gradient"]


def frequency_design_gradient(beam: Beam, design: Design, lengths_m: np.ndarray,
                              stiffness_Nm_per_rad: np.ndarray,
                              d_stiffness: np.ndarray | None = None,
                              min_fraction: float = MIN_FRACTION,
                              sections: SectionDesignGradient | None = None
                              ) -> tuple[np.ndarray, np.ndarray]:
    """Return the chain's straight-pose frequencies and their design derivatives at fixed lengths.

    The chain is cut from ``beam`` at ``lengths_m``; the derivatives are with respect to the
    variables of ``design``.

    Parameters
    ----------
    beam : Beam
        ``design.beam_at(p)``.
    design : Design
        The design variables.
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m (held fixed).
    stiffness_Nm_per_rad : array_like, shape (n,)
        Joint springs, N m/rad.
    d_stiffness : array_like, shape (n, nv), optional
        The springs' derivatives per unit of each variable (N m/rad per unit); default zero
        (springs held fixed).
    min_fraction : float
        Eq. 15's bound the lengths are checked against.
    sections : SectionDesignGradient, optional
        ``section_design_gradient(beam, design, lengths_m)`` when already computed.

    Returns
    -------
    omega : ndarray, shape (n,)
        rad/s, ascending.
    d_omega : ndarray, shape (n, nv)
        rad/s per unit of each variable.
    """
    sec = sections if sections is not None else section_design_gradient(beam, design,
                                                                         lengths_m, min_fraction)
    L = np.asarray(lengths_m, dtype=float)
    n = L.size - 1
    k = validate_stiffness(stiffness_Nm_per_rad, n)
    lam, d_lam, d_k = section_frequency_gradients(
        L, sec.mass_kg, sec.com_offset_m, sec.inertia_yy_kg_m2, k, np.zeros((1, n)),
        sec.d_mass_kg, sec.d_com_offset_m, sec.d_inertia_yy_kg_m2)
    d_lam = d_lam[0]
    if d_stiffness is not None:
        dk = np.asarray(d_stiffness, dtype=float)
        if dk.shape != (n, design.size):
            raise BeamInputError(f"d_stiffness has shape {dk.shape}: needs ({n}, {design.size})"
                                 " (one row per joint, one column per design variable)")
        d_lam = d_lam + d_k[0] @ dk
    omega = np.sqrt(lam[0])
    return omega, d_lam / (2.0 * omega[:, None])
