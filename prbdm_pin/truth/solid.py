"""3D solid truth: quadratic hexahedra (27 nodes), one element through the thickness.

The planform's quadrilateral mesh (``feature_mesh.planform_quad_mesh``: triangles graded by the
local feature size, each split into three quadrilaterals) is extruded through the thickness
(mid-surface at z = 0). Stiffness and mass come from batched element matrices of the scalar
forms int d_k phi_a d_m phi_b and int phi_a phi_b on ``ElementHex2``, summed into one scalar
sparsity pattern and laid out as 3 x 3 blocks (DOF 3 a + i is component i at scalar DOF a),
an order of magnitude faster than ``ElementVector``. A 3 x 3 x 3 Gauss rule replaces the default
343-point rule (4 x 4 x 4 points change the square plate's frequencies by < 0.01 %).

The large-deflection model is total-Lagrangian Saint Venant-Kirchhoff (second Piola-Kirchhoff
stress S = lambda tr(E) I + 2 mu E of the Green strain E), solved by Newton's method with load
steps under the dead tip load. Each tangent is a batch of BLAS products summed into a fixed CSR
pattern of the free DOFs; Newton corrections come from conjugate gradients preconditioned by the
last LU factorisation while the tangent changes little, and from a new factorisation otherwise.
Factorisations use a minimum-degree order of the planform column graph (``ordering``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree
from skfem import Basis, ElementHex2, FacetBasis, LinearForm, MeshHex, asm

from ..errors import BeamInputError, SolveError
from ..geometry import Beam
from .feature_mesh import planform_quad_mesh
from .mesh import element_size
from .ordering import column_order
from .result import ModalSolution, StaticSolution, Timings

__all__ = ["default_solid_level", "solid_mesh", "solid_modal", "solid_static"]

_INTORDER = 4  # 3 x 3 x 3 Gauss points
# elements on the clamp no deeper than this many thicknesses: the clamp blocks the Poisson
# contraction of the root section (measured on square-plate.json at level 2: mode 1 0.09 % above
# the plate table without, 0.03 % with, for 15 % more DOFs)
ROOT_THICKNESSES = 2.5
# skfem's hex vertex order -> VTK/meshio "hexahedron" order.
_VTK_HEX = [0, 3, 6, 2, 1, 5, 7, 4]


def default_solid_level(beam: Beam) -> int:
    """Mesh level whose in-plane element size is closest to 2.5 thicknesses."""
    return max(0, int(round(np.log2(element_size(beam, 0) / (2.5 * beam.thickness_m)))))


def _level(beam: Beam, level: int | None) -> int:
    if level is None:
        return default_solid_level(beam)
    if not isinstance(level, (int, np.integer)) or isinstance(level, bool) or level < 0:
        raise BeamInputError(f"level = {level!r}: must be an integer >= 0")
    return int(level)


def solid_mesh(beam: Beam, level: int | None = None) -> MeshHex:
    """The planform's quadrilateral mesh (``planform_quad_mesh``) extruded to one hexahedron
    through the thickness.

    Nodes in m, z in [-t/2, t/2] (mid-surface at z = 0).
    """
    quad = planform_quad_mesh(beam, _level(beam, level),
                              root_size_m=ROOT_THICKNESSES * beam.thickness_m)
    p2, t2 = quad.p, quad.t
    n = p2.shape[1]
    h = 0.5 * beam.thickness_m
    p = np.hstack([np.vstack([p2, np.full(n, -h)]), np.vstack([p2, np.full(n, h)])])
    a, b, c, d = t2
    # Reference hex vertices (0,0,0), (0,0,1), (0,1,0), (1,0,0), (0,1,1), (1,0,1), (1,1,0), (1,1,1)
    # with the quad's a-b along xi and a-d along eta.
    t = np.vstack([a, a + n, d, b, d + n, b + n, c, c + n])
    return MeshHex(p, t)


@dataclass(frozen=True, eq=False)
class _Discretisation:
    mesh: MeshHex
    basis: Basis
    level: int
    lam: float
    mu: float
    free: np.ndarray  # free vector DOFs
    n_vec: int
    order: np.ndarray | None = None  # fill-reducing order of the free DOFs (None: SuperLU's)


def _lame(beam: Beam) -> tuple[float, float]:
    E, nu = beam.material.E_Pa, beam.material.nu
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def _discretise(beam: Beam, level: int | None) -> _Discretisation:
    from .mesh_budget import check_dofs, check_solid_budget

    lev = _level(beam, level)
    check_solid_budget(beam, lev)
    mesh = solid_mesh(beam, lev)
    # 27-node hexahedra: a node at every vertex, edge, face and cell centre, 3 DOFs each
    check_dofs("solid", lev, 3 * (mesh.p.shape[1] + mesh.edges.shape[1] + mesh.facets.shape[1]
                                  + mesh.t.shape[1]), beam)
    basis = Basis(mesh, ElementHex2(), intorder=_INTORDER)
    root = basis.get_dofs(lambda x: np.isclose(x[0], 0.0, atol=1e-12 * beam.length_m)).all()
    fixed = (3 * root[:, None] + np.arange(3)).ravel()
    n_vec = 3 * basis.N
    free = np.setdiff1d(np.arange(n_vec), fixed)
    lam, mu = _lame(beam)
    order = column_order(basis.doflocs, basis.element_dofs, free)
    return _Discretisation(mesh, basis, lev, lam, mu, free, n_vec, order)


class _ScalarPattern:
    """CSR pattern of the scalar element matrices (27 x 27 per element) and the slot of every
    element-matrix entry, so each scalar matrix is one ``bincount``."""

    def __init__(self, element_dofs: np.ndarray, n: int):
        e = element_dofs.T.astype(np.int64)  # (E, 27)
        rows = np.broadcast_to(e[:, :, None], (*e.shape, e.shape[1])).ravel()
        cols = np.broadcast_to(e[:, None, :], (*e.shape, e.shape[1])).ravel()
        unique, self.pos = np.unique(rows * n + cols, return_inverse=True)
        self.indices = (unique % n).astype(np.int32)
        self.indptr = np.searchsorted(unique // n, np.arange(n + 1)).astype(np.int32)
        self.n = n
        self.nnz = unique.size

    def data(self, element_matrices: np.ndarray) -> np.ndarray:
        return np.bincount(self.pos, weights=element_matrices.ravel(), minlength=self.nnz)

    def vector_matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """The (3n, 3n) matrix whose 3 x 3 block at (a, b) is ``blocks[slot(a, b)]``: vector DOF
        3 a + i is component i at scalar DOF a."""
        return sp.bsr_matrix((blocks, self.indices, self.indptr),
                             shape=(3 * self.n, 3 * self.n)).tocsr()


def _assemble(beam: Beam, d: _Discretisation) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Linear-elastic stiffness and consistent mass (full vector numbering).

    K_ij = lam A_ij + mu (delta_ij sum_k A_kk + A_ji) from the scalar matrices
    A_km[a, b] = int d_k phi_a d_m phi_b, each element's A_km a batched matrix product over the
    Gauss points (scikit-fem's ``asm`` loops over the 27 x 27 basis pairs, several times slower).
    """
    b = d.basis
    pattern = _ScalarPattern(b.element_dofs, b.N)
    w = b.dx  # (E, Q)
    G = np.stack([np.asarray(f[0].grad) for f in b.basis], axis=0)  # (27, 3, E, Q)
    G = G.transpose(2, 1, 3, 0)  # (E, 3, Q, 27)
    A = np.empty((pattern.nnz, 3, 3))
    for k in range(3):
        wg = np.swapaxes(G[:, k] * w[..., None], 1, 2)  # (E, 27, Q)
        for m in range(k, 3):
            A[:, k, m] = pattern.data(wg @ G[:, m])
            A[:, m, k] = A[:, k, m] if k == m else pattern.data(np.swapaxes(wg @ G[:, m], 1, 2))
    trace = A[:, 0, 0] + A[:, 1, 1] + A[:, 2, 2]
    blocks = d.lam * A + d.mu * np.swapaxes(A, 1, 2) + d.mu * trace[:, None, None] * np.eye(3)
    V = np.stack([np.asarray(f[0]) for f in b.basis], axis=-1)  # (E, Q, 27)
    m = pattern.data(np.swapaxes(V * w[..., None], 1, 2) @ V)
    mass = beam.material.rho_kg_m3 * m[:, None, None] * np.eye(3)
    return pattern.vector_matrix(blocks), pattern.vector_matrix(mass)


