"""Derivatives of a spatial chain's frequencies by axis in the stations, springs and design.

Each axis block at the straight pose is a planar chain (:mod:`.spatial_modes`), so the planar
chain's derivatives apply block by block: with mass-normalised modes phi_k of the block and
distinct eigenvalues lam_k = omega_k^2, ``d lam_k = phi_k^T (dK - lam_k dM) phi_k``, the mass
term the change of the mode's kinetic energy (:mod:`.mode_energy`). Per block, what moves M:

- stations (lengths): the links' masses, centres of mass and the block's inertia
  (:func:`.sections_derivatives.planar_sections_gradient`, and
  :func:`.sections_derivatives.roll_yaw_inertia_gradient` for I_xx and I_zz), and the chain's
  geometry (a longer link carries every centre of mass beyond it away from the joints before
  it; none for torsion, whose block has no translation);
- design variables at fixed lengths: the same sections
  (:func:`.sections_design_derivatives.section_design_gradient`).

The springs of an axis enter its own block only: d lam_k / d k_j = phi_jk^2.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..member.design import Design
from ..member.geometry import Beam
from ..options.choices import MIN_FRACTION
from .chain_derivatives import frequency_gradients
from .mode_energy import section_frequency_gradients
from .sections_derivatives import (
    SectionGradient,
    planar_sections_gradient,
    roll_yaw_inertia_gradient,
)
from .sections_design_derivatives import SectionDesignGradient, section_design_gradient

__all__ = ["axis_section_gradient", "axis_frequency_gradients",
           "axis_frequency_design_gradient"]


def axis_section_gradient(beam: Beam, lengths_m: np.ndarray, axis: str,
                          planar: SectionGradient | None = None,
                          roll_yaw: tuple | None = None) -> SectionGradient:
    """Return the planar-chain sections of one axis block and their station derivatives.

    The result's ``inertia_yy_kg_m2`` and ``d_inertia_yy_kg_m`` hold the block's inertia
    (I_yy, I_zz or I_xx, kg m^2, and kg m per m of each station); for ``x`` the masses and
    their derivatives are zero (the torsion block has no translation).

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    axis : {"y", "z", "x"}
    planar : SectionGradient, optional
        ``planar_sections_gradient(beam, lengths_m)`` when already computed.
    roll_yaw : tuple, optional
        ``roll_yaw_inertia_gradient(beam, lengths_m, planar)`` when already computed.

    Returns
    -------
    SectionGradient
        As :func:`.sections_derivatives.planar_sections_gradient`, with the block's inertia.
    """
    L = np.asarray(lengths_m, dtype=float)
    sec = planar if planar is not None else planar_sections_gradient(beam, L)
    if axis == "y":
        return sec
    if axis not in ("x", "z"):
        raise ValueError(f"axis = {axis!r}: must be 'x', 'y' or 'z'")
    Ixx, Izz, dIxx, dIzz = roll_yaw if roll_yaw is not None else \
        roll_yaw_inertia_gradient(beam, L, sec)
    if axis == "z":
        return replace(sec, inertia_yy_kg_m2=Izz, d_inertia_yy_kg_m=dIzz)
    zero = np.zeros_like(sec.d_mass_kg_per_m)
    return replace(sec, mass_kg=np.zeros_like(sec.mass_kg), inertia_yy_kg_m2=Ixx,
                   d_mass_kg_per_m=zero, d_com_offset=zero, d_inertia_yy_kg_m=dIxx)


def axis_frequency_gradients(beam: Beam, lengths_m: np.ndarray,
                             stiffness_Nm_per_rad: np.ndarray, axis: str,
                             sections: SectionGradient | None = None
                             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return one axis block's squared frequencies and their station and spring derivatives.

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        The springs about ``axis``, one per node, N m/rad (held fixed when the stations move;
        a spring law chains through
        :func:`.spatial_stiffness_derivatives.axis_stiffness_gradient`).
    axis : {"y", "z", "x"}
    sections : SectionGradient, optional
        ``axis_section_gradient(beam, lengths_m, axis)`` when already computed.

    Returns
    -------
    lam : ndarray, shape (n,)
        omega^2 of the block, ascending, rad^2/s^2.
    d_station : ndarray, shape (n, n)
        d lam_k / d x_j at [k, j], rad^2/s^2 per m.
    d_stiffness : ndarray, shape (n, n)
        d lam_k / d k_j at [k, j], rad^2/s^2 per N m/rad (phi_jk^2).
    """
    L = np.asarray(lengths_m, dtype=float)
    sec = sections if sections is not None else axis_section_gradient(beam, L, axis)
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    lam, d_station, d_stiffness = frequency_gradients(L, sec, k, np.zeros((1, k.size)))
    return lam[0], d_station[0], d_stiffness[0]


def axis_frequency_design_gradient(beam: Beam, design: Design, lengths_m: np.ndarray,
                                   stiffness_Nm_per_rad: np.ndarray, axis: str,
                                   d_stiffness: np.ndarray | None = None,
                                   min_fraction: float = MIN_FRACTION,
                                   sections: SectionDesignGradient | None = None
                                   ) -> tuple[np.ndarray, np.ndarray]:
    """Return one axis block's frequencies and their design derivatives at fixed lengths.

    Parameters
    ----------
    beam : Beam
        ``design.beam_at(p)``.
    design : Design
        The design variables.
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m (held fixed).
    stiffness_Nm_per_rad : array_like, shape (n,)
        The springs about ``axis``, N m/rad.
    axis : {"y", "z", "x"}
    d_stiffness : array_like, shape (n, nv), optional
        The springs' derivatives per unit of each variable (N m/rad per unit), e.g. from
        :func:`.spatial_stiffness_derivatives.axis_stiffness_design_gradient`; default zero
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
        rad/s per SI unit of each variable.
    """
    if axis not in ("x", "y", "z"):
        raise ValueError(f"axis = {axis!r}: must be 'x', 'y' or 'z'")
    L = np.asarray(lengths_m, dtype=float)
    sec = sections if sections is not None else section_design_gradient(beam, design, L,
                                                                        min_fraction)
    inertia = {"x": (sec.inertia_xx_kg_m2, sec.d_inertia_xx_kg_m2),
               "y": (sec.inertia_yy_kg_m2, sec.d_inertia_yy_kg_m2),
               "z": (sec.inertia_zz_kg_m2, sec.d_inertia_zz_kg_m2)}[axis]
    mass, d_mass = sec.mass_kg, sec.d_mass_kg
    if axis == "x":  # no translation in the torsion block
        mass, d_mass = np.zeros_like(mass), np.zeros_like(d_mass)
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    lam, d_lam, d_k = section_frequency_gradients(
        L, mass, sec.com_offset_m, inertia[0], k, np.zeros((1, k.size)), d_mass,
        sec.d_com_offset_m, inertia[1])
    d_lam = d_lam[0]
    if d_stiffness is not None:
        d_lam = d_lam + d_k[0] @ np.asarray(d_stiffness, dtype=float)
    omega = np.sqrt(lam[0])
    return omega, d_lam / (2.0 * omega[:, None])
