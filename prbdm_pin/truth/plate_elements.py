"""Argyris and Morley plate triangles whose bases are built in scaled element-local coordinates.

scikit-fem's ``ElementTriArgyris`` builds each element's basis by inverting a 21 x 21 matrix of
monomials evaluated in global coordinates. With elements of size h at distance ~1 m from the
origin the columns scale like h^k and the matrix becomes singular to working precision on fine
meshes (condition ~1e17): frequencies come out silently wrong and change when the mesh is
translated. The elements here evaluate the monomials in element-local coordinates
xi = (x - x_c) / h (centroid x_c, longest edge h), where the matrix is well conditioned for any
element position and size, and build all elements' bases at once with batched numpy.
"""

from __future__ import annotations

import numpy as np
from skfem import MeshTri
from skfem.element import ElementGlobal
from skfem.element.discrete_field import DiscreteField
from skfem.refdom import RefTri

__all__ = ["ElementTriArgyrisLocal", "ElementTriMorleyLocal", "PLATE_ELEMENTS"]


def monomial_exponents(deg: int) -> np.ndarray:
    """Return the exponents (i, j) of the monomials x^i y^j of total degree at most ``deg``."""
    return np.array([(i, j) for i in range(deg + 1) for j in range(deg + 1) if i + j <= deg])


def monomial_table(exps: np.ndarray, x: np.ndarray, y: np.ndarray,
                   derivatives: tuple[tuple[int, int], ...]) -> np.ndarray:
    """Return ``d^(dx+dy)/dx^dx dy^dy`` of every monomial x^i y^j of ``exps`` at (x, y).

    Real or complex coordinates (dimensionless); one (dx, dy) per entry of ``derivatives``;
    shape ``(*x.shape, len(derivatives), len(exps))``.
    """
    i, j = exps[:, 0], exps[:, 1]
    xp = [np.ones_like(x)]
    yp = [np.ones_like(y)]
    for _ in range(int(exps.max())):
        xp.append(xp[-1] * x)
        yp.append(yp[-1] * y)
    xp, yp = np.stack(xp, axis=-1), np.stack(yp, axis=-1)
    out = np.empty((*np.shape(x), len(derivatives), i.size), dtype=np.result_type(x, y))
    for k, (dx, dy) in enumerate(derivatives):
        # falling factorials i (i - 1) ... (i - dx + 1), zero where the derivative vanishes
        coef = np.ones(i.size)
        for f in range(dx):
            coef *= i - f
        for f in range(dy):
            coef *= j - f
        coef[(i < dx) | (j < dy)] = 0.0
        o = out[..., k, :]
        np.multiply(xp[..., np.maximum(i - dx, 0)], yp[..., np.maximum(j - dy, 0)], out=o)
        o *= coef
    return out


def _monomials(exps: np.ndarray, x: np.ndarray, y: np.ndarray, dx: int, dy: int) -> np.ndarray:
    """Return one derivative of every monomial at (x, y), shape ``(N, *x.shape)``."""
    return np.moveaxis(monomial_table(exps, x, y, ((dx, dy),))[..., 0, :], -1, 0)


