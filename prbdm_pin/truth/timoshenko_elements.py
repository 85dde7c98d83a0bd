"""The Timoshenko beam elements of ``beam_timoshenko`` and their assembly (why these two: there).

Element matrices K = int E I theta'^2 + kappa G A (w' - theta)^2 dx and
M = int rho A w^2 + rho I theta^2 dx (w deflection, m; theta section rotation, rad), vectorised
over the elements; the global matrices have DOFs (w, theta) per node in order along x.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from .timoshenko_sections import SectionLaws

__all__ = ["ELEMENTS", "element_matrices", "assemble"]

_GX, _GW = np.polynomial.legendre.leggauss(6)
_GX = 0.5 * (_GX + 1.0)  # on [0, 1]
_GW = 0.5 * _GW
# 2-point Gauss for the quadratic element's shear (reduced integration)
_RX, _RW = np.polynomial.legendre.leggauss(2)
_RX = 0.5 * (_RX + 1.0)
_RW = 0.5 * _RW
ELEMENTS = ("quadratic", "interdependent")


def _shape(s: np.ndarray, h: np.ndarray, phi: np.ndarray):
    """Friedman-Kosmatka shape functions at fractions ``s`` (q,) of elements (e,) of length h.

    Returns Nw, dNw/dx, Nt, dNt/dx, each (e, q, 4), DOF order (w1, theta1, w2, theta2).
    """
    s = s[None, :]
    h = h[:, None]
    c = 1.0 / (1.0 + phi[:, None])
    p = phi[:, None]
    s2, s3 = s * s, s * s * s
    Nw = np.stack([c * (2 * s3 - 3 * s2 - p * s + 1 + p),
                   c * h * (s3 - (2 + p / 2) * s2 + (1 + p / 2) * s),
                   -c * (2 * s3 - 3 * s2 - p * s),
                   c * h * (s3 - (1 - p / 2) * s2 - (p / 2) * s)], axis=-1)
    dNw = np.stack([c * (6 * s2 - 6 * s - p) / h,
                    c * (3 * s2 - (4 + p) * s + 1 + p / 2),
                    -c * (6 * s2 - 6 * s - p) / h,
                    c * (3 * s2 - (2 - p) * s - p / 2)], axis=-1)
    Nt = np.stack([6 * c / h * (s2 - s),
                   c * (3 * s2 - (4 + p) * s + 1 + p),
                   -6 * c / h * (s2 - s),
                   c * (3 * s2 - (2 - p) * s)], axis=-1)
    dNt = np.stack([6 * c / h * (2 * s - 1) / h,
                    c * (6 * s - (4 + p)) / h,
                    -6 * c / h * (2 * s - 1) / h,
                    c * (6 * s - (2 - p)) / h], axis=-1)
    return Nw, dNw, Nt, dNt


def _fk_matrices(xs: np.ndarray, laws: SectionLaws):
    """Friedman-Kosmatka element matrices (e, 4, 4), DOFs (w1, theta1, w2, theta2)."""
    a, h = xs[:-1], np.diff(xs)
    mid = a + 0.5 * h
    phi = 12.0 * laws.EI_Nm2(mid) / (laws.kappaGA_N(mid) * h * h)
    Nw, dNw, Nt, dNt = _shape(_GX, h, phi)
    xq = a[:, None] + h[:, None] * _GX[None, :]
    wq = h[:, None] * _GW[None, :]
    gam = dNw - Nt
    K = (_gram(laws.EI_Nm2(xq) * wq, dNt, dNt) + _gram(laws.kappaGA_N(xq) * wq, gam, gam))
    M = _gram(laws.rhoA_kg_m(xq) * wq, Nw, Nw) + _gram(laws.rhoI_kg_m(xq) * wq, Nt, Nt)
    return K, M


def _quadratic_matrices(xs: np.ndarray, laws: SectionLaws):
    """Three-node Lagrange element matrices (e, 6, 6), DOFs (w, theta) at the ends and middle.

    Shear at the 2 reduced Gauss points: there the quadratic theta is replaced by its linear
    projection, the space of w', so a pure bending state has zero shear energy (no locking).
    """
    a, h = xs[:-1], np.diff(xs)

    def lagrange(s):
        N = np.stack([2 * (s - 0.5) * (s - 1), -4 * s * (s - 1), 2 * s * (s - 0.5)], -1)
        dN = np.stack([4 * s - 3, 4 - 8 * s, 4 * s - 1], -1)
        return N, dN

    def fields(s):
        N, dN = lagrange(s)
        z = np.zeros(N.shape[:-1] + (6,))
        Nw, Nt = z.copy(), z.copy()
        Nw[..., 0::2], Nt[..., 1::2] = N, N
        dNw, dNt = z.copy(), z.copy()
        dNw[..., 0::2], dNt[..., 1::2] = dN, dN
        # d/dx = d/ds / h per element
        return (np.broadcast_to(Nw, (h.size,) + Nw.shape), dNw[None] / h[:, None, None],
                np.broadcast_to(Nt, (h.size,) + Nt.shape), dNt[None] / h[:, None, None])

    Nw, dNw, Nt, dNt = fields(_GX)
    xq = a[:, None] + h[:, None] * _GX[None, :]
    wq = h[:, None] * _GW[None, :]
    K = _gram(laws.EI_Nm2(xq) * wq, dNt, dNt)
    M = _gram(laws.rhoA_kg_m(xq) * wq, Nw, Nw) + _gram(laws.rhoI_kg_m(xq) * wq, Nt, Nt)
    _, dNw2, Nt2, _ = fields(_RX)
    xr = a[:, None] + h[:, None] * _RX[None, :]
    gam = dNw2 - Nt2
    K = K + _gram(laws.kappaGA_N(xr) * h[:, None] * _RW[None, :], gam, gam)
    return K, M


def _gram(wq: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """sum_q wq A_qi B_qj per element: (e, q), (e, q, i), (e, q, j) -> (e, i, j)."""
    return np.einsum("eq,eqi,eqj->eij", wq, A, B)


def element_matrices(stations_m: np.ndarray, laws: SectionLaws, element: str = "quadratic"):
    """Stiffness and mass matrices of the elements between ``stations_m`` (m).

    K = int E I theta'^2 + kappa G A (w' - theta)^2 dx, M = int rho A w^2 + rho I theta^2 dx
    over the element's shape functions: (e, 6, 6) for ``"quadratic"`` (DOFs w, theta at the
    ends and the middle, in order along x), (e, 4, 4) for ``"interdependent"``.
    """
    xs = np.asarray(stations_m, dtype=float)
    if element == "quadratic":
        return _quadratic_matrices(xs, laws)
    if element == "interdependent":
        return _fk_matrices(xs, laws)
    raise BeamInputError(f"element = {element!r}: must be one of {ELEMENTS}")


def assemble(stations_m: np.ndarray, laws: SectionLaws, element: str):
    """Return K, M (CSR, N/m and kg in the DOF units) and the free DOFs (root clamped)."""
    import scipy.sparse as sp

    Ke, Me = element_matrices(stations_m, laws, element)
    e = np.arange(Ke.shape[0])
    per = Ke.shape[1]  # 4: nodes 0, 1 of each element; 6: nodes 0, 1, 2 (the middle one inside)
    step = per // 2 - 1
    first = 2 * step * e
    dofs = first[:, None] + np.arange(per)[None, :]
    rows = np.repeat(dofs, per, axis=1).ravel()
    cols = np.tile(dofs, (1, per)).ravel()
    n = 2 * (step * e.size + 1)
    K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))
    M = sp.csr_matrix((Me.ravel(), (rows, cols)), shape=(n, n))
    return K, M, np.arange(2, n)  # the root node's w and theta clamped


