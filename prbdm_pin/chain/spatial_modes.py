"""A spatial chain's frequencies by axis at the straight pose, in closed form.

At the straight pose the axis blocks of the spatial chain's mass matrix do not couple (every
product of inertia that would couple them vanishes for a planform symmetric about x and a
section symmetric about its mid-plane; :mod:`prbdm_pin.fitting.spatial_fit`), and each block is
the mass matrix of a planar chain with the links' own masses and centres of mass and one inertia:

- y (out-of-plane bending): the planar chain itself, I_yy;
- z (in-plane bending): the same geometry turned into the plane, I_zz;
- x (torsion): the centres of mass lie on the axis, so no translation: no mass, I_xx
  (``M_jk = sum_(i >= max(j, k)) I_xx,i``).

So :func:`.planar_mass.planar_mass_matrices` at q = 0 gives every block without building a
``pinocchio.Model``; tests/chain/test_spatial_derivatives.py checks them against ``pin.crba``.
"""

from __future__ import annotations

import numpy as np

from ..member.geometry import Beam
from .eigen import modes_from_mass
from .planar_mass import planar_mass_matrices
from .sections import link_sections_unchecked

__all__ = ["AXIS_INERTIA", "axis_sections", "axis_mass_matrix", "axis_modes"]

AXIS_INERTIA = {"x": 0, "y": 1, "z": 2}  # the inertia tensor's diagonal entry of each axis


def axis_sections(beam: Beam, lengths_m: np.ndarray, axis: str
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the planar-chain sections of one axis block (see the module docstring).

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    axis : {"y", "z", "x"}

    Returns
    -------
    mass_kg, com_offset_m, inertia_kg_m2 : ndarray, shape (n+1,)
        Link masses (kg; zero for torsion), centre-of-mass distances from each link's start (m)
        and inertias about the centre of mass around ``axis`` (kg m^2).
    """
    if axis not in AXIS_INERTIA:
        raise ValueError(f"axis = {axis!r}: must be 'x', 'y' or 'z'")
    sec = link_sections_unchecked(beam, np.asarray(lengths_m, dtype=float))
    a = AXIS_INERTIA[axis]
    mass = np.zeros_like(sec.mass_kg) if axis == "x" else sec.mass_kg
    return mass, sec.com_m[:, 0] - sec.start_m, sec.inertia_com_kg_m2[:, a, a]


def axis_mass_matrix(beam: Beam, lengths_m: np.ndarray, axis: str) -> np.ndarray:
    """Return the straight-pose mass matrix block of one axis' joints, kg m^2, shape (n, n)."""
    L = np.asarray(lengths_m, dtype=float)
    mass, offset, inertia = axis_sections(beam, L, axis)
    return planar_mass_matrices(L, mass, offset, inertia, np.zeros((1, L.size - 1)))[0]


def axis_modes(beam: Beam, lengths_m: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
               axis: str) -> tuple[np.ndarray, np.ndarray]:
    """Return the frequencies and mass-normalised modes of one axis block at the straight pose.

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    stiffness_Nm_per_rad : ndarray, shape (n,)
        The springs about ``axis``, N m/rad, one per node.
    axis : {"y", "z", "x"}

    Returns
    -------
    omega : ndarray, shape (n,)
        rad/s, ascending.
    Phi : ndarray, shape (n, n)
        Mode shapes (rad per unit modal coordinate), Phi[joint, mode], Phi^T M Phi = I.
    """
    M = axis_mass_matrix(beam, lengths_m, axis)
    omega, Phi = modes_from_mass(M[None], np.asarray(stiffness_Nm_per_rad, dtype=float))
    return omega[0], Phi[0]
