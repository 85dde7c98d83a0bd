"""Design variables: values, bounds and beams of a vector; the mesh that follows the planform."""

from __future__ import annotations

import numpy as np
import pytest
from paths import BEAMS
from skfem import MeshTri
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.truth.mesh import planform_tri_mesh
from prbdm_pin.truth.morph import morph_plane


def test_values_units_and_beam_at():
    beam = pp.load_beam(BEAMS / "stepped-narrow.json")
    d = pp.Design(beam, ("thickness", "half_width[1]", "x[2]", "E", "rho", "nu"))
    np.testing.assert_array_equal(d.values, [0.005, 0.02, 0.4, 205e9, 7850.0, 0.28])
    assert d.units == ("m", "m", "m", "Pa", "kg/m^3", "1")
    b = d.beam_at([0.006, 0.03, 0.5, 1e11, 2700.0, 0.33])
    # x[2] names the width step: both of its vertices move
    np.testing.assert_array_equal(b.x_m, [0.0, 0.5, 0.5, 1.0])
    np.testing.assert_array_equal(b.half_width_m, [0.02, 0.03, 0.01, 0.01])
    assert (b.thickness_m, b.material.E_Pa, b.material.rho_kg_m3, b.material.nu) == (
        0.006, 1e11, 2700.0, 0.33)
    assert b.mass_kg == pytest.approx(2700.0 * 0.006 * 2 * (0.5 * 0.025 + 0.5 * 0.01))


def test_bounds_keep_the_vertex_structure():
    beam = pp.load_beam(BEAMS / "reference-random.json")
    x = beam.x_m
    d = pp.Design(beam, ("x[3]", "x[4]", "x[6]"))
    lo, hi = d.bounds.T
    # adjacent varied stations split their gap at the midpoint, so no vector reorders them
    np.testing.assert_allclose(lo, [x[2], 0.5 * (x[3] + x[4]), x[5]])
    np.testing.assert_allclose(hi, [0.5 * (x[3] + x[4]), x[5], x[7]])
    step = pp.Design(pp.load_beam(BEAMS / "stepped-narrow.json"), ("half_width[1]",
                                                                    "half_width[2]"))
    # the wide side of the step stays wider than the narrow one
    np.testing.assert_allclose(step.bounds, [[0.015, np.inf], [0.0, 0.015]])
    with pytest.raises(BeamInputError, match=r"half_width\[2\] = 0.016"):
        step.beam_at([0.02, 0.016])


@pytest.mark.parametrize("names, needle", [
    (("x[2]", "x[1]"), "named twice"),  # the two vertices of one step
    (("x[0]",), "clamped root"),
    (("rho", "width"), "'width'"),
    ((), "at least one"),
    ("thickness", "sequence"),
])
def test_bad_variables_refused(names, needle):
    with pytest.raises(BeamInputError, match=needle):
        pp.Design(pp.load_beam(BEAMS / "stepped-narrow.json"), names)


@pytest.mark.parametrize("name", ["reference-random", "stepped-narrow", "tapered"])
def test_moved_mesh_tiles_the_new_planform(name):
    beam = pp.load_beam(BEAMS / f"{name}.json")
    k = beam.x_m.size
    names = tuple(f"half_width[{i}]" for i in range(k)) + tuple(
        f"x[{i}]" for i in range(1, k - 1) if beam.x_m[i] != beam.x_m[i - 1])
    d = pp.Design(beam, names)
    # a move of 10 % of every variable's scale (the map is for the small moves of gradients and
    # optimiser steps; a large one can fold the small elements at a step's corner)
    new = d.beam_at(d.values + 0.1 * d.scales * np.cos(np.arange(d.size)))
    mesh = planform_tri_mesh(beam, 0)
    moved = MeshTri(morph_plane(beam, new, mesh.p), mesh.t)
    def signed_areas(p):
        v = p[:, mesh.t]
        return 0.5 * ((v[0, 1] - v[0, 0]) * (v[1, 2] - v[1, 0])
                      - (v[0, 2] - v[0, 0]) * (v[1, 1] - v[1, 0]))

    area = signed_areas(moved.p)
    assert np.all(np.sign(area) == np.sign(signed_areas(mesh.p)))  # no element inverted
    # a sum of 120 to 2410 positive areas, each exact to a few EPS: <= 2410 EPS in the worst
    # case (1 EPS measured); kept: the test's 1e-12
    assert np.abs(area).sum() == pytest.approx(new.planform_area_m2, rel=5000 * EPS)
    # every planform vertex of the new beam is a node of the moved mesh
    for xv, wv in zip(new.x_m, new.half_width_m, strict=True):
        assert np.min(np.hypot(moved.p[0] - xv, moved.p[1] - wv)) < 1e-12
