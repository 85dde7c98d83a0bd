"""Kirchhoff plate modal truth: Argyris (conforming, from above) and Morley (from below).

The elements (``plate_elements``) are built in scaled element-local coordinates; the stiffness
and mass forms here are contracted over all basis pairs at once, and the clamped-free plate's
modes are classified for the bending-mode selection.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from skfem import Basis, BilinearForm, MeshTri
from skfem.helpers import dd, ddot, eye, trace

from ..member.geometry import Beam
from .plate_elements import PLATE_ELEMENTS
from .result import ModalSolution, Timings
from .settings import lanczos_start

__all__ = [
    "PlateModes",
    "plate_modes",
    "plate_modal",
    "classified_plate_modes",
    "plate_forms",
    "assemble_plate",
    "plate_rigidity_Nm",
    "plate_section",
    "plate_basis",
    "ROOT_CLAMP_DOFS",
]

# Along the clamped edge x = 0: u = u_x = 0 for every y, hence u_y = u_yy = u_xy = 0 too; u_xx is
# not constrained (clamping it over-stiffens the plate by ~0.4 %).
ROOT_CLAMP_DOFS = {
    "argyris": ("u", "u_x", "u_y", "u_xy", "u_yy", "u_n"),
    "morley": ("u", "u_n"),
}


def plate_rigidity_Nm(beam: Beam) -> float:
    """Flexural rigidity D = E t^3 / (12 (1 - nu^2)) of the beam's plate, N m.

    One thickness only (a law is refused by name): ``plate_section`` takes the law.
    """
    mat = beam.material
    return mat.E_Pa * beam.uniform_thickness_m("the plate truth")**3 / (12.0 * (1.0 - mat.nu**2))


def plate_section(beam: Beam, basis: Basis) -> tuple[float | np.ndarray, float | np.ndarray]:
    """Flexural rigidity D (N m) and mass per area rho t (kg/m^2) for ``assemble_plate``.

    Floats for a uniform thickness; with a thickness law t(x), arrays (elements, quadrature
    points) of D(x) = E t(x)^3 / (12 (1 - nu^2)) and rho t(x) at the basis's quadrature points.
    The mesh has edges along every station of the law (``mesh.law_stations``), so t is linear in
    each element and ``plate_basis``'s quadrature integrates both exactly.
    """
    beam.rectangle_only("the plate truth")  # a round or table member is no plate
    mat = beam.material
    if beam.thickness_law_m is None:
        return plate_rigidity_Nm(beam), mat.rho_kg_m3 * beam.thickness_m
    t = beam.thickness_at(basis.global_coordinates()[0])
    return mat.E_Pa * t**3 / (12.0 * (1.0 - mat.nu**2)), mat.rho_kg_m3 * t


def plate_basis(beam: Beam, mesh: MeshTri, element) -> Basis:
    """Return the plate's scikit-fem basis of ``element`` (an element object) on ``mesh``.

    scikit-fem's default rule (degree 2 p for the degree-p element) is exact for a uniform
    thickness; a thickness law adds degree 3 to the stiffness (t^3, linear t) and 1 to the
    mass integrand, so its rule is 3 degrees higher.
    """
    beam.rectangle_only("the plate truth")
    if beam.thickness_law_m is None:
        return Basis(mesh, element)
    return Basis(mesh, element, intorder=2 * element.maxdeg + 3)


def plate_forms(D_Nm: float, nu: float, rho_h_kg_m2: float):
    """Return the Kirchhoff plate's stiffness and mass bilinear forms (scikit-fem).

    Parameters
    ----------
    D_Nm : float
        Flexural rigidity E t^3 / (12 (1 - nu^2)), N m.
    nu : float
        Poisson's ratio.
    rho_h_kg_m2 : float
        Mass per unit area, kg/m^2.
    """
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


def assemble_plate(basis: Basis, D_Nm: float, nu: float, rho_h_kg_m2: float):
    """Assemble the plate stiffness and mass matrices.

    The same forms as ``plate_forms`` but contracted over all basis-function pairs at once
    (scikit-fem's ``asm`` loops over the 21 x 21 pairs, which dominated the solve time).
    ``D_Nm`` and ``rho_h_kg_m2`` are floats or arrays (elements, quadrature points) of a
    thickness law (``plate_section``).
    """
    from scipy.sparse import coo_matrix

    dx = basis.dx  # (nel, nq)
    H = np.stack([b[0].hess for b in basis.basis])  # (Nd, 2, 2, nel, nq)
    V = np.stack([np.asarray(b[0]) for b in basis.basis])  # (Nd, nel, nq)
    B = np.stack([H[:, 0, 0], H[:, 1, 1], np.sqrt(2.0) * H[:, 0, 1]], axis=1)
    T = H[:, 0, 0] + H[:, 1, 1]
    if np.ndim(D_Nm) == 0 and np.ndim(rho_h_kg_m2) == 0:
        Ke = D_Nm * ((1.0 - nu) * np.einsum("icEq,jcEq,Eq->Eij", B, B, dx, optimize=True)
                     + nu * np.einsum("iEq,jEq,Eq->Eij", T, T, dx, optimize=True))
        Me = rho_h_kg_m2 * np.einsum("iEq,jEq,Eq->Eij", V, V, dx, optimize=True)
    else:
        dxD = dx * D_Nm  # D(x) at the quadrature points joins the weights
        Ke = ((1.0 - nu) * np.einsum("icEq,jcEq,Eq->Eij", B, B, dxD, optimize=True)
              + nu * np.einsum("iEq,jEq,Eq->Eij", T, T, dxD, optimize=True))
        Me = np.einsum("iEq,jEq,Eq->Eij", V, V, dx * rho_h_kg_m2, optimize=True)
    dofs = basis.element_dofs  # (Nd, nel)
    rows = np.broadcast_to(dofs.T[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(dofs.T[:, None, :], Ke.shape).ravel()
    shape = (basis.N, basis.N)
    K = coo_matrix((Ke.ravel(), (rows, cols)), shape=shape).tocsr()
    M = coo_matrix((Me.ravel(), (rows, cols)), shape=shape).tocsr()
    return K, M


def _with_nu(section, nu: float):
    """(D, nu, rho t): ``assemble_plate``'s argument order from ``plate_section``'s pair."""
    return section[0], nu, section[1]


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
    rel_residual : ndarray, shape (k,), optional
        Each eigenpair's relative residual ||K y - lambda M y|| / (lambda ||M y||) on the
        scaled matrices: how far the shift-invert solve is from an exact eigenpair. On the
        refined meshes of jagged panels it is 1e-6 ... 1e-5 (the factorisation of K, condition
        near 1e10, leaves that much), and the frequencies then differ by as much between two
        BLAS kernels.
    """

    element: str
    omega_rad_s: np.ndarray
    phi: np.ndarray
    mesh: MeshTri
    basis: Basis
    M: object
    rz: np.ndarray
    timings: tuple[float, float, float, float]
    rel_residual: np.ndarray | None = None

    @property
    def dofs(self) -> int:
        """Number of DOFs of the discretisation."""
        return int(self.phi.shape[0])

    def nodal_uz(self) -> np.ndarray:
        """Return the z displacement of every mode at the mesh nodes, (k, n_nodes), m.

        The modes are mass-normalised.
        """
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

    if element not in PLATE_ELEMENTS:
        raise ValueError(f"element = {element!r}: must be one of {sorted(PLATE_ELEMENTS)}")
    t0 = time.perf_counter()
    if mesh is None:
        check_plate_budget(beam, level, element)
        mesh = planform_tri_mesh(beam, level)
    check_dofs(f"plate-{element}", level, PLATE_DOFS_PER_NODE[element] * mesh.p.shape[1]
               + PLATE_DOFS_PER_EDGE * mesh.facets.shape[1], beam)
    t1 = time.perf_counter()
    elem = PLATE_ELEMENTS[element]()  # a new element object per mesh: it caches per-mesh state
    basis = plate_basis(beam, mesh, elem)
    t2 = time.perf_counter()
    K, M = assemble_plate(basis, *_with_nu(plate_section(beam, basis), beam.material.nu))
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
    lam, y = eigsh(Ks, k=k, M=Ms, sigma=0.0, which="LM", v0=lanczos_start(Ks.shape[0]))
    order = np.argsort(lam)
    lam, y = lam[order], y[:, order]
    My = Ms @ y
    resid = np.linalg.norm(Ks @ y - My * lam, axis=0) / (np.abs(lam) * np.linalg.norm(My, axis=0))
    phi_f = s @ y
    t4 = time.perf_counter()
    phi = np.zeros((basis.N, k))
    phi[free] = phi_f
    rz = np.zeros(basis.N)
    rz[basis.nodal_dofs[0]] = 1.0
    omega = np.sqrt(np.abs(lam)) * np.sign(lam)
    return PlateModes(
        element=element, omega_rad_s=omega, phi=phi, mesh=mesh, basis=basis, M=M, rz=rz,
        timings=(t1 - t0, t2 - t1, t3 - t2, t4 - t3), rel_residual=resid,
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
    return classified_plate_modes(beam, plate_modes(beam, level, n_modes, element), level)


def classified_plate_modes(beam: Beam, pm: PlateModes, level: int) -> ModalSolution:
    """Return the ``ModalSolution`` of raw plate modes ``pm`` of ``beam`` at mesh ``level``.

    It adds z mass participation, symmetry about x and MAC with beam modes (``plate_modal``'s
    classification).
    """
    from .modes import beam_mac, mass_participation_z, symmetry_about_x

    element = pm.element
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
        eig_residual=pm.rel_residual,
    )
