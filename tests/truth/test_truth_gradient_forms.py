"""The plate truth gradient's element integrals and their shape derivatives (truth_gradient's
planform part) against independent references: scikit-fem's own Argyris basis and facet
assembly on the truth's mesh, and finite differences of that basis on the moved mesh."""

from __future__ import annotations

import numpy as np
import pytest
from paths import BEAMS
from skfem import Basis, FacetBasis, LinearForm, MeshTri, asm
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.truth.argyris_forms import (
    argyris_coefficients,
    argyris_edge_integrals,
    argyris_plate_forms,
    monomial_table,
)
from prbdm_pin.truth.mesh import planform_tri_mesh
from prbdm_pin.truth.morph import morph_plane
from prbdm_pin.truth.plate import plate_modes
from prbdm_pin.truth.plate_elements import ElementTriArgyrisLocal
from prbdm_pin.truth.plate_shape import node_velocities, plate_form_derivatives
from prbdm_pin.truth.shape_forms import plate_element_forms


@LinearForm
def _unit(v, w):
    return 1.0 * v


def _setup(name: str, level: int = 0):
    beam = pp.load_beam(BEAMS / f"{name}.json")
    mesh = planform_tri_mesh(beam, level)
    pm = plate_modes(beam, level, 6, "argyris", mesh=mesh)
    return beam, mesh, pm.basis, pm.phi[:, :4]


def _tip_elements(mesh: MeshTri, L: float):
    on = np.abs(mesh.p[0, mesh.t] - L) < 1e-9 * L
    el = np.flatnonzero(on.sum(axis=0) == 2)
    ends = np.array([[1, 0, 0], [2, 2, 1]])[:, np.argmin(on[:, el], axis=0)]
    return el, ends


def _sums(mesh: MeshTri, p: np.ndarray, vectors: np.ndarray, L: float) -> np.ndarray:
    """Sums of the forms (k1, k2, mass per vector) and the tip-edge integrals of ``vectors`` on
    the mesh moved to nodes p, by scikit-fem's basis and facet assembly."""
    moved = MeshTri(p, mesh.t)
    basis = Basis(moved, ElementTriArgyrisLocal())
    c = vectors[basis.element_dofs]
    forms = [f.sum(axis=0) for f in plate_element_forms(basis, c, c)]
    facets = moved.facets_satisfying(lambda x: np.abs(x[0] - L) < 1e-9 * L)
    edge = asm(_unit, FacetBasis(moved, ElementTriArgyrisLocal(), facets=facets)) @ vectors
    return np.concatenate([*forms, edge])


@pytest.mark.parametrize("name", ["stepped-narrow", "reference-random"])
def test_direct_forms_are_the_basis_forms(name):
    # the same integrals from the vertex coordinates (one solve per element) and from
    # scikit-fem's basis of the element (its inverse DOF matrix, evaluated by skfem's mapping)
    beam, mesh, basis, phi = _setup(name)
    vec = phi
    c = vec[basis.element_dofs]
    left, right = np.array([0, 1, 3]), np.array([0, 2, 1])
    ref = plate_element_forms(basis, c[:, :, left], c[:, :, right])
    v = mesh.p[:, mesh.t]
    a, centre, size = argyris_coefficients(v, mesh.t, c)
    got = argyris_plate_forms(v, a, centre, size, left, right, basis.X, basis.W)
    for r, g in zip(ref, got, strict=True):
        scale = np.abs(r).max(axis=0)
        assert np.all(np.abs(g - r) <= 1e-10 * scale), np.abs(g - r).max(axis=0) / scale
    el, ends = _tip_elements(mesh, beam.length_m)
    edge = argyris_edge_integrals(v[:, :, el], a[el], centre[:, el], size[el], ends).sum(axis=0)
    facets = mesh.facets_satisfying(lambda x: np.abs(x[0] - beam.length_m) < 1e-9)
    ref_edge = asm(_unit, FacetBasis(mesh, ElementTriArgyrisLocal(), facets=facets)) @ vec
    # atol for the entries that cancel: a few EPS of the largest (7 EPS measured); kept: the
    # test's 1e-14 of it
    np.testing.assert_allclose(edge, ref_edge, rtol=1e-11,
                               atol=50 * EPS * np.abs(ref_edge).max())


