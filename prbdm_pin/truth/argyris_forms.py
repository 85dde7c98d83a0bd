"""Argyris element integrals of DOF vectors from the vertex coordinates alone (real or complex).

Shape derivatives need the plate's element integrals v^T K_e w, v^T M_e w of fixed DOF vectors
as functions of the element's vertex coordinates. This module builds the same quintic fields as
``ElementTriArgyrisLocal`` (the same DOF functionals, in the same scaled element-local
monomials) without a skfem mesh or basis: the monomial coefficients of the fields solve every
element's 21 x 21 DOF system with the DOF values as right-hand sides (no inverse, no basis
functions), and only what the plate forms need (values and Hessians at the quadrature points, or
values along an edge) is evaluated.

Every operation is analytic in the coordinates: lengths are square roots of sums of squares, the
Jacobian's sign is taken from its real part, and the local frame (centre, size) is taken from the
real part and held fixed (the fields do not depend on it, only the conditioning does). With
complex coordinates P + i tau V the imaginary part of a result divided by tau is its derivative
along the node velocity V, exact to rounding for a tiny tau (complex step).
"""

from __future__ import annotations

import numpy as np

from .plate_elements import monomial_exponents
from .plate_elements import monomial_table as plate_monomials

__all__ = ["EXPONENTS", "monomial_table", "argyris_coefficients", "argyris_plate_forms",
           "argyris_edge_integrals", "GAUSS_EDGE"]

# the quintic monomials xi^i eta^j, i + j <= 5
EXPONENTS = monomial_exponents(5)
# DOF functionals at each vertex (the element's order), then one normal derivative per edge
_VERTEX_DERIVATIVES = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
_EDGES = ((0, 1), (1, 2), (0, 2))  # scikit-fem's facet order for triangles
# 6-point Gauss-Legendre on [0, 1]: exact to degree 11 (a quintic trace times a constant load)
_g, _w = np.polynomial.legendre.leggauss(6)
GAUSS_EDGE = (0.5 * (_g + 1.0), 0.5 * _w)


def monomial_table(xi: np.ndarray, eta: np.ndarray,
                   derivatives: tuple[tuple[int, int], ...]) -> np.ndarray:
    """Return the derivatives of the Argyris monomials (``EXPONENTS``) at (xi, eta).

    Shape ``(*xi.shape, len(derivatives), 21)``; see ``plate_elements.monomial_table``.
    """
    return plate_monomials(EXPONENTS, xi, eta, derivatives)


def argyris_coefficients(v: np.ndarray, t: np.ndarray, c: np.ndarray):
    """Monomial coefficients of the Argyris fields with local DOF values ``c``.

    Parameters
    ----------
    v : ndarray, shape (2, 3, ne)
        Vertex coordinates of every element (m; real or complex).
    t : ndarray of int, shape (3, ne)
        The elements' global node indices (they orient the edge normals: from the lower to the
        higher index, as the element does).
    c : ndarray, shape (21, ne, m)
        Local DOF values (the element's DOF order) of m vectors.

    Returns
    -------
    a : ndarray, shape (ne, 21, m)
        Coefficients of the fields in the monomials of (x - centre) / size.
    centre : ndarray, shape (2, ne)
        Element centroids (m, real part).
    size : ndarray, shape (ne,)
        Longest edges (m, real part).
    """
    vr = v.real
    centre = vr.mean(axis=1)
    size = np.max([np.hypot(*(vr[:, a] - vr[:, b])) for a, b in _EDGES], axis=0)
    xi = (v - centre[:, None, :]) / size
    rows, scale = [], []
    for k in range(3):
        rows.append(monomial_table(xi[0, k], xi[1, k], _VERTEX_DERIVATIVES))
        scale += [size ** (dx + dy) for dx, dy in _VERTEX_DERIVATIVES]
    nt = np.arange(t.shape[1])
    for a, b in _EDGES:
        lo = np.where(t[a] < t[b], a, b)
        hi = np.where(t[a] < t[b], b, a)
        d = v[:, lo, nt] - v[:, hi, nt]
        length = np.sqrt(d[0] ** 2 + d[1] ** 2)
        mid = 0.5 * (xi[:, a] + xi[:, b])
        grad = monomial_table(mid[0], mid[1], ((1, 0), (0, 1)))  # (ne, 2, 21)
        rows.append(((d[1, :, None] * grad[:, 0] - d[0, :, None] * grad[:, 1])
                     / length[:, None])[:, None])
        scale.append(size)
    V = np.concatenate(rows, axis=1)  # (ne, functional, monomial)
    # the functionals act on monomials of the scaled coordinate: scale the DOF values to match
    rhs = np.moveaxis(c * np.stack(scale)[:, :, None], 1, 0)
    return np.linalg.solve(V, rhs), centre, size


