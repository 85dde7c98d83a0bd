"""Shape derivatives of the plate's element integrals by complex step on the moving mesh.

A planform variable p_j moves the truth's mesh nodes with the planform (``morph``). The map is
affine in every design variable, so the node velocity V_j = dP/dp_j is a central difference of
the map, exact to rounding. The derivative of a form v^T K(p) w with fixed DOF vectors is the
sum over the elements with a moving node of Im I_e(P + i tau V_j) / tau, with I_e the element
integral built from the vertex coordinates (``argyris_forms``): exact to rounding (no truncation
error, no subtraction), one complex evaluation per moved element and variable, all variables'
moved elements in batches.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import Basis

from ..member.design import Design
from .argyris_forms import argyris_coefficients, argyris_edge_integrals, argyris_plate_forms
from .derivative_rules import COMPLEX_STEP, VELOCITY_STEP
from .morph import morph_plane

__all__ = ["PlateFormDerivatives", "node_velocities", "plate_form_derivatives"]

# moved element rows per batch (bounds the memory of the quadrature tables)
BATCH = 2048
# the two local vertices of the edge opposite local vertex k (tip edges)
_OPPOSITE = np.array([[1, 0, 0], [2, 2, 1]])


@dataclass(frozen=True, eq=False)
class PlateFormDerivatives:
    """Derivatives of the element-integral sums with respect to planform variables.

    Attributes
    ----------
    k1, k2, mass : ndarray, shape (rows, pairs)
        d/dp_j of the sums of ``argyris_plate_forms``' k1 (m^-2), k2 (m^-2) and mass (m^4) per
        unit DOF, per unit of the variable.
    tip_edge : ndarray, shape (rows,)
        d/dp_j of the integral of the edge vector's field along the tip edge x = L (m per unit
        DOF, per unit of the variable); zeros without an edge vector.
    d_tip_half_width : ndarray, shape (rows,)
        d w(L) / dp_j (m per unit of the variable).
    """

    k1: np.ndarray
    k2: np.ndarray
    mass: np.ndarray
    tip_edge: np.ndarray
    d_tip_half_width: np.ndarray


def node_velocities(design: Design, row: int, p: np.ndarray) -> tuple[np.ndarray, float]:
    """Return the node velocities dP/dp_row and d w(L) / dp_row (m per unit of the variable).

    The nodes ``p`` (2, N) are those of ``design.beam``'s mesh, moving with the planform.
    """
    beam = design.beam
    h = VELOCITY_STEP * design.scales[row]
    e = np.zeros(design.size)
    e[row] = h
    hi, lo = design.beam_at(design.values + e), design.beam_at(design.values - e)
    vel = (morph_plane(beam, hi, p) - morph_plane(beam, lo, p)) / (2.0 * h)
    L = beam.length_m
    return vel, (hi.half_width_at(L) - lo.half_width_at(L)) / (2.0 * h)


def plate_form_derivatives(design: Design, rows: list[int], basis: Basis, vectors: np.ndarray,
                           left: np.ndarray, right: np.ndarray,
                           edge_vector: int | None = None) -> PlateFormDerivatives:
    """Shape derivatives of the plate forms of fixed DOF vectors on the truth's mesh.

    Parameters
    ----------
    design : Design
        The design variables at ``design.beam``, whose mesh is ``basis.mesh``.
    rows : list of int
        The planform variables (half-widths, stations) among ``design``'s.
    basis : skfem Basis
        The truth's Argyris basis (its DOF numbering and quadrature are used).
    vectors : ndarray, shape (ndofs, m)
        Global DOF vectors (fixed).
    left, right : ndarray of int
        The vector pairs of the forms (indices into ``vectors``' columns).
    edge_vector : int, optional
        A vector whose integral along the tip edge is also differentiated.

    Returns
    -------
    PlateFormDerivatives
    """
    mesh = basis.mesh
    t, dofs = mesh.t, basis.element_dofs
    L = design.beam.length_m
    elements, owner, moves = [], [], []
    d_w = np.zeros(len(rows))
    for k, row in enumerate(rows):
        vel, d_w[k] = node_velocities(design, row, mesh.p)
        el = np.flatnonzero(np.any(vel != 0.0, axis=0)[t].any(axis=0))
        elements.append(el)
        owner.append(np.full(el.size, k))
        moves.append(vel[:, t[:, el]])
    el, owner, moves = np.concatenate(elements), np.concatenate(owner), np.concatenate(moves, 2)
    at_tip = np.abs(mesh.p[0] - L) < 1e-9 * L
    out = [np.zeros((len(rows), len(left))) for _ in range(3)]
    edge = np.zeros(len(rows))
    for s in range(0, el.size, BATCH):
        e, who = el[s:s + BATCH], owner[s:s + BATCH]
        v = mesh.p[:, t[:, e]] + 1j * COMPLEX_STEP * moves[:, :, s:s + BATCH]
        a, centre, size = argyris_coefficients(v, t[:, e], vectors[dofs[:, e]])
        for acc, form in zip(out, argyris_plate_forms(v, a, centre, size, left, right, basis.X,
                                                      basis.W), strict=True):
            np.add.at(acc, who, form.imag)
        if edge_vector is None:
            continue
        on_tip = at_tip[t[:, e]]
        tip = np.flatnonzero(on_tip.sum(axis=0) == 2)
        if tip.size:
            ends = _OPPOSITE[:, np.argmin(on_tip[:, tip], axis=0)]
            g = argyris_edge_integrals(v[:, :, tip], a[tip][:, :, [edge_vector]],
                                       centre[:, tip], size[tip], ends)
            np.add.at(edge, who[tip], g[:, 0].imag)
    k1, k2, mass = (acc / COMPLEX_STEP for acc in out)
    return PlateFormDerivatives(k1=k1, k2=k2, mass=mass, tip_edge=edge / COMPLEX_STEP,
                                d_tip_half_width=d_w)