class _LocalScaledGlobalTri(ElementGlobal):
    """A triangle defined by its DOF functionals, built in scaled local coordinates.

    Subclasses set ``maxdeg``, ``vertex_derivatives`` (the derivative multi-indices taken at every
    vertex) and have one normal-derivative DOF at every edge midpoint. The global DOF layout
    (nodal, then facet) is scikit-fem's, so ``Basis``, ``asm`` and ``get_dofs`` work unchanged.
    Element objects cache per-mesh state: use a new element object for every mesh.
    """

    refdom = RefTri
    facet_dofs = 1
    vertex_derivatives: tuple[tuple[int, int], ...] = ()

    def __init__(self) -> None:
        self._exps = monomial_exponents(self.maxdeg)
        self._mesh_state = None
        self._eval_cache = None

    # -- per-mesh coefficients ------------------------------------------------------------------
    def _state(self, mesh: MeshTri):
        if self._mesh_state is not None and self._mesh_state[0] is mesh:
            return self._mesh_state[1:]
        p, t = mesh.p, mesh.t
        v = p[:, t]  # (2, 3, nt)
        centre = v.mean(axis=1)
        edges = ((0, 1), (1, 2), (0, 2))  # scikit-fem's facet order for triangles
        lengths = np.stack([np.linalg.norm(v[:, a] - v[:, b], axis=0) for a, b in edges])
        h = lengths.max(axis=0)
        xi = (v - centre[:, None, :]) / h  # (2, 3, nt), |xi| <= 1
        rows = []
        scale = []
        for k in range(3):
            for dx, dy in self.vertex_derivatives:
                rows.append(_monomials(self._exps, xi[0, k], xi[1, k], dx, dy))
                scale.append(h ** (dx + dy))
        for a, b in edges:
            # the normal of an edge points the same way from both of its elements: it is the
            # rotated vector from the lower to the higher global node index
            lo = np.where(t[a] < t[b], a, b)
            hi = np.where(t[a] < t[b], b, a)
            nt_ = np.arange(t.shape[1])
            d = v[:, lo, nt_] - v[:, hi, nt_]
            n = np.vstack([d[1], -d[0]]) / np.linalg.norm(d, axis=0)
            mid = 0.5 * (xi[:, a] + xi[:, b])
            gx = _monomials(self._exps, mid[0], mid[1], 1, 0)
            gy = _monomials(self._exps, mid[0], mid[1], 0, 1)
            rows.append(n[0] * gx + n[1] * gy)
            scale.append(h)
        # V[e, j, m] = scaled functional j applied to monomial m; dual basis = columns of inv(V)
        V = np.stack(rows, axis=1).transpose(2, 1, 0)
        C = np.linalg.inv(V)  # (nt, N_monomials, N_dofs)
        # the dual basis of the unscaled functionals: phi_i = h^|alpha_i| * phi~_i
        C = C * np.stack(scale, axis=0).T[:, None, :]
        self._mesh_state = (mesh, C, centre, h)
        self._eval_cache = None
        return C, centre, h

    def condition_numbers(self, mesh: MeshTri) -> np.ndarray:
        """2-norm condition number of every element's scaled local DOF matrix."""
        C, _, h = self._state(mesh)
        # undo the unscaling to get the inverse of the scaled matrix back
        return np.linalg.cond(C)

    # -- evaluation -------------------------------------------------------------------------------
    def _evaluate(self, mapping, X, tind):
        cache = self._eval_cache
        if cache is not None and cache[0] is X and cache[1] is tind and cache[2] is mapping:
            return cache[3]
        mesh = mapping.mesh
        C, centre, h = self._state(mesh)
        if tind is None:
            tind_ = np.arange(mesh.t.shape[1])
        else:
            tind_ = np.asarray(tind)
        x = mapping.F(X, tind=tind)  # (2, nel, nq)
        c = centre[:, tind_][:, :, None]
        hh = h[tind_][:, None]
        xi = (x[0] - c[0]) / hh
        eta = (x[1] - c[1]) / hh
        e = self._exps
        Ct = C[tind_]  # (nel, Nm, Nd)

        def comb(dx, dy):
            P = _monomials(e, xi, eta, dx, dy)  # (Nm, nel, nq)
            return np.einsum("emd,meq->deq", Ct, P, optimize=True) / hh ** (dx + dy)

        val = comb(0, 0)
        gx, gy = comb(1, 0), comb(0, 1)
        hxx, hxy, hyy = comb(2, 0), comb(1, 1), comb(0, 2)
        out = (val, np.stack([gx, gy], axis=1), np.stack([np.stack([hxx, hxy], 1),
                                                           np.stack([hxy, hyy], 1)], 1))
        self._eval_cache = (X, tind, mapping, out)
        return out

    def gbasis(self, mapping, X, i, tind=None):
        val, grad, hess = self._evaluate(mapping, X, tind)
        return (DiscreteField(value=val[i], grad=grad[i], hess=hess[i]),)

    def gdof(self, F, w, i):  # pragma: no cover - the DOF matrix is built in _state
        raise NotImplementedError


class ElementTriArgyrisLocal(_LocalScaledGlobalTri):
    """Argyris triangle (quintic, C1) with the basis built in scaled element-local coordinates."""

    nodal_dofs = 6
    maxdeg = 5
    dofnames = ["u", "u_x", "u_y", "u_xx", "u_xy", "u_yy", "u_n"]
    vertex_derivatives = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
    doflocs = np.array([[0.0, 0.0]] * 6 + [[1.0, 0.0]] * 6 + [[0.0, 1.0]] * 6
                       + [[0.5, 0.0], [0.5, 0.5], [0.0, 0.5]])


class ElementTriMorleyLocal(_LocalScaledGlobalTri):
    """Morley triangle (quadratic, nonconforming; converges from below for the plate)."""

    nodal_dofs = 1
    maxdeg = 2
    dofnames = ["u", "u_n"]
    vertex_derivatives = ((0, 0),)
    doflocs = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]])


PLATE_ELEMENTS = {"argyris": ElementTriArgyrisLocal, "morley": ElementTriMorleyLocal}
