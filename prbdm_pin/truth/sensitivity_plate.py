"""Design sensitivities of the Kirchhoff plate truth (Argyris): frequencies and linear tip.

The truth is solved once on its own mesh (the modes of ``plate_modes``, classified and selected
as ``compute_truth`` does, and the tip-load case of ``plate_static``). Thickness and material
derivatives are closed-form scalings of the forms; planform derivatives move the mesh with the
planform (``morph``) on its fixed topology and differentiate the element integrals of the fixed
modes and static/adjoint fields by central differences over the elements that move
(semi-analytic: no re-solve, no assembly; fourth-order differences, see
``sensitivity_rules.STEP_REL``).
"""

from __future__ import annotations

import time

import numpy as np
from skfem import Basis, MeshTri

from ..design import Design
from ..errors import TruthError
from .mesh import planform_tri_mesh
from .mesh_budget import check_plate_budget
from .modes import select_modes
from .morph import morph_plane
from .plate import ROOT_CLAMP_DOFS, assemble_plate, classified_plate_modes, plate_modes
from .plate_elements import ElementTriArgyrisLocal
from .plate_static import spd_solve
from .sensitivity_rules import (
    STENCIL,
    STEP_REL,
    check_gaps,
    material_forms,
    omega_derivative,
    stencil_derivative,
    tip_derivative,
)
from .shape_forms import copies_tri_mesh, plate_element_forms, tip_edge_integrals

__all__ = ["plate_sensitivity"]