class _Factor:
    """LU of a symmetric positive definite matrix in a given order (MMD if none)."""

    def __init__(self, A: sp.spmatrix, order: np.ndarray | None = None):
        self.order = order
        A = sp.csc_matrix(A)
        if order is not None:
            A = A[order][:, order].tocsc()
        # symmetric positive definite: a symmetric order and no pivoting
        self.lu = spla.splu(
            A, permc_spec="NATURAL" if order is not None else "MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0, options={"SymmetricMode": True},
        )

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.order is None:
            return self.lu.solve(b)
        x = np.empty_like(b)
        x[self.order] = self.lu.solve(b[self.order])
        return x


def _factor(A: sp.spmatrix, order: np.ndarray | None = None) -> _Factor:
    return _Factor(A, order)


def _mirror_index(points: np.ndarray, scale: float) -> np.ndarray:
    """Index of the DOF location mirrored about y = 0 (points shape (N, 3))."""
    mirrored = points * np.array([1.0, -1.0, 1.0])
    dist, idx = cKDTree(points).query(mirrored)
    if np.max(dist) > 1e-9 * scale:
        raise SolveError("solid mesh is not mirror-symmetric about y = 0")
    return idx


def solid_modal(beam: Beam, level: int | None = None, n_modes: int = 30) -> ModalSolution:
    """Lowest modes of the 3D solid by shift-invert Lanczos about 0.

    Parameters
    ----------
    beam : Beam
    level : int, optional
        Planform mesh level (element size about L / (10 2^level) where the planform is wide,
        smaller at its features); default: closest to 2.5 t.
    n_modes : int
        Number of modes (all types: bending, torsion, chordwise, in-plane).

    Returns
    -------
    ModalSolution
        ``mpf_z`` in kg from M and the rigid z translation; ``symmetric`` from the z displacement
        mirrored about y = 0; ``centerline_uz`` the mid-surface z displacement on y = 0 (scaled
        to unit maximum, positive at the tip) and ``node_uz`` at the same scale; ``mac_beam``
        against the 1D beam's bending modes; ``z_energy_fraction`` the share of each mode's
        kinetic energy in z motion (in-plane modes near 0).
    """
    if not isinstance(n_modes, (int, np.integer)) or isinstance(n_modes, bool) or n_modes < 1:
        raise BeamInputError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    t0 = time.perf_counter()
    d = _discretise(beam, level)
    t1 = time.perf_counter()
    K, M = _assemble(beam, d)
    Kff = K[d.free][:, d.free]
    Mff = M[d.free][:, d.free]
    t2 = time.perf_counter()
    k = min(n_modes, d.free.size - 2)
    lu = _factor(Kff, d.order)
    OPinv = spla.LinearOperator(Kff.shape, matvec=lu.solve, dtype=float)
    lam, vec = spla.eigsh(Kff, k=k, M=Mff, sigma=0.0, which="LM", OPinv=OPinv, tol=1e-12)
    t3 = time.perf_counter()
    if np.any(lam <= 0.0) or not np.all(np.isfinite(lam)):
        raise SolveError(f"solid eigenvalues not positive: min = {lam.min():.3e} (rad/s)^2")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    phi = np.zeros((d.n_vec, k))
    phi[d.free] = vec
    r_z = np.zeros(d.n_vec)
    r_z[2::3] = 1.0  # Lagrange element: the rigid z translation interpolates to 1 at every DOF
    Mphi = M @ phi
    mpf = (r_z @ Mphi) ** 2 / np.einsum("ij,ij->j", phi, Mphi)

    locs = d.basis.doflocs.T
    uz = phi[2::3].T  # (k, N)
    # kinetic-energy share of the z motion: near 1 for bending and torsion, near 0 in plane
    ez = np.einsum("ij,ij->j", phi[2::3], Mphi[2::3]) / np.einsum("ij,ij->j", phi, Mphi)
    mirror = _mirror_index(locs, beam.length_m)
    sym = np.linalg.norm(uz - uz[:, mirror], axis=1) < np.linalg.norm(uz + uz[:, mirror], axis=1)
    tol = 1e-9 * beam.length_m
    line = np.flatnonzero((np.abs(locs[:, 1]) < tol) & (np.abs(locs[:, 2]) < tol))
    line = line[np.argsort(locs[line, 0])]
    cl = uz[:, line]
    # scale every mode to a unit centreline peak, positive at the tip (a mode whose centreline
    # does not move, torsion or in-plane, to a unit peak of z displacement instead)
    peak = np.max(np.abs(cl), axis=1)
    top = np.max(np.abs(uz), axis=1)
    peak = np.where(peak > 1e-6 * top, peak, top)
    scale = np.where(cl[:, -1] < 0, -1.0, 1.0) / peak
    cl = cl * scale[:, None]
    from .modes import beam_mac

    mac, best = beam_mac(beam, locs[line, 0], cl)
    verts = d.basis.nodal_dofs[0]
    return ModalSolution(
        model="solid",
        omega_rad_s=np.sqrt(lam),
        mpf_z=mpf,
        mpf_z_fraction=mpf / beam.mass_kg,
        symmetric=sym,
        mac_beam=mac,
        beam_mode_index=best,
        centerline_x_m=locs[line, 0].copy(),
        centerline_uz=cl,
        dofs=int(d.free.size),
        mesh_level=d.level,
        timings=Timings(mesh_s=t1 - t0, assembly_s=t2 - t1, solve_s=t3 - t2),
        nodes_m=d.mesh.p.T.copy(),
        cells=d.mesh.t[_VTK_HEX].T.copy(),
        cell_type="hexahedron",
        node_uz=uz[:, verts] * scale[:, None],
        modal_mass_kg=scale**2,  # the eigenvectors are mass-normalised before scaling
        z_energy_fraction=ez,
    )


