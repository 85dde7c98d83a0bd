"""The Kirchhoff plate truth's modes read along lines x = const.

Edge averages and width-averaged section rotations, from the element's own basis at any point
(inside elements too).

A width average over the line x = x0 runs from y = -w(x0) to w(x0) in segments cut where the line
crosses the mesh's edges; inside a segment the field is one element's polynomial, which
Gauss-Legendre quadrature of ``LINE_GAUSS`` points integrates exactly (Argyris: a quintic value,
a quartic slope).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from skfem import Basis, Functional, LinearForm, asm

from ...member.geometry import Beam
from ..plate import plate_modes
from .fields import ModeFields, section_rotation_sign

__all__ = ["LINE_GAUSS", "probe_matrix", "line_average_matrix", "plate_mode_fields"]

LINE_GAUSS = 4


def probe_matrix(basis: Basis, x_m: np.ndarray, y_m: np.ndarray, d_dx: bool = False):
    """Sparse (points, DOFs) matrix giving a field's value (or d/dx, ``d_dx``) at the points.

    Like scikit-fem's ``Basis.probes`` (values only) but with the x derivative available; a
    point on an element edge takes one of the elements beside it (Argyris is C1 there).
    """
    x = np.atleast_1d(np.asarray(x_m, dtype=float))
    y = np.atleast_1d(np.asarray(y_m, dtype=float))
    cells = basis.mesh.element_finder(mapping=basis.mapping)(x, y)
    X = basis.mapping.invF(np.vstack([x, y])[:, :, None], tind=cells)
    data = []
    for k in range(basis.Nbfun):
        f = basis.elem.gbasis(basis.mapping, X, k, tind=cells)[0]
        data.append((f.grad[0] if d_dx else np.asarray(f))[:, 0])
    rows = np.tile(np.arange(x.size), basis.Nbfun)
    cols = basis.element_dofs[:, cells].ravel()
    return coo_matrix((np.ravel(data), (rows, cols)), shape=(x.size, basis.N)).tocsr()


def _line_rule(basis: Basis, x0: float, half_width: float) -> tuple[np.ndarray, np.ndarray]:
    """Points y (m) and weights (summing to 1) of the width average along x = x0."""
    p, f = basis.mesh.p, basis.mesh.facets
    x1, x2 = p[0, f[0]], p[0, f[1]]
    y1, y2 = p[1, f[0]], p[1, f[1]]
    hit = (np.minimum(x1, x2) <= x0) & (np.maximum(x1, x2) >= x0) & (x1 != x2)
    s = (x0 - x1[hit]) / (x2[hit] - x1[hit])
    cuts = np.concatenate([y1[hit] + s * (y2[hit] - y1[hit]), [-half_width, half_width]])
    cuts = np.unique(np.clip(cuts, -half_width, half_width))
    a, b = cuts[:-1], cuts[1:]
    keep = b - a > 1e-12 * half_width
    a, b = a[keep], b[keep]
    g, gw = np.polynomial.legendre.leggauss(LINE_GAUSS)
    y = (0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * g).ravel()
    w = (0.5 * (b - a)[:, None] * gw).ravel() / (2.0 * half_width)
    return y, w


def line_average_matrix(basis: Basis, x0_m: float, half_width_m: float, d_dx: bool = False):
    """Return the row vector (1, DOFs) of a field's width average along the line x = x0.

    Or of its x derivative's (``d_dx``), over ``|y| <= half_width`` (m).
    """
    y, w = _line_rule(basis, float(x0_m), float(half_width_m))
    P = probe_matrix(basis, np.full(y.size, float(x0_m)), y, d_dx)
    return (P.T @ w)[None, :]


@Functional
def _one(w):
    return 1.0 + 0.0 * w.x[0]


@Functional
def _x(w):
    return w.x[0]


@Functional
def _x2(w):
    return w.x[0] ** 2


@LinearForm
def _v(v, w):
    return v


@LinearForm
def _xv(v, w):
    return w.x[0] * v


def _half_width_over(beam: Beam, x: float) -> float:
    """Return the full width present at station x: at a width step, the wider side's."""
    return float(max(beam.half_width_at(x, "left"), beam.half_width_at(x, "right")))


def plate_mode_fields(beam: Beam, level: int, n_modes: int, element: str,
                      stations_m: np.ndarray) -> ModeFields:
    """Every input, output and inertia term of the plate truth's ``n_modes`` lowest modes.

    Parameters
    ----------
    beam : Beam
    level : int
        The truth's mesh level.
    n_modes : int
        Modes computed (the truth's count).
    element : {"argyris", "morley"}
        Morley is nonconforming: its slope jumps across edges and the width average is that of
        whichever element a point is found in.
    stations_m : ndarray, shape (a, 2)
        Actuator stations (x_a, x_b) in m, checked by the caller.

    Returns
    -------
    ModeFields
        Tip force spread uniformly over the free edge (as ``plate_static``); tip z read at the
        mid-surface point (L, 0) (as ``plate_static``); the modes at the tip corners
        (L, +-w(L)), where a corner force acts and a corner's z is read.
    """
    pm = plate_modes(beam, level, n_modes, element)
    basis, phi = pm.basis, pm.phi  # phi^T M phi = 1
    L = beam.length_m
    tip_in = line_average_matrix(basis, L, _half_width_over(beam, L)) @ phi
    tip_out = probe_matrix(basis, np.array([L]), np.array([0.0])) @ phi
    w_tip = float(beam.half_width_m[-1])  # the free edge's, as the chain's corner points
    corners = probe_matrix(basis, np.array([L, L]), np.array([w_tip, -w_tip])) @ phi
    st = np.asarray(stations_m, dtype=float).reshape(-1, 2)
    rows = [line_average_matrix(basis, x, _half_width_over(beam, x), d_dx=True)
            for x in st.ravel()]
    rot = section_rotation_sign() * (np.vstack(rows) @ phi if rows else np.zeros((0, phi.shape[1])))
    rho_h = beam.material.rho_kg_m3 * beam.uniform_thickness_m("the plate truth")
    return ModeFields(
        model=f"plate-{element}",
        omega_rad_s=pm.omega_rad_s,
        node_uz=pm.nodal_uz(),
        tip_force_per_sqrt_kg=np.ravel(tip_in),
        tip_z_per_sqrt_kg=np.ravel(tip_out),
        strain_per_sqrt_kg_m=rot[1::2] - rot[0::2],
        translation_sqrt_kg=rho_h * (asm(_v, basis) @ phi),
        moment_sqrt_kg_m=rho_h * (asm(_xv, basis) @ phi),
        mass_kg=rho_h * float(asm(_one, basis)),
        first_moment_kg_m=rho_h * float(asm(_x, basis)),
        second_moment_kg_m2=rho_h * float(asm(_x2, basis)),
        corner_per_sqrt_kg=np.asarray(corners),
    )
