"""The clamped 1D Euler-Bernoulli truth's modes as full Hermite DOF vectors, with slopes anywhere.

The plant needs deflections and slopes of exactly the modes the truth computed: they come from
the truth's own assembly and solver (``truth.beam.beam_modes``) on the same stations, and
``truth_modal_gains`` still refuses them unless their frequencies and shapes are the truth's.
"""

from __future__ import annotations

import numpy as np

from ...member.geometry import Beam
from ..beam import beam_modes, beam_stations
from .fields import ModeFields, section_rotation_sign

__all__ = ["BEAM_ELEMENTS", "beam_mode_fields", "hermite_slope"]

# the 1D truth's default element count (beam_modal, beam_static)
BEAM_ELEMENTS = 200


def hermite_slope(xs: np.ndarray, u: np.ndarray, ux: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Return du/dx at ``x`` (m) of cubic Hermite fields; shape (fields, len(x)).

    The fields have nodal values ``u`` and slopes ``ux`` (rows: fields) at ascending nodes
    ``xs`` (m).
    """
    e = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    h = xs[e + 1] - xs[e]
    s = (x - xs[e]) / h
    d00 = (6 * s**2 - 6 * s) / h
    d10 = 3 * s**2 - 4 * s + 1
    d01 = -d00
    d11 = 3 * s**2 - 2 * s
    return d00 * u[:, e] + d10 * ux[:, e] + d01 * u[:, e + 1] + d11 * ux[:, e + 1]


def beam_mode_fields(beam: Beam, n_modes: int, stations_m: np.ndarray,
                     n_elements: int = BEAM_ELEMENTS) -> ModeFields:
    """Every input, output and inertia term of the 1D truth's ``n_modes`` lowest modes.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Modes computed (the truth's count; fewer if the mesh has fewer DOFs).
    stations_m : ndarray, shape (a, 2)
        Actuator stations (x_a, x_b) in m, checked by the caller.
    n_elements : int
        As ``beam_modal``'s (the truth uses the default).

    Returns
    -------
    ModeFields
        Tip force acting at, and tip z read at, the tip node (as ``beam_static``).
    """
    xs = beam_stations(beam, n_elements)
    # the truth's own assembly and solver (truth.beam): the same modes, not a re-derivation
    _, basis, _, M, _, _, lam, phi, _ = beam_modes(beam, int(n_modes), n_elements, xs)
    u_dof, ux_dof = basis.nodal_dofs  # MeshLine keeps the ascending order of xs
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))
    u, ux = phi[u_dof].T, phi[ux_dof].T
    st = np.asarray(stations_m, dtype=float).reshape(-1, 2)
    rot = section_rotation_sign() * hermite_slope(xs, u, ux, st.ravel())  # (k, 2a)
    strain = (rot[:, 1::2] - rot[:, 0::2]).T
    r0 = np.zeros(basis.N)
    r0[u_dof] = 1.0  # the field 1: exact in the Hermite space
    r1 = np.zeros(basis.N)
    r1[u_dof], r1[ux_dof] = xs, 1.0  # the field x
    M0, M1 = M @ r0, M @ r1
    return ModeFields(
        model="beam",
        omega_rad_s=np.sqrt(lam),
        node_uz=u,
        tip_force_per_sqrt_kg=u[:, -1].copy(),
        tip_z_per_sqrt_kg=u[:, -1].copy(),
        strain_per_sqrt_kg_m=strain,
        translation_sqrt_kg=M0 @ phi,
        moment_sqrt_kg_m=M1 @ phi,
        mass_kg=float(r0 @ M0),
        first_moment_kg_m=float(r0 @ M1),
        second_moment_kg_m2=float(r1 @ M1),
    )
