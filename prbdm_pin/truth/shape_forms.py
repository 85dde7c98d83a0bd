"""Element integrals of given DOF vectors: the forms the truth gradients differentiate.

A shape derivative of a quadratic form v^T K(p) w with v, w fixed is the derivative of a sum
of element integrals over the elements whose nodes move with p. The functions here evaluate
those integrals element by element, without assembling any matrix: the plate's on a skfem
Argyris basis (the truth's own, at the design), the 1D beam's cubic Hermite ones from the
element ends (which the 1D sensitivities move). The plate's moved elements are integrated by
``argyris_forms`` from their vertex coordinates.
"""

from __future__ import annotations

import numpy as np
from skfem import Basis

__all__ = ["plate_element_forms", "hermite_forms", "GAUSS_1D"]

# 4-point Gauss-Legendre on [0, 1]: exact to degree 7, the 1D truth's mass integrand (linear
# rho A times two cubics), as scikit-fem's intorder=7 there
_g, _w = np.polynomial.legendre.leggauss(4)
GAUSS_1D = (0.5 * (_g + 1.0), 0.5 * _w)


def _tri_fields(fields, c: np.ndarray):
    """Values (nel, nq, m) and Hessians (2, 2, nel, nq, m) of local DOF values c (Nd, nel, m)."""
    V, H = fields
    return (np.einsum("ieq,iem->eqm", V, c, optimize=True),
            np.einsum("ijkeq,iem->jkeqm", H, c, optimize=True))


def plate_element_forms(basis: Basis, a: np.ndarray, b: np.ndarray | None = None):
    """Per element and vector pair: the integrals of k(a) : k(b), tr k(a) tr k(b) and a b.

    Parameters
    ----------
    basis : skfem Basis
        Argyris basis of the (copies) mesh.
    a, b : ndarray, shape (21, nel, m)
        Local DOF values of m vectors on every element (b defaults to a).

    Returns
    -------
    k1, k2, mass : ndarray, shape (nel, m)
        With D and nu the plate's bending form is D [(1 - nu) k1 + nu k2] (N m), its mass form
        rho t times ``mass``; k = hess of the field (1/m); units m^-2, m^-2 and m^4 per unit DOF.
    """
    fields = (np.stack([np.asarray(f[0]) for f in basis.basis]),
              np.stack([f[0].hess for f in basis.basis]))
    va, ha = _tri_fields(fields, a)
    vb, hb = (va, ha) if b is None else _tri_fields(fields, b)
    dx = basis.dx[:, :, None]
    kk = ha[0, 0] * hb[0, 0] + ha[1, 1] * hb[1, 1] + ha[0, 1] * hb[0, 1] + ha[1, 0] * hb[1, 0]
    tt = (ha[0, 0] + ha[1, 1]) * (hb[0, 0] + hb[1, 1])
    return ((kk * dx).sum(axis=1), (tt * dx).sum(axis=1), (va * vb * dx).sum(axis=1))


def hermite_forms(xa: np.ndarray, xb: np.ndarray, ei_q: np.ndarray, rhoa_q: np.ndarray,
                  a: np.ndarray, b: np.ndarray | None = None):
    """Integrate EI a'' b'' and rho A a b per element and vector pair.

    The fields are cubic Hermite fields on the elements [xa, xb] (m).

    Parameters
    ----------
    ei_q, rhoa_q : ndarray, shape (nel, 4)
        EI (N m^2) and rho A (kg/m) at the ``GAUSS_1D`` points of every element.
    a, b : ndarray, shape (4, nel, m)
        Local DOF values (u_a, u_x at a, u_b, u_x at b) of m vectors (b defaults to a).

    Returns
    -------
    k, mass : ndarray, shape (nel, m)
    """
    s, w = GAUSS_1D
    h = (xb - xa)[:, None]  # (nel, 1)
    # shape functions of (u_a, h u_x(a), u_b, h u_x(b)) in s and their second s-derivatives
    N = np.array([1 - 3 * s**2 + 2 * s**3, s - 2 * s**2 + s**3, 3 * s**2 - 2 * s**3,
                  -(s**2) + s**3])
    N2 = np.array([-6 + 12 * s, -4 + 6 * s, 6 - 12 * s, -2 + 6 * s])
    scale = np.stack([np.ones_like(h), h, np.ones_like(h), h])  # (4, nel, 1)

    def fields(c):
        cs = c * scale
        return (np.einsum("iq,iem->eqm", N, cs), np.einsum("iq,iem->eqm", N2, cs) / h[:, :, None]
                ** 2)

    va, da = fields(a)
    vb, db = (va, da) if b is None else fields(b)
    jw = (h * w)[:, :, None]
    return ((ei_q[:, :, None] * da * db * jw).sum(axis=1),
            (rhoa_q[:, :, None] * va * vb * jw).sum(axis=1))