def _local(centre: np.ndarray, size: np.ndarray, x: np.ndarray):
    """Scaled local coordinates (xi, eta) of points x (2, ne, nq)."""
    return (x[0] - centre[0][:, None]) / size[:, None], (x[1] - centre[1][:, None]) / size[:, None]


def _fields(a: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Fields (ne, nq, kinds, m) of coefficients a (ne, 21, m) from a table (ne, nq, kinds, 21)."""
    ne, nq, k, nm = table.shape
    return np.matmul(table.reshape(ne, nq * k, nm), a).reshape(ne, nq, k, -1)


def argyris_plate_forms(v: np.ndarray, a: np.ndarray, centre: np.ndarray, size: np.ndarray,
                        left: np.ndarray, right: np.ndarray, X: np.ndarray, W: np.ndarray):
    """Integrate the plate forms per element and vector pair (left[k], right[k]).

    The integrals are those of k : k, tr k tr k and the product of the fields (k the Hessian), as
    ``shape_forms.plate_element_forms``.

    Parameters
    ----------
    v : ndarray, shape (2, 3, ne)
        Vertex coordinates (m; real or complex).
    a, centre, size
        From ``argyris_coefficients``.
    left, right : ndarray of int, shape (p,)
        Indices of the vector pairs among the m vectors of ``a``.
    X, W : ndarray, shapes (2, nq) and (nq,)
        Quadrature on the reference triangle (0, 0), (1, 0), (0, 1).

    Returns
    -------
    k1, k2, mass : ndarray, shape (ne, p)
        Units m^-2, m^-2 and m^4 per unit DOF (the plate's bending form is
        D [(1 - nu) k1 + nu k2], its mass form rho t times ``mass``).
    """
    e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    x = v[:, 0][:, :, None] + e1[:, :, None] * X[0] + e2[:, :, None] * X[1]
    det = e1[0] * e2[1] - e1[1] * e2[0]
    dx = (np.sign(det.real) * det)[:, None] * W  # (ne, nq)
    xi, eta = _local(centre, size, x)
    f = _fields(a, monomial_table(xi, eta, ((0, 0), (2, 0), (1, 1), (0, 2))))
    f[:, :, 1:] /= (size ** 2)[:, None, None, None]
    fl, fr = f[..., left], f[..., right]  # (ne, nq, 4, p)
    dxm = dx[:, :, None]
    kk = fl[:, :, 1] * fr[:, :, 1] + fl[:, :, 3] * fr[:, :, 3] + 2.0 * fl[:, :, 2] * fr[:, :, 2]
    tt = (fl[:, :, 1] + fl[:, :, 3]) * (fr[:, :, 1] + fr[:, :, 3])
    return ((kk * dxm).sum(1), (tt * dxm).sum(1), (fl[:, :, 0] * fr[:, :, 0] * dxm).sum(1))


def argyris_edge_integrals(v: np.ndarray, a: np.ndarray, centre: np.ndarray, size: np.ndarray,
                           ends: np.ndarray) -> np.ndarray:
    """Integrate the fields along one edge of every element, m per unit DOF.

    Parameters
    ----------
    v, a, centre, size
        As in ``argyris_plate_forms``.
    ends : ndarray of int, shape (2, ne)
        The local vertices (0, 1 or 2) at the ends of every element's edge.

    Returns
    -------
    ndarray, shape (ne, m)
    """
    nt = np.arange(v.shape[2])
    p0, p1 = v[:, ends[0], nt], v[:, ends[1], nt]
    s, w = GAUSS_EDGE
    x = p0[:, :, None] + (p1 - p0)[:, :, None] * s
    xi, eta = _local(centre, size, x)
    f = _fields(a, monomial_table(xi, eta, ((0, 0),)))[:, :, 0]  # (ne, ng, m)
    length = np.sqrt((p1[0] - p0[0]) ** 2 + (p1[1] - p0[1]) ** 2)
    return length[:, None] * np.einsum("g,egm->em", w, f)