def _tip_load(beam: Beam, d: _Discretisation, F: np.ndarray) -> np.ndarray:
    """Consistent nodal forces of the traction F / area spread uniformly over the face x = L."""
    L = beam.length_m
    facets = d.mesh.facets_satisfying(lambda x: np.isclose(x[0], L, atol=1e-12 * L))
    fb = FacetBasis(d.mesh, ElementHex2(), facets=facets, intorder=_INTORDER)
    fs = asm(LinearForm(lambda v, w: v), fb)
    f = np.zeros(d.n_vec)
    for i in range(3):
        f[i::3] = F[i] * fs / fs.sum()
    return f


def _tip_dofs(beam: Beam, d: _Discretisation) -> np.ndarray:
    locs = d.basis.doflocs
    tol = 1e-9 * beam.length_m
    tip = np.flatnonzero((np.abs(locs[0] - beam.length_m) < tol) & (np.abs(locs[1]) < tol))
    if tip.size != 3:
        raise SolveError(f"found {tip.size} tip-centreline DOF locations, expected 3")
    return tip


class _Pattern:
    """Fixed CSR sparsity of the element matrices restricted to a DOF subset.

    ``pos`` sends every kept element-matrix entry to its slot in the CSR data array, so each
    tangent is assembled by one ``bincount`` instead of a COO -> CSR conversion (sort and
    duplicate sum of ~10^7 entries).
    """

    def __init__(self, vdofs: np.ndarray, keep: np.ndarray, n_vec: int):
        index = np.full(n_vec, -1, dtype=np.int64)
        index[keep] = np.arange(keep.size)
        loc = index[vdofs]  # (E, 81) reduced index, -1 where the DOF is not kept
        ne, nd = loc.shape
        rows = np.repeat(loc, nd, axis=1).ravel()
        cols = np.tile(loc, (1, nd)).ravel()
        self.mask = (rows >= 0) & (cols >= 0)
        n = keep.size
        key = rows[self.mask] * n + cols[self.mask]
        unique, self.pos = np.unique(key, return_inverse=True)
        self.indices = (unique % n).astype(np.int32)
        self.indptr = np.searchsorted(unique // n, np.arange(n + 1)).astype(np.int32)
        self.shape = (n, n)
        self.nnz = unique.size

    def matrix(self, element_matrices: np.ndarray) -> sp.csr_matrix:
        data = np.bincount(self.pos, weights=element_matrices.ravel()[self.mask],
                           minlength=self.nnz)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape)


