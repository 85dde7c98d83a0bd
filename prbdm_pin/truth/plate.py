"""Kirchhoff plate modal truth: Argyris (conforming, from above) and Morley (from below).

scikit-fem's ``ElementTriArgyris`` builds each element's basis by inverting a 21 x 21 matrix of
monomials evaluated in global coordinates. With elements of size h at distance ~1 m from the
origin the columns scale like h^k and the matrix becomes singular to working precision on fine
meshes (condition ~1e17): frequencies come out silently wrong and change when the mesh is
translated. The elements here evaluate the monomials in element-local coordinates
xi = (x - x_c) / h (centroid x_c, longest edge h), where the matrix is well conditioned for any
element position and size, and build all elements' bases at once with batched numpy.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from skfem import Basis, BilinearForm, MeshTri
from skfem.element import ElementGlobal
from skfem.element.discrete_field import DiscreteField
from skfem.helpers import dd, ddot, eye, trace
from skfem.refdom import RefTri

from ..geometry import Beam
from .result import ModalSolution, Timings

__all__ = [
    "ElementTriArgyrisLocal",
    "ElementTriMorleyLocal",
    "PlateModes",
    "plate_modes",
    "plate_modal",
    "ROOT_CLAMP_DOFS",
]

# Along the clamped edge x = 0: u = u_x = 0 for every y, hence u_y = u_yy = u_xy = 0 too; u_xx is
# not constrained (clamping it over-stiffens the plate by ~0.4 %).
ROOT_CLAMP_DOFS = {
    "argyris": ("u", "u_x", "u_y", "u_xy", "u_yy", "u_n"),
    "morley": ("u", "u_n"),
}


def _monomial_exponents(deg: int) -> np.ndarray:
    return np.array([(i, j) for i in range(deg + 1) for j in range(deg + 1) if i + j <= deg])


def _monomials(exps: np.ndarray, x: np.ndarray, y: np.ndarray, dx: int, dy: int) -> np.ndarray:
    """d^(dx+dy)/dx^dx dy^dy of every monomial x^i y^j at (x, y); shape (N, *x.shape)."""
    out = np.zeros((exps.shape[0], *x.shape))
    deg = int(exps.max())
    xp = [np.ones_like(x)]
    yp = [np.ones_like(y)]
    for _ in range(deg):
        xp.append(xp[-1] * x)
        yp.append(yp[-1] * y)
    for m, (i, j) in enumerate(exps):
        if i < dx or j < dy:
            continue
        c = np.prod(np.arange(i - dx + 1, i + 1)) * np.prod(np.arange(j - dy + 1, j + 1))
        out[m] = c * xp[i - dx] * yp[j - dy]
    return out


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
        self._exps = _monomial_exponents(self.maxdeg)
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


_ELEMENTS = {"argyris": ElementTriArgyrisLocal, "morley": ElementTriMorleyLocal}


def _plate_forms(D_Nm: float, nu: float, rho_h_kg_m2: float):
    @BilinearForm
    def stiffness(u, v, w):
        # bending energy density D [(1 - nu) k:k + nu tr(k)^2], k = hess(u)
        def moment(T):
            return D_Nm * ((1.0 - nu) * T + nu * eye(trace(T), 2))

        return ddot(moment(dd(u)), dd(v))

    @BilinearForm
    def mass(u, v, w):
        return rho_h_kg_m2 * u * v

    return stiffness, mass


def _assemble_plate(basis: Basis, D_Nm: float, nu: float, rho_h_kg_m2: float):
    """Plate stiffness and mass matrices; the same forms as ``_plate_forms`` but contracted over
    all basis-function pairs at once (scikit-fem's ``asm`` loops over the 21 x 21 pairs, which
    dominated the solve time)."""
    from scipy.sparse import coo_matrix

    dx = basis.dx  # (nel, nq)
    H = np.stack([b[0].hess for b in basis.basis])  # (Nd, 2, 2, nel, nq)
    V = np.stack([np.asarray(b[0]) for b in basis.basis])  # (Nd, nel, nq)
    B = np.stack([H[:, 0, 0], H[:, 1, 1], np.sqrt(2.0) * H[:, 0, 1]], axis=1)
    T = H[:, 0, 0] + H[:, 1, 1]
    Ke = D_Nm * ((1.0 - nu) * np.einsum("icEq,jcEq,Eq->Eij", B, B, dx, optimize=True)
                 + nu * np.einsum("iEq,jEq,Eq->Eij", T, T, dx, optimize=True))
    Me = rho_h_kg_m2 * np.einsum("iEq,jEq,Eq->Eij", V, V, dx, optimize=True)
    dofs = basis.element_dofs  # (Nd, nel)
    rows = np.broadcast_to(dofs.T[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(dofs.T[:, None, :], Ke.shape).ravel()
    shape = (basis.N, basis.N)
    K = coo_matrix((Ke.ravel(), (rows, cols)), shape=shape).tocsr()
    M = coo_matrix((Me.ravel(), (rows, cols)), shape=shape).tocsr()
    return K, M


@dataclass(frozen=True, eq=False)
class PlateModes:
    """Raw output of the plate eigensolve (before classification).

    Attributes
    ----------
    element : str
        ``"argyris"`` or ``"morley"``.
    omega_rad_s : ndarray, shape (k,)
    phi : ndarray, shape (ndofs, k)
        Full DOF vectors (clamped DOFs zero), mass-normalised.
    mesh : MeshTri
    basis : skfem Basis
    M : sparse matrix
        Full mass matrix (for participation factors).
    rz : ndarray, shape (ndofs,)
        DOF vector of the rigid translation u = 1.
    timings : tuple of float
        (mesh_s, basis_s, assembly_s, solve_s).
    """

    element: str
    omega_rad_s: np.ndarray
    phi: np.ndarray
    mesh: MeshTri
    basis: Basis
    M: object
    rz: np.ndarray
    timings: tuple[float, float, float, float]

    @property
    def dofs(self) -> int:
        return int(self.phi.shape[0])

    def nodal_uz(self) -> np.ndarray:
        """z displacement of every mode at the mesh nodes, (k, n_nodes), m (mass-normalised)."""
        return self.phi[self.basis.nodal_dofs[0]].T


def plate_modes(
    beam: Beam,
    level: int = 1,
    n_modes: int = 25,
    element: str = "argyris",
    mesh: MeshTri | None = None,
) -> PlateModes:
    """Natural modes of the clamped-free Kirchhoff plate of a beam's planform.

    Parameters
    ----------
    beam : Beam
    level : int
        Mesh refinement level (``planform_tri_mesh``); ignored when ``mesh`` is given.
    n_modes : int
        Number of lowest modes computed.
    element : {"argyris", "morley"}
    mesh : MeshTri, optional
        A ready mesh (nodes in m) with the clamp at x = 0.

    Returns
    -------
    PlateModes
        Frequencies in rad/s; eigenvalues are checked by the caller.
    """
    from scipy.sparse import diags
    from scipy.sparse.linalg import eigsh

    from .mesh import planform_tri_mesh
    from .mesh_budget import (
        PLATE_DOFS_PER_EDGE,
        PLATE_DOFS_PER_NODE,
        check_dofs,
        check_plate_budget,
    )

    if element not in _ELEMENTS:
        raise ValueError(f"element = {element!r}: must be one of {sorted(_ELEMENTS)}")
    t0 = time.perf_counter()
    if mesh is None:
        check_plate_budget(beam, level, element)
        mesh = planform_tri_mesh(beam, level)
    check_dofs(f"plate-{element}", level, PLATE_DOFS_PER_NODE[element] * mesh.p.shape[1]
               + PLATE_DOFS_PER_EDGE * mesh.facets.shape[1], beam)
    t1 = time.perf_counter()
    elem = _ELEMENTS[element]()  # a new element object per mesh: it caches per-mesh state
    basis = Basis(mesh, elem)
    t2 = time.perf_counter()
    mat = beam.material
    t = beam.thickness_m
    D = mat.E_Pa * t**3 / (12.0 * (1.0 - mat.nu**2))
    K, M = _assemble_plate(basis, D, mat.nu, mat.rho_kg_m3 * t)
    x0 = float(mesh.p[0].min())
    tol = 1e-9 * float(np.ptp(mesh.p[0]))
    clamped = basis.get_dofs(lambda x: np.abs(x[0] - x0) < tol).all(ROOT_CLAMP_DOFS[element])
    free = np.setdiff1d(np.arange(basis.N), clamped)
    Kf = K[free][:, free].tocsc()
    Mf = M[free][:, free].tocsc()
    t3 = time.perf_counter()
    # symmetric diagonal scaling leaves the eigenvalues unchanged and equilibrates the DOF kinds
    # (values, slopes, curvatures differ in scale by h^-1, h^-2 in the matrices)
    s = diags(1.0 / np.sqrt(Kf.diagonal()))
    Ks = (s @ Kf @ s).tocsc()
    Ms = (s @ Mf @ s).tocsc()
    k = min(n_modes, free.size - 2)
    lam, y = eigsh(Ks, k=k, M=Ms, sigma=0.0, which="LM")
    order = np.argsort(lam)
    lam, y = lam[order], y[:, order]
    phi_f = s @ y
    t4 = time.perf_counter()
    phi = np.zeros((basis.N, k))
    phi[free] = phi_f
    rz = np.zeros(basis.N)
    rz[basis.nodal_dofs[0]] = 1.0
    omega = np.sqrt(np.abs(lam)) * np.sign(lam)
    return PlateModes(
        element=element, omega_rad_s=omega, phi=phi, mesh=mesh, basis=basis, M=M, rz=rz,
        timings=(t1 - t0, t2 - t1, t3 - t2, t4 - t3),
    )


def plate_modal(
    beam: Beam, level: int = 0, n_modes: int = 25, element: str = "argyris"
) -> ModalSolution:
    """Plate modes with z mass participation, symmetry about x and MAC with beam modes.

    Parameters
    ----------
    beam : Beam
    level : int
        Mesh refinement level (element size L / (10 * 2^level), graded at short vertex
        intervals, narrow necks and re-entrant corners; see ``planform_tri_mesh``).
    n_modes : int
        Number of lowest modes computed (20-30 so that a bending-mode selection is complete).
    element : {"argyris", "morley"}

    Returns
    -------
    ModalSolution
        ``model`` is ``"plate-argyris"`` or ``"plate-morley"``; frequencies in rad/s (a negative
        value stands for a negative eigenvalue, which the caller must refuse).
    """
    from .modes import beam_mac, mass_participation_z, symmetry_about_x

    pm = plate_modes(beam, level, n_modes, element)
    mpf = mass_participation_z(pm.M, pm.phi, pm.rz)
    uz = pm.nodal_uz()
    nodes = np.column_stack([pm.mesh.p.T, np.zeros(pm.mesh.p.shape[1])])
    sym = symmetry_about_x(nodes, uz)
    axis = np.flatnonzero(pm.mesh.p[1] == 0.0)
    axis = axis[np.argsort(pm.mesh.p[0, axis])]
    xc = pm.mesh.p[0, axis]
    uc = uz[:, axis]
    mac, idx = beam_mac(beam, xc, uc)
    ms, bs, as_, ss = pm.timings
    return ModalSolution(
        model=f"plate-{element}",
        omega_rad_s=pm.omega_rad_s,
        mpf_z=mpf,
        mpf_z_fraction=mpf / beam.mass_kg,
        symmetric=sym > 0.0,
        mac_beam=mac,
        beam_mode_index=idx,
        centerline_x_m=xc,
        centerline_uz=uc,
        dofs=int(pm.dofs),
        mesh_level=int(level),
        timings=Timings(mesh_s=ms, basis_s=bs, assembly_s=as_, solve_s=ss),
        nodes_m=nodes,
        cells=pm.mesh.t.T.copy(),
        cell_type="triangle",
        node_uz=uz,
        modal_mass_kg=np.ones(pm.omega_rad_s.size),  # the eigenvectors are mass-normalised
    )