def test_monomial_derivatives_against_finite_differences():
    xi, eta = np.array([0.3, -0.7]), np.array([-0.2, 0.45])
    h = 1e-6
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1), (2, 0)):
        d = monomial_table(xi, eta, ((dx + 1, dy), (dx, dy + 1)))
        fd_x = (monomial_table(xi + h, eta, ((dx, dy),)) - monomial_table(xi - h, eta,
                                                                          ((dx, dy),))) / (2 * h)
        fd_y = (monomial_table(xi, eta + h, ((dx, dy),)) - monomial_table(xi, eta - h,
                                                                          ((dx, dy),))) / (2 * h)
        np.testing.assert_allclose(d[:, 0], fd_x[:, 0], rtol=0, atol=1e-8)
        np.testing.assert_allclose(d[:, 1], fd_y[:, 0], rtol=0, atol=1e-8)


def test_node_velocities_of_the_affine_morph():
    # the velocity from one step predicts the morph at another (far larger) step exactly
    beam, mesh, _, _ = _setup("stepped-narrow")
    d = pp.Design(beam, ("half_width[1]", "half_width[3]", "x[2]"))
    for row in range(d.size):
        vel, d_w = node_velocities(d, row, mesh.p)
        step = np.zeros(d.size)
        step[row] = 0.3 * d.scales[row]
        b = d.beam_at(d.values + step)
        # an affine map either way: a few roundings of 1 m coordinates (8 EPS measured);
        # kept: the test's 1e-12 m
        np.testing.assert_allclose(morph_plane(beam, b, mesh.p), mesh.p + step[row] * vel,
                                   rtol=0, atol=5000 * EPS)
        assert d_w == pytest.approx((b.half_width_at(1.0) - beam.half_width_at(1.0))
                                    / step[row], rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("name, variables", [
    ("stepped-narrow", ("half_width[2]", "half_width[3]", "x[2]")),
    ("tapered", ("half_width[0]", "half_width[1]")),
])
def test_shape_derivatives_against_finite_differences_of_the_basis(name, variables):
    # complex step through the direct element integrals against fourth-order differences of
    # scikit-fem's basis on the whole moved mesh (unmoved elements cancel exactly)
    beam, mesh, basis, phi = _setup(name)
    d = pp.Design(beam, variables)
    n = phi.shape[1]
    pairs = np.arange(n)
    # the tip-edge integral of the first mode (bending: not zero by symmetry)
    got = plate_form_derivatives(d, list(range(d.size)), basis, phi, pairs, pairs, 0)
    for row in range(d.size):
        h = 1e-4 * d.scales[row]
        e = np.zeros(d.size)
        e[row] = h
        s = {k: _sums(mesh, morph_plane(beam, d.beam_at(d.values + k * e), mesh.p), phi,
                      beam.length_m) for k in (-2, -1, 1, 2)}
        fd = (8.0 * (s[1] - s[-1]) - (s[2] - s[-2])) / (12.0 * h)
        mine = np.concatenate([got.k1[row], got.k2[row], got.mass[row],
                               np.r_[got.tip_edge[row], np.zeros(n - 1)]])
        fd[3 * n + 1:] = 0.0  # only the first vector's edge integral is differentiated
        base = _sums(mesh, mesh.p, phi, beam.length_m)
        ref = np.maximum(np.abs(fd), 1e-3 * np.abs(base) / d.scales[row])
        assert np.all(np.abs(mine - fd) <= 1e-6 * ref), (d.names[row], np.abs(mine - fd) / ref)