class _Kinematics:
    """Element-level total-Lagrangian SVK kernel: internal forces and tangent stiffness.

    The contractions over Gauss points are batched matrix products (BLAS) rather than
    ``einsum`` loops; the tangent goes into a precomputed sparsity pattern.
    """

    def __init__(self, d: _Discretisation, chunk: int = 64):
        b = d.basis
        self.d = d
        self.dofs = b.element_dofs.T  # (E, 27)
        # G[e, q, a, j] = d phi_a / d X_j at Gauss point q of element e
        self.G = np.stack([b.basis[a][0].grad for a in range(len(b.basis))], axis=0)
        self.G = np.ascontiguousarray(self.G.transpose(2, 3, 0, 1))
        self.w = b.dx  # (E, Q) quadrature weights times |J|
        self.chunk = chunk
        ne, na = self.dofs.shape
        self.vdofs = (3 * self.dofs[:, :, None] + np.arange(3)).reshape(ne, 3 * na)
        self._patterns: dict[str, _Pattern] = {}

    def pattern(self, which: str = "full") -> _Pattern:
        if which not in self._patterns:
            keep = np.arange(self.d.n_vec) if which == "full" else self.d.free
            self._patterns[which] = _Pattern(self.vdofs, keep, self.d.n_vec)
        return self._patterns[which]

    def evaluate(self, u: np.ndarray, tangent: bool = True, which: str = "full"):
        """Internal force vector (all DOFs) and, if asked, the tangent stiffness (CSR) on
        ``which`` DOFs: ``"full"`` or ``"free"``."""
        lam, mu = self.d.lam, self.d.mu
        ne, na = self.dofs.shape
        nd = 3 * na
        fint = np.zeros(self.d.n_vec)
        kdata = np.empty((ne, nd, nd)) if tangent else None
        I3 = np.eye(3)
        for s in range(0, ne, self.chunk):
            sl = slice(s, min(s + self.chunk, ne))
            G, w = self.G[sl], self.w[sl]
            n, nq = w.shape
            ue = u[self.vdofs[sl]].reshape(n, 1, na, 3)
            F = I3 + np.swapaxes(ue, 2, 3) @ G  # F_ij = delta_ij + sum_a u_ai g_aj
            Egl = 0.5 * (np.swapaxes(F, 2, 3) @ F - I3)
            tr = Egl[..., 0, 0] + Egl[..., 1, 1] + Egl[..., 2, 2]
            wS = w[..., None, None] * (lam * tr[..., None, None] * I3 + 2 * mu * Egl)
            fe = (G @ np.swapaxes(F @ wS, 2, 3)).sum(axis=1)  # sum_q w P_ij g_aj
            np.add.at(fint, self.vdofs[sl].ravel(), fe.ravel())
            if not tangent:
                continue
            h = (G @ np.swapaxes(F, 2, 3)).reshape(n, nq, nd)  # h_(a i) = F_ij g_aj
            wh = w[..., None] * h
            hh = (np.swapaxes(wh, 1, 2) @ h).reshape(n, na, 3, na, 3)
            # mu (F F^T)_ik (g_a . g_b) and the initial-stress term (g_a . S g_b) delta_ik
            gg = (G @ np.swapaxes(G, 2, 3)).reshape(n, nq, na * na)
            wbF = (mu * w[..., None, None] * (F @ np.swapaxes(F, 2, 3))).reshape(n, nq, 9)
            Kb = (np.swapaxes(wbF, 1, 2) @ gg).reshape(n, 3, 3, na, na)
            gSg = ((G @ wS).transpose(0, 2, 1, 3).reshape(n, na, nq * 3)
                   @ G.transpose(0, 1, 3, 2).reshape(n, nq * 3, na))
            Ke = lam * hh + mu * hh.transpose(0, 1, 4, 3, 2) + Kb.transpose(0, 3, 1, 4, 2)
            Ke[:, :, [0, 1, 2], :, [0, 1, 2]] += gSg
            kdata[sl] = Ke.reshape(n, nd, nd)
        if not tangent:
            return fint, None
        return fint, self.pattern(which).matrix(kdata)


