"""Design sensitivities of the 1D Euler-Bernoulli truth: frequencies and linear tip deflection.

The modes of ``beam_modes`` (selected as ``compute_truth`` selects them) and the tip-load solve
of ``beam_static``; thickness and material derivatives are closed-form scalings of the forms,
planform derivatives move the element edges with the planform (``morph_x``) and differentiate
the element integrals (EI u'' v'', rho A u v, with EI(x) and rho A(x) of the moved planform) by
complex step (``sensitivity_rules.COMPLEX_STEP``) over the elements that move.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg

from ..errors import TruthError
from ..member.design import Design
from .beam import beam_modal_solution, beam_modes, beam_stations
from .derivative_rules import (
    COMPLEX_STEP,
    VELOCITY_STEP,
    check_gaps,
    material_forms,
    omega_derivative,
    tip_derivative,
)
from .modes import select_modes
from .morph import morph_x
from .shape_forms import GAUSS_1D, hermite_forms

__all__ = ["beam_sensitivity"]


def _quadrature_x(xa, xb):
    """Stations (nel, 4) of the ``GAUSS_1D`` points of elements [xa, xb] (m)."""
    return xa[:, None] + (xb - xa)[:, None] * GAUSS_1D[0]


def _forms(beam, xa, xb, w, a, b):
    """Return the element forms (k, mass), each (nel, m), of the Hermite fields a, b.

    The elements are [xa, xb], the half-width w (nel, 4) is given at the quadrature points (m;
    all may be complex).
    """
    t = beam.uniform_thickness_m("the 1D truth's shape derivatives")
    return hermite_forms(xa, xb, beam.material.E_Pa * 2.0 * w * t**3 / 12.0,
                         beam.material.rho_kg_m3 * 2.0 * w * t, a, b)


def beam_sensitivity(design: Design, modes: int, selection: str, n_computed: int,
                     static: bool, n_elements: int = 200) -> dict:
    """Compute the 1D beam truth's frequencies, tip deflection and their design derivatives.

    Returns the dict of ``plate_sensitivity`` (``mesh_level`` None).
    """
    beam = design.beam
    t0, c0 = time.perf_counter(), time.process_time()
    xs = beam_stations(beam, n_elements)
    raw = beam_modes(beam, min(n_computed, 2 * xs.size - 2), n_elements, xs)
    mesh, basis, K, M, u_dofs, free, lam_all, phi_all, _ = raw
    modal = beam_modal_solution(beam, *raw)
    try:
        index = select_modes(modal, modes, selection)
    except ValueError as exc:
        raise TruthError(f"{beam.name!r}: {exc}") from exc
    check_gaps(beam.name, lam_all, index)
    phi = phi_all[:, index]
    omega = np.sqrt(lam_all[index])
    dofs = basis.element_dofs  # (4, nel): u, u_x at the element's first and second node
    order = np.argsort(mesh.p[0])
    if not np.array_equal(mesh.t[0], order[:-1]) or not np.array_equal(mesh.t[1], order[1:]):
        raise TruthError("1D mesh elements are not ordered along x")
    tip = int(np.argmax(mesh.p[0]))
    if static:
        f = np.zeros(basis.N)
        f[basis.nodal_dofs[0, tip]] = beam.tip_force_N[2]
        c = np.zeros(basis.N)
        c[basis.nodal_dofs[0, tip]] = 1.0
        Kf = K[free][:, free].toarray()
        u, adj = np.zeros(basis.N), np.zeros(basis.N)
        # one right-hand side per call, as beam_static solves: the same rounding as the truth's
        u[free] = scipy.linalg.solve(Kf, f[free], assume_a="pos")
        adj[free] = scipy.linalg.solve(Kf, c[free], assume_a="pos")
        tip_z = float(u[basis.nodal_dofs[0, tip]])
        vecs, avecs = np.column_stack([phi, u]), np.column_stack([phi, adj])
    else:
        tip_z = None
        vecs = avecs = phi
    t1, c1 = time.perf_counter(), time.process_time()

    n, m = design.size, index.size
    d_omega = np.zeros((m, n))
    d_tip = np.zeros(n)
    X = mesh.p[0]
    xa, xb = X[mesh.t[0]], X[mesh.t[1]]
    k0, m0 = _forms(beam, xa, xb, beam.half_width_at(_quadrature_x(xa, xb)), avecs[dofs],
                    vecs[dofs])
    qk, qm = k0.sum(axis=0), m0.sum(axis=0)
    for row, (kind, i) in enumerate(design.kinds):
        if i >= 0:
            continue
        dqk, dqm = material_forms(kind, beam, False, qk, qm)
        d_omega[:, row] = omega_derivative(omega, dqk[:m], dqm[:m], qk[:m], qm[:m])
        if static:
            d_tip[row] = tip_derivative(tip_z, 0.0, dqk[m], qk[m])
    p0, scales = design.values, design.scales
    for row, (_, i) in enumerate(design.kinds):
        if i < 0:
            continue
        h = VELOCITY_STEP * scales[row]
        e = np.zeros(n)
        e[row] = h
        # vertex i moves (or widens) the elements between its neighbouring stations only
        xv = beam.x_m
        lo = xv[xv < xv[i]].max(initial=0.0)
        hi = xv[xv > xv[i]].min(initial=beam.length_m)
        el = np.flatnonzero((xa >= lo) & (xb <= hi))
        # the element ends and the half-width at the moving quadrature points are affine in
        # the variable (they keep their relative place in the vertex interval): their
        # velocities are central differences, exact to rounding
        ends, widths = [], []
        for b in (design.beam_at(p0 + e), design.beam_at(p0 - e)):
            Xb = morph_x(beam, b, X)
            ends.append(np.stack([Xb[mesh.t[0, el]], Xb[mesh.t[1, el]]]))
            widths.append(b.half_width_at(_quadrature_x(*ends[-1])))
        tau = 1j * COMPLEX_STEP / (2.0 * h)
        xe = np.stack([xa[el], xb[el]]) + tau * (ends[0] - ends[1])
        w = beam.half_width_at(_quadrature_x(xa[el], xb[el])) + tau * (widths[0] - widths[1])
        k, mm = _forms(beam, xe[0], xe[1], w, avecs[dofs[:, el]], vecs[dofs[:, el]])
        dqk = k.imag.sum(axis=0) / COMPLEX_STEP
        dqm = mm.imag.sum(axis=0) / COMPLEX_STEP
        d_omega[:, row] = omega_derivative(omega, dqk[:m], dqm[:m], qk[:m], qm[:m])
        if static:  # a point load at the tip node: f does not depend on the planform
            d_tip[row] = tip_derivative(tip_z, 0.0, dqk[m], qk[m])
    t2, c2 = time.perf_counter(), time.process_time()
    return dict(mode_index=index, omega_rad_s=omega, d_omega_rad_s=d_omega, tip_z_m=tip_z,
                d_tip_z_m=d_tip if static else None, solve_s=t1 - t0, gradient_s=t2 - t1,
                solve_cpu_s=c1 - c0, gradient_cpu_s=c2 - c1,
                dofs=int(free.size), mesh_level=None)
