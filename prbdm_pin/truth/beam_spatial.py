"""The 1D truth's torsion and in-plane bending modes, beside its out-of-plane bending modes.

A planform symmetric about x has its shear centre on the axis, so the three families of the
straight clamped member are uncoupled and solved one by one on the same element edges
(``beam_stations``):

- ``bending`` (out of plane, about y): ``beam.beam_modes``, unchanged;
- ``in-plane`` (about z): the same Hermite elements with E I_z(x) = E t (2 w)^3 / 12 and the
  same mass rho A(x);
- ``torsion`` (about x): Saint-Venant torsion, G J(x) theta'' = rho I_p(x) theta_tt, clamped at
  the root, free at the tip, on quadratic Lagrange elements; J the exact Saint-Venant constant
  of the local rectangle 2 w(x) x t (``member.section.torsion_constant_m4``), I_p = I_y + I_z;
  a round member's J = I_p = pi (D^4 - d^4) / 32 (``member.section_law``; no warping).
  Warping restraint at the clamp (Vlasov) is left out: with the strip's warping constant
  Gamma = b^3 t^3 / 144 it stiffens the torsion modes by a fraction of order
  sqrt(E Gamma / (G J)) / L = (b / L) sqrt(E / (48 G)) (1 % for L = 20 b), which the plate and
  solid truths keep.

The merged ``ModalSolution`` holds all modes ascending in frequency, with ``kinds`` naming the
family of each; the torsion and in-plane modes have no z displacement on the axis (zero
``centerline_uz``, ``mpf_z``, ``mac_beam``; ``beam_mode_index`` -1), so every selection of
bending modes picks what the bending-only truth picks.
"""

from __future__ import annotations

import time

import numpy as np
from skfem import Basis, BilinearForm, ElementLineP2, MeshLine, asm
from skfem.helpers import grad

from ..member.geometry import Beam
from ..member.section import area_moment_z_m4, polar_area_moment_m4, torsion_constant_m4
from ..member.section_law import section_properties
from .beam import DENSE_MAX_DOFS, _assemble, _check_count, _eigh, beam_modal, beam_stations
from .result import ModalSolution, Timings

__all__ = ["BEAM_KINDS", "beam_spatial_modal", "beam_torsion_modes", "beam_in_plane_modes"]

# the families of the 1D truth, in the order they are solved
BEAM_KINDS = ("bending", "torsion", "in-plane")
# mass: rho I_p(x) is cubic in x (w linear), P2 x P2 quartic: degree 7, exact; stiffness: G J(x)
# is smooth on an element (linear in b for b >> t) against P1 x P1 gradients: the 4-point rule
# integrates it far below the discretisation error
_INTORDER = 7
# a round member: G J and rho I_x quartic in x (D, d linear), P2 x P2 mass: degree 8, exact
_INTORDER_SECTION = 8


@BilinearForm
def _torsion_stiffness(u, v, w):
    return w["GJ"] * grad(u)[0] * grad(v)[0]


@BilinearForm
def _rotary_mass(u, v, w):
    return w["rhoI"] * u * v


def _torsion_assemble(beam: Beam, n_elements: int):
    mesh = MeshLine(beam_stations(beam, n_elements))
    if beam.section is not None:  # a section law: G J, rho I_x, rho I_z from it
        basis = Basis(mesh, ElementLineP2(), intorder=_INTORDER_SECTION)
        sp = section_properties(beam, basis.global_coordinates()[0])
        K = asm(_torsion_stiffness, basis, GJ=sp.GJ_Nm2)
        M = asm(_rotary_mass, basis, rhoI=sp.rhoI_x_kg_m)
        Mz = asm(_rotary_mass, basis, rhoI=sp.rhoI_z_kg_m)
        root = int(np.argmin(mesh.p[0]))
        return mesh, basis, K, M, Mz, np.setdiff1d(np.arange(basis.N), basis.nodal_dofs[:, root])
    basis = Basis(mesh, ElementLineP2(), intorder=_INTORDER)
    xq = basis.global_coordinates()[0]
    b = 2.0 * beam.half_width_at(xq)
    t = beam.uniform_thickness_m("the 1D torsion truth")
    rho = beam.material.rho_kg_m3
    K = asm(_torsion_stiffness, basis, GJ=beam.material.G_Pa * torsion_constant_m4(b, t))
    M = asm(_rotary_mass, basis, rhoI=rho * polar_area_moment_m4(b, t))
    # the z motion's share of the rotary inertia: theta y moves in z, theta z in y
    Mz = asm(_rotary_mass, basis, rhoI=rho * area_moment_z_m4(b, t))
    root = int(np.argmin(mesh.p[0]))
    free = np.setdiff1d(np.arange(basis.N), basis.nodal_dofs[:, root])
    return mesh, basis, K, M, Mz, free