class _TangentSolver:
    """Newton corrections K du = r: a fresh factorisation, or conjugate gradients preconditioned
    by the last factorisation while they converge fast.

    Within a load step the tangent changes little between Newton iterations, so the previous
    LU is an excellent preconditioner: a few CG iterations (one triangular solve each) replace a
    new factorisation. The corrections are solved to ``rtol``, so Newton keeps its quadratic
    convergence; if CG needs more than ``max_cg`` iterations the tangent is factored again.
    """

    def __init__(self, rtol: float = 1e-6, max_cg: int = 20, order: np.ndarray | None = None):
        self.lu = None
        self.order = order
        self.rtol = rtol
        self.max_cg = max_cg
        self.factorisations = 0
        self.cg_iterations = 0

    def solve(self, K: sp.csr_matrix, r: np.ndarray, refactor: bool = False) -> np.ndarray:
        if self.lu is not None and not refactor:
            M = spla.LinearOperator(K.shape, matvec=self.lu.solve, dtype=float)
            count = [0]

            def tally(_):
                count[0] += 1

            du, info = spla.cg(K, r, x0=self.lu.solve(r), rtol=self.rtol, maxiter=self.max_cg,
                               M=M, callback=tally)
            self.cg_iterations += count[0]
            if info == 0 and np.all(np.isfinite(du)):
                return du
        self.lu = _factor(K, self.order)
        self.factorisations += 1
        return self.lu.solve(r)


