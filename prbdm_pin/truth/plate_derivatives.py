"""Design sensitivities of the Kirchhoff plate truth (Argyris): frequencies and linear tip.

The truth is solved once on its own mesh (the modes of ``plate_modes``, classified and selected
as ``compute_truth`` does, and the tip-load case of ``plate_static``, with its adjoint).
Thickness and material derivatives are closed-form scalings of the forms; planform derivatives
move the mesh with the planform (``morph``) on its fixed topology and differentiate the element
integrals of the fixed modes and static/adjoint fields over the elements that move, by complex
step (``plate_shape``: semi-analytic, no re-solve, no assembly, exact to rounding).
"""

from __future__ import annotations

import time

import numpy as np
from skfem import FacetBasis, MeshTri

from ..errors import TruthError
from ..member.design import Design
from .derivative_rules import check_gaps, material_forms, omega_derivative, tip_derivative
from .mesh import planform_tri_mesh
from .mesh_budget import check_plate_budget
from .modes import select_modes
from .plate import (
    ROOT_CLAMP_DOFS,
    assemble_plate,
    classified_plate_modes,
    plate_modes,
    plate_rigidity_Nm,
)
from .plate_elements import ElementTriArgyrisLocal
from .plate_shape import plate_form_derivatives
from .plate_static import spd_solve, tip_edge_load
from .shape_forms import plate_element_forms

__all__ = ["plate_sensitivity"]

def plate_sensitivity(design: Design, level: int, modes: int, selection: str,
                      n_computed: int, static: bool, mesh: MeshTri | None = None) -> dict:
    """Compute the plate truth's frequencies, tip deflection and their design derivatives.

    The truth is solved on its own mesh of ``level``, or on ``mesh``, a mesh of
    ``design.beam``'s planform.

    Returns a dict of plain arrays (``truth_gradient`` wraps it): ``mode_index``,
    ``omega_rad_s``, ``d_omega_rad_s`` (modes, n), ``tip_z_m``, ``d_tip_z_m`` (n,),
    ``solve_s``, ``gradient_s`` (wall), ``solve_cpu_s``, ``gradient_cpu_s``, ``dofs``.
    """
    beam = design.beam
    t0, c0 = time.perf_counter(), time.process_time()
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
    D = plate_rigidity_Nm(beam)
    rho_h = mat.rho_kg_m3 * beam.uniform_thickness_m("the plate truth")
    L = beam.length_m
    Fz = float(beam.tip_force_N[2])
    if static:
        K, _ = assemble_plate(basis, D, mat.nu, rho_h)
        clamped = basis.get_dofs(lambda x: np.abs(x[0]) < 1e-9 * L).all(ROOT_CLAMP_DOFS["argyris"])
        free = np.setdiff1d(np.arange(basis.N), clamped)
        tip_facets = mesh.facets_satisfying(lambda x: np.abs(x[0] - L) < 1e-9 * L)
        f = tip_edge_load(beam, FacetBasis(mesh, ElementTriArgyrisLocal(), facets=tip_facets), Fz)
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
    t1, c1 = time.perf_counter(), time.process_time()

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
    # the planform: shape derivatives of the moved elements' integrals (complex step)
    rows = [row for row, (_, i) in enumerate(kinds) if i >= 0]
    if rows:
        # distinct vectors: the modes, then u and the adjoint; pairs (a, b) as in qk, qm
        vectors = np.column_stack([phi, u, adj]) if static else phi
        pairs = np.arange(m)
        left = np.r_[pairs, m + 1] if static else pairs
        right = np.r_[pairs, m] if static else pairs
        dq = plate_form_derivatives(design, rows, basis, vectors, left, right,
                                    m + 1 if static else None)
        w_tip = beam.half_width_at(L)
        for k, row in enumerate(rows):
            dqk = D * ((1.0 - mat.nu) * dq.k1[k] + mat.nu * dq.k2[k])
            dqm = rho_h * dq.mass[k]
            d_omega[:, row] = omega_derivative(omega, dqk[:m], dqm[:m], qk[:m], qm[:m])
            if static:
                # the load q = F_z / (2 w(L)) along the tip edge: q and the edge both move (the
                # adjoint's edge integral at the design is a^T f / q)
                d_load = Fz / (2.0 * w_tip) * dq.tip_edge[k] - dq.d_tip_half_width[k] / w_tip * (
                    adj @ f)
                d_tip[row] = tip_derivative(tip_z, d_load, dqk[m], qk[m])
    t2, c2 = time.perf_counter(), time.process_time()
    return dict(mode_index=index, omega_rad_s=omega, d_omega_rad_s=d_omega, tip_z_m=tip_z,
                d_tip_z_m=d_tip if static else None, solve_s=t1 - t0, gradient_s=t2 - t1,
                solve_cpu_s=c1 - c0, gradient_cpu_s=c2 - c1,
                dofs=int(pm.dofs), mesh_level=level)