def beam_torsion_modes(beam: Beam, n_modes: int, n_elements: int = 200,
                       dense_max_dofs: int = DENSE_MAX_DOFS):
    """Saint-Venant torsion modes of the clamped-free member.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Number of modes (lowest first; fewer if the mesh has fewer DOFs).
    n_elements : int
        About this many quadratic elements along the span (vertices are element edges).
    dense_max_dofs : int
        Above this many free DOFs the eigenproblem is solved sparse.

    Returns
    -------
    omega_rad_s : ndarray, shape (k,)
        Ascending, rad/s.
    x_m : ndarray, shape (s,)
        The element edges, m, ascending.
    theta : ndarray, shape (k, s)
        Twist at the edges, arbitrary scale (unit maximum, positive at the tip).
    z_energy_fraction : ndarray, shape (k,)
        Share of each mode's kinetic energy in z motion, int rho I_z theta^2 / int rho I_p
        theta^2.
    dofs : int
        Free DOFs.
    """
    n_modes = _check_count("n_modes", n_modes)
    mesh, basis, K, M, Mz, free = _torsion_assemble(beam, n_elements)
    lam, vec = _eigh(K, M, free, n_modes, dense_max_dofs)
    phi = np.zeros((basis.N, lam.size))
    phi[free] = vec
    ez = np.einsum("ij,ij->j", phi, Mz @ phi) / np.einsum("ij,ij->j", phi, M @ phi)
    x = mesh.p[0]
    order = np.argsort(x)
    theta = phi[basis.nodal_dofs[0][order]].T
    theta = theta * (np.sign(theta[:, -1:]) / np.max(np.abs(theta), axis=1, keepdims=True))
    return np.sqrt(lam), x[order], theta, ez, int(free.size)


def beam_in_plane_modes(beam: Beam, n_modes: int, n_elements: int = 200,
                        dense_max_dofs: int = DENSE_MAX_DOFS):
    """In-plane bending modes (about z) of the clamped-free member.

    Parameters and returns as :func:`beam_torsion_modes`, without the energy fraction: the
    third array is the y deflection at the edges (unit maximum, positive at the tip).
    """
    n_modes = _check_count("n_modes", n_modes)
    mesh, basis, K, M, u_dofs, free = _assemble(beam, n_elements, in_plane=True)
    lam, vec = _eigh(K, M, free, n_modes, dense_max_dofs)
    phi = np.zeros((basis.N, lam.size))
    phi[free] = vec
    x = mesh.p[0]
    order = np.argsort(x)
    uy = phi[u_dofs[order]].T
    uy = uy * (np.sign(uy[:, -1:]) / np.max(np.abs(uy), axis=1, keepdims=True))
    return np.sqrt(lam), x[order], uy, int(free.size)


def beam_spatial_modal(beam: Beam, n_modes: int = 10, n_elements: int = 200,
                       dense_max_dofs: int = DENSE_MAX_DOFS) -> ModalSolution:
    """Out-of-plane bending, torsion and in-plane bending modes of the 1D member, merged.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Modes of each family (lowest first): the solution holds up to 3 ``n_modes``.
    n_elements : int
        About this many elements along the span, for every family.
    dense_max_dofs : int
        As in :func:`~prbdm_pin.truth.beam.beam_modal`.

    Returns
    -------
    ModalSolution
        All modes ascending in ``omega_rad_s`` (rad/s), ``kinds`` the family of each
        (``"bending"``, ``"torsion"``, ``"in-plane"``). The bending modes carry what
        ``beam_modal`` gives them, bit for bit; the torsion and in-plane modes have zero z mass
        participation, centreline z displacement and beam MAC, ``beam_mode_index`` -1,
        ``symmetric`` False for torsion (u_z = theta y) and True for in-plane (u_z = 0), and
        ``z_energy_fraction`` 1 (bending), int I_z theta^2 / int I_p theta^2 (torsion), 0
        (in-plane).
    """
    n_modes = _check_count("n_modes", n_modes)
    t0 = time.perf_counter()
    bend = beam_modal(beam, n_modes, n_elements, dense_max_dofs=dense_max_dofs)
    w_t, _, _, ez_t, dofs_t = beam_torsion_modes(beam, n_modes, n_elements, dense_max_dofs)
    w_v, _, _, dofs_v = beam_in_plane_modes(beam, n_modes, n_elements, dense_max_dofs)
    t1 = time.perf_counter()
    nb, nt, nv = bend.omega_rad_s.size, w_t.size, w_v.size
    kinds = np.array(("bending",) * nb + ("torsion",) * nt + ("in-plane",) * nv)
    omega = np.concatenate([bend.omega_rad_s, w_t, w_v])
    # stable: the bending modes keep their order among themselves whatever ties there are
    order = np.argsort(omega, kind="stable")
    zeros = np.zeros(nt + nv)
    s = bend.centerline_x_m.size

    def merged(bending_part, other):
        return np.concatenate([np.asarray(bending_part), other])[order]

    uz = np.concatenate([bend.centerline_uz, np.zeros((nt + nv, s))])[order]
    return ModalSolution(
        model="beam",
        omega_rad_s=omega[order],
        mpf_z=merged(bend.mpf_z, zeros),
        mpf_z_fraction=merged(bend.mpf_z_fraction, zeros),
        symmetric=merged(bend.symmetric, np.r_[np.zeros(nt, bool), np.ones(nv, bool)]),
        mac_beam=merged(bend.mac_beam, zeros),
        beam_mode_index=merged(bend.beam_mode_index, np.full(nt + nv, -1)),
        centerline_x_m=bend.centerline_x_m.copy(),
        centerline_uz=uz,
        dofs=int(bend.dofs) + dofs_t + dofs_v,
        mesh_level=bend.mesh_level,
        timings=Timings(assembly_s=bend.timings.assembly_s,
                        solve_s=(t1 - t0) - bend.timings.assembly_s),
        nodes_m=bend.nodes_m,
        cells=bend.cells,
        cell_type=bend.cell_type,
        node_uz=uz.copy(),
        z_energy_fraction=merged(np.ones(nb), np.r_[ez_t, np.zeros(nv)]),
        kinds=tuple(str(k) for k in kinds[order]),
    )