def _nonlinear(beam, d, f_ext, load_steps, tol, max_iter, progress=None, stats=None):
    kin = _Kinematics(d)
    solver = _TangentSolver(order=d.order)
    free = d.free
    u = np.zeros(d.n_vec)
    u_prev, lam_prev = None, 0.0
    fscale = np.linalg.norm(f_ext[free])
    lam_done, dlam = 0.0, 1.0 / load_steps
    steps = iterations = 0
    while lam_done < 1.0 - 1e-12:
        lam_try = min(1.0, lam_done + dlam)
        u_try = u.copy()
        if u_prev is not None:
            # secant predictor along the converged load path
            u_try += (lam_try - lam_done) / (lam_done - lam_prev) * (u - u_prev)
        converged = False
        du_norm = r_prev = np.inf
        for _ in range(max_iter):
            fint, K = kin.evaluate(u_try, which="free")
            r = (lam_try * f_ext - fint)[free]
            r_norm = np.linalg.norm(r)
            # Rounding in the stiff membrane terms floors the residual (near 1e-9 of the load at
            # P L^2/EI = 1, relatively higher for small loads): accept a residual below tol or
            # one that stopped falling, once the last Newton correction is negligible.
            small_step = du_norm <= 1e-6 * np.linalg.norm(u_try)
            if small_step and (r_norm <= tol * fscale or r_norm > 0.5 * r_prev):
                converged = True
                break
            r_prev = r_norm
            # a large last correction means the tangent moved: factor it afresh
            du = solver.solve(K, r, refactor=du_norm > 3e-2 * np.linalg.norm(u_try))
            du_norm = np.linalg.norm(du)
            u_try[free] += du
            iterations += 1
            if not np.all(np.isfinite(u_try)):
                break
        if converged:
            u_prev, lam_prev = u, lam_done
            u, lam_done = u_try, lam_try
            steps += 1
            if progress is not None:
                progress(lam_done)
        else:
            dlam *= 0.5  # cut the increment and retry from the last converged state
            solver.lu = None
            if dlam < 1e-4:
                raise SolveError(f"solid Newton failed at load factor {lam_try:.4g}")
    if stats is not None:
        stats.update(newton_iterations=iterations, factorisations=solver.factorisations,
                     cg_iterations=solver.cg_iterations)
    return u, steps


