"""Linear static truth of the Kirchhoff plate under the tip force spread over the free edge.

The same element (Argyris in scaled element-local coordinates), mesh and root clamp as the plate
modal truth (``plate``). The tip force F_z becomes the uniform line load q = F_z / (2 w(L))
along the free edge x = L, integrated against the Argyris basis on the tip facets (a consistent
load vector, not a nodal lump). Kirchhoff bending carries only F_z: in-plane components are
reported in ``tip_force_N`` but produce no displacement here (as in the 1D beam model).
"""

from __future__ import annotations

import time

import numpy as np
from scipy.sparse import diags
from scipy.sparse.linalg import splu
from skfem import FacetBasis, LinearForm, MeshTri, asm

from ..errors import BeamInputError, TruthError
from ..member.geometry import Beam
from .mesh_budget import PLATE_DOFS_PER_EDGE, PLATE_DOFS_PER_NODE, check_dofs, check_plate_budget
from .plate import ROOT_CLAMP_DOFS, assemble_plate, plate_basis, plate_section
from .plate_elements import ElementTriArgyrisLocal
from .result import StaticSolution, Timings
from .settings import DEFAULT_PLATE_LEVEL, check_level

__all__ = ["plate_static", "tip_edge_load", "spd_solve"]


@LinearForm
def _unit_line_load(v, w):
    return 1.0 * v


def tip_edge_load(beam: Beam, facet_basis: FacetBasis, force_z_N: float) -> np.ndarray:
    """Consistent load vector (N) of the line load F_z / (2 w(L)) on the tip-edge facets."""
    q_N_m = force_z_N / (2.0 * beam.half_width_at(beam.length_m))
    return q_N_m * asm(_unit_line_load, facet_basis)


def spd_solve(Kf, b: np.ndarray) -> np.ndarray:
    """Solution of the sparse SPD system Kf x = b (b of shape (n,) or (n, m)).

    A symmetric diagonal scaling equilibrates values, slopes and curvatures (scales h^0..h^-2);
    the scaled matrix is SPD: symmetric fill-reducing order, no pivoting (least fill measured),
    then one step of iterative refinement.
    """
    s = 1.0 / np.sqrt(Kf.diagonal())
    A = (diags(s) @ Kf @ diags(s)).tocsc()
    lu = splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
              options={"SymmetricMode": True})
    sb = s * b.T
    rhs = sb.T
    y = lu.solve(rhs)
    y += lu.solve(rhs - A @ y)
    return (s * y.T).T


def plate_static(
    beam: Beam, level: int | None = None, tip_force_N: np.ndarray | None = None,
    mesh: MeshTri | None = None,
) -> StaticSolution:
    """Linear tip deflection of the clamped Kirchhoff plate under a uniform tip-edge load.

    Parameters
    ----------
    beam : Beam
    level : int, optional
        Mesh level of ``planform_tri_mesh`` (default: the plate modal truth's default level).
    tip_force_N : array_like, shape (3,), optional
        Total tip force in N (default: ``beam.tip_force_N``); its z component is spread
        uniformly over the free edge x = L as a line load F_z / (2 w(L)) in N/m.
    mesh : MeshTri, optional
        A ready mesh of the planform (nodes in m, the clamp at x = 0, a node at (L, 0)), as
        ``plate_modes`` takes; ``level`` then only labels the result.

    Returns
    -------
    StaticSolution
        Deflection of the mid-surface point (L, 0): tip position (L, 0, w) and displacement
        (0, 0, w) in m; ``dofs`` counts the free plate DOFs.
    """
    # looked up per call, as the modal truth does (a test replaces it to prove the budget comes
    # first)
    from .mesh import planform_tri_mesh

    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    lev = DEFAULT_PLATE_LEVEL if level is None else check_level(level)
    L = beam.length_m
    t0 = time.perf_counter()
    if mesh is None:
        check_plate_budget(beam, lev, "argyris")
        mesh = planform_tri_mesh(beam, lev)
    check_dofs("plate-argyris", lev, PLATE_DOFS_PER_NODE["argyris"] * mesh.p.shape[1]
               + PLATE_DOFS_PER_EDGE * mesh.facets.shape[1], beam)
    t1 = time.perf_counter()
    # a new element object per basis: the element caches per-mesh and per-point state
    basis = plate_basis(beam, mesh, ElementTriArgyrisLocal())
    tol = 1e-9 * L
    tip_facets = mesh.facets_satisfying(lambda x: np.abs(x[0] - L) < tol)
    fbasis = FacetBasis(mesh, ElementTriArgyrisLocal(), facets=tip_facets)
    t2 = time.perf_counter()
    D, rho_t = plate_section(beam, basis)
    K, _ = assemble_plate(basis, D, beam.material.nu, rho_t)
    f = tip_edge_load(beam, fbasis, F[2])
    clamped = basis.get_dofs(lambda x: np.abs(x[0]) < tol).all(ROOT_CLAMP_DOFS["argyris"])
    free = np.setdiff1d(np.arange(basis.N), clamped)
    Kf = K[free][:, free].tocsc()
    t3 = time.perf_counter()
    u = np.zeros(basis.N)
    u[free] = spd_solve(Kf, f[free])
    t4 = time.perf_counter()
    node = np.flatnonzero((np.abs(mesh.p[0] - L) < tol) & (mesh.p[1] == 0.0))
    if node.size != 1:
        raise TruthError(f"{beam.name!r}: plate mesh has {node.size} nodes at (L, 0)")
    disp = np.array([0.0, 0.0, u[basis.nodal_dofs[0, node[0]]]])
    return StaticSolution(
        model="plate-argyris",
        nonlinear=False,
        tip_force_N=F.copy(),
        tip_position_m=np.array([L, 0.0, 0.0]) + disp,
        tip_displacement_m=disp,
        dofs=int(free.size),
        mesh_level=lev,
        load_steps=1,
        timings=Timings(mesh_s=t1 - t0, basis_s=t2 - t1, assembly_s=t3 - t2, solve_s=t4 - t3),
    )