def plate_sensitivity(design: Design, level: int, modes: int, selection: str,
                      n_computed: int, static: bool, mesh: MeshTri | None = None) -> dict:
    """Frequencies, tip deflection and their design derivatives of the plate truth (on its own
    mesh of ``level``, or on ``mesh``, a mesh of ``design.beam``'s planform).

    Returns a dict of plain arrays (``truth_gradient`` wraps it): ``mode_index``,
    ``omega_rad_s``, ``d_omega_rad_s`` (modes, n), ``tip_z_m``, ``d_tip_z_m`` (n,),
    ``solve_s``, ``gradient_s``, ``dofs``.
    """
    beam = design.beam
    t0 = time.perf_counter()
    if mesh is None:
        check_plate_budget(beam, level, "argyris")
        mesh = planform_tri_mesh(beam, level)
    pm = plate_modes(beam, level, n_computed, "argyris", mesh=mesh)
    lam_all = np.sign(pm.omega_rad_s) * pm.omega_rad_s**2
    if np.any(lam_all <= 0.0) or not np.all(np.isfinite(lam_all)):
        raise TruthError(f"plate model of {beam.name!r} (level {level}) has non-positive "
                         "eigenvalues: the mesh or the solve cannot be trusted")
    modal = classified_plate_modes(beam, pm, level)
    try:
        index = select_modes(modal, modes, selection)
    except ValueError as exc:
        raise TruthError(f"{beam.name!r}: {exc}") from exc
    check_gaps(beam.name, lam_all, index)
    basis = pm.basis
    dofs = basis.element_dofs  # (21, nel)
    phi = pm.phi[:, index]
    omega = pm.omega_rad_s[index]
    mat = beam.material
    D = mat.E_Pa * beam.thickness_m**3 / (12.0 * (1.0 - mat.nu**2))
    rho_h = mat.rho_kg_m3 * beam.thickness_m
    L = beam.length_m
    Fz = float(beam.tip_force_N[2])
    tip_elems = np.flatnonzero((np.abs(mesh.p[0, mesh.t] - L) < 1e-9 * L).sum(axis=0) >= 2)
    if static:
        K, _ = assemble_plate(basis, D, mat.nu, rho_h)
        clamped = basis.get_dofs(lambda x: np.abs(x[0]) < 1e-9 * L).all(ROOT_CLAMP_DOFS["argyris"])
        free = np.setdiff1d(np.arange(basis.N), clamped)
        g, tind = tip_edge_integrals(copies_tri_mesh(mesh.t, tip_elems, [mesh.p]), L)
        f = np.zeros(basis.N)
        np.add.at(f, dofs[:, tip_elems[tind]].T, g * Fz / (2.0 * beam.half_width_at(L)))
        node = np.flatnonzero((np.abs(mesh.p[0] - L) < 1e-9 * L) & (mesh.p[1] == 0.0))
        if node.size != 1:
            raise TruthError(f"{beam.name!r}: plate mesh has {node.size} nodes at (L, 0)")
        c = np.zeros(basis.N)
        c[basis.nodal_dofs[0, node[0]]] = 1.0
        sol = np.zeros((basis.N, 2))
        sol[free] = spd_solve(K[free][:, free].tocsc(), np.column_stack([f, c])[free])
        u, adj = sol[:, 0], sol[:, 1]
        tip_z = float(u[basis.nodal_dofs[0, node[0]]])
        vecs = np.column_stack([phi, u])
        avecs = np.column_stack([phi, adj])
    else:
        tip_z = None
        vecs = avecs = phi
    t1 = time.perf_counter()

    n = design.size
    m = index.size
    d_omega = np.zeros((m, n))
    d_tip = np.zeros(n)
    # the forms at the design itself (the modal solve's own basis): Rayleigh quotients of the
    # modes and the static a^T K u
    k1, k2, mm = (s.sum(axis=0) for s in plate_element_forms(basis, avecs[dofs], vecs[dofs]))
    qk = D * ((1.0 - mat.nu) * k1 + mat.nu * k2)
    qm = rho_h * mm
    # thickness and material: closed-form scalings of the forms
    kinds = design.kinds
    for row, (kind, i) in enumerate(kinds):
        if i >= 0:
            continue
        dqk, dqm = material_forms(kind, beam, True, qk, qm, k1, k2)
        d_omega[:, row] = omega_derivative(omega, dqk[:m], dqm[:m], qk[:m], qm[:m])
        if static:  # the load does not depend on t or the material
            d_tip[row] = tip_derivative(tip_z, 0.0, dqk[m], qk[m])
    # the planform: element integrals on moved copies of the elements that move
    p0 = design.values
    scales = design.scales
    for row, (_, i) in enumerate(kinds):
        if i < 0:
            continue
        h = STEP_REL * scales[row]
        e = np.zeros(n)
        e[row] = h
        beams = [design.beam_at(p0 + k * e) for k, _ in STENCIL]
        pos = [morph_plane(beam, b, mesh.p) for b in beams]
        moved = np.any([np.any(q != mesh.p, axis=0) for q in pos], axis=0)
        tip_moves = bool(np.any(moved & (np.abs(mesh.p[0] - L) < 1e-9 * L)))
        elems = np.flatnonzero(moved[mesh.t].any(axis=0))
        if tip_moves:
            elems = np.union1d(elems, tip_elems)
        copies = copies_tri_mesh(mesh.t, elems, pos)
        cb = Basis(copies, ElementTriArgyrisLocal())
        nc, ne = len(pos), elems.size
        k1, k2, mm = plate_element_forms(cb, np.concatenate([avecs[dofs[:, elems]]] * nc, axis=1),
                                         np.concatenate([vecs[dofs[:, elems]]] * nc, axis=1))
        qk_c = (D * ((1.0 - mat.nu) * k1 + mat.nu * k2)).reshape(nc, ne, -1).sum(axis=1)
        qm_c = rho_h * mm.reshape(nc, ne, -1).sum(axis=1)
        dqk = stencil_derivative(list(qk_c), h)
        dqm = stencil_derivative(list(qm_c), h)
        d_omega[:, row] = omega_derivative(omega, dqk[:m], dqm[:m], qk[:m], qm[:m])
        if static:
            d_load = 0.0
            if tip_moves:
                g, tind = tip_edge_integrals(copies, L)
                a_loc = adj[dofs[:, elems[tind % ne]]].T  # (nf, 21)
                part = np.bincount(tind // ne, np.einsum("fi,fi->f", g, a_loc), minlength=nc)
                q = [Fz / (2.0 * b.half_width_at(L)) for b in beams]
                d_load = stencil_derivative([qc * pc for qc, pc in zip(q, part, strict=True)],
                                            h)
            d_tip[row] = tip_derivative(tip_z, d_load, dqk[m], qk[m])
    t2 = time.perf_counter()
    return dict(mode_index=index, omega_rad_s=omega, d_omega_rad_s=d_omega, tip_z_m=tip_z,
                d_tip_z_m=d_tip if static else None, solve_s=t1 - t0, gradient_s=t2 - t1,
                dofs=int(pm.dofs), mesh_level=level)