def solid_static(
    beam: Beam,
    level: int | None = None,
    tip_force_N: np.ndarray | None = None,
    nonlinear: bool = False,
    load_steps: int | None = None,
    tol: float = 1e-7,
    max_iter: int = 25,
) -> StaticSolution:
    """Tip response of the 3D solid under a tip force spread uniformly over the face x = L.

    Parameters
    ----------
    beam : Beam
    level : int, optional
        Planform mesh level; default: in-plane element size closest to 2.5 t.
    tip_force_N : array_like, shape (3,), optional
        Total tip force in N (default: ``beam.tip_force_N``); a dead load in the nonlinear solve.
    nonlinear : bool
        Geometrically nonlinear (total-Lagrangian Saint Venant-Kirchhoff) if True.
    load_steps : int, optional
        Initial load increments (default: about 3 per unit of P L^2 / EI_root); an increment whose
        Newton iteration fails is halved.
    tol : float
        Newton tolerance on the free residual relative to the load vector norm.
    max_iter : int
        Newton iterations per increment.

    Returns
    -------
    StaticSolution
        Displacement of the mid-surface tip point (L, 0, 0): the mean of the three DOFs on the
        tip edge's centreline (z = -t/2, 0, t/2), m.
    """
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    if load_steps is None:
        load_steps = int(np.clip(np.ceil(3 * beam.load_index(float(np.linalg.norm(F)))), 1, 100))
    if not isinstance(load_steps, (int, np.integer)) or load_steps < 1:
        raise BeamInputError(f"load_steps = {load_steps!r}: must be an integer >= 1")
    t0 = time.perf_counter()
    d = _discretise(beam, level)
    f = _tip_load(beam, d, F)
    t1 = time.perf_counter()
    if nonlinear:
        u, steps = _nonlinear(beam, d, f, load_steps, tol, max_iter)
        t2 = t3 = time.perf_counter()
    else:
        K, _ = _assemble(beam, d)
        Kff = K[d.free][:, d.free]
        t2 = time.perf_counter()
        u = np.zeros(d.n_vec)
        u[d.free] = _factor(Kff, d.order).solve(f[d.free])
        steps = 1
        t3 = time.perf_counter()
    tip = _tip_dofs(beam, d)
    disp = np.array([u[3 * tip + i].mean() for i in range(3)])
    return StaticSolution(
        model="solid",
        nonlinear=bool(nonlinear),
        tip_force_N=F.copy(),
        tip_position_m=np.array([beam.length_m, 0.0, 0.0]) + disp,
        tip_displacement_m=disp,
        dofs=int(d.free.size),
        mesh_level=d.level,
        load_steps=steps,
        timings=Timings(mesh_s=t1 - t0, assembly_s=t2 - t1, solve_s=t3 - t2),
    )
