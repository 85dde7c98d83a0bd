"""Linear static plate truth against beam theory, plate-theory bounds and mesh refinement."""


import numpy as np
import pytest
from paths import BEAMS
from skfem import Basis, FacetBasis
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth.mesh import planform_tri_mesh
from prbdm_pin.truth.plate_elements import ElementTriArgyrisLocal
from prbdm_pin.truth.plate_static import plate_static, tip_edge_load


def _beam_theory(beam) -> float:
    """Euler-Bernoulli tip deflection P L^3 / (3 E I) in m."""
    return beam.tip_force_N[2] * beam.length_m**3 / (3 * beam.root_EI_Nm2)


def test_narrow_strip_within_half_percent_of_euler_bernoulli(narrow):
    s = plate_static(narrow, level=1)
    rel = s.tip_displacement_m[2] / _beam_theory(narrow) - 1
    # The clamp blocks the root's anticlastic (Poisson) curvature: the plate is stiffer than
    # the beam, by 0.47 % here (converged; the 3D solid gives 0.38 % with its shear flexibility).
    assert -5e-3 < rel < -4e-3, rel
    assert s.tip_displacement_m[0] == 0.0 and s.tip_displacement_m[1] == 0.0
    np.testing.assert_allclose(s.tip_position_m, [1.0, 0.0, s.tip_displacement_m[2]])
    assert not s.nonlinear and s.mesh_level == 1


def test_default_level_is_the_modal_default_and_within_0_05_percent(narrow):
    from prbdm_pin.truth import DEFAULT_PLATE_LEVEL

    s0 = plate_static(narrow)
    s2 = plate_static(narrow, level=DEFAULT_PLATE_LEVEL + 2)
    assert s0.mesh_level == DEFAULT_PLATE_LEVEL
    # measured 0.034 % at level 0 (two elements across the 50 mm strip)
    assert s0.tip_displacement_m[2] / s2.tip_displacement_m[2] - 1 == pytest.approx(0, abs=5e-4)


def test_tip_deflection_converged_on_the_graded_mesh(narrow):
    # The only slowly converging error of the strip sits at the two clamped-free root corners;
    # the mesh refines them, so the deflection is converged at the default level already:
    # nested refinements change it by < 1e-6 relative (measured 7e-8), far below the 0.47 %
    # physical gap to P L^3 / (3 E I).
    w = np.array([plate_static(narrow, lv).tip_displacement_m[2] for lv in (0, 1, 2)])
    np.testing.assert_allclose(w, w[-1], rtol=1e-6)
    P = abs(narrow.tip_force_N[2])
    w_eb = -P * narrow.length_m**3 / (3.0 * narrow.root_EI_Nm2)
    assert 0.0 < 1.0 - w[0] / w_eb < 5e-3


def test_square_plate_between_beam_and_plate_strip_bounds():
    beam = load_beam(BEAMS / "square-plate.json")
    s = plate_static(beam, level=1)
    nu = beam.material.nu
    beam_value = _beam_theory(beam)  # free anticlastic curvature: the softest bound
    strip_value = beam_value * (1 - nu**2)  # cylindrical bending with D: the stiffest bound
    w = s.tip_displacement_m[2]
    assert abs(strip_value) < abs(w) < abs(beam_value)
    # measured: 5.15 % stiffer than the beam value, a little over half way to the 9 % bound
    assert w / beam_value - 1 == pytest.approx(-0.0515, abs=1e-3)


def test_edge_load_sums_to_the_tip_force():
    beam = load_beam(BEAMS / "reference-random.json")
    mesh = planform_tri_mesh(beam, 0)
    basis = Basis(mesh, ElementTriArgyrisLocal())
    tip = mesh.facets_satisfying(lambda x: np.abs(x[0] - beam.length_m) < 1e-9)
    f = tip_edge_load(beam, FacetBasis(mesh, ElementTriArgyrisLocal(), facets=tip), -2500.0)
    rigid = np.zeros(basis.N)
    rigid[basis.nodal_dofs[0]] = 1.0  # u = 1: value DOFs one, derivative DOFs zero
    # the load's edge integrals summed: a few roundings (4 EPS measured); kept: the test's
    # 1e-12
    assert f @ rigid == pytest.approx(-2500.0, rel=5000 * EPS)
    # only the tip edge is loaded
    loaded = np.unique(basis.element_dofs[:, mesh.f2t[0, tip]])
    assert np.all(np.delete(f, loaded) == 0.0)


def test_in_plane_force_does_not_bend(narrow):
    s = plate_static(narrow, level=0, tip_force_N=np.array([100.0, 50.0, 0.0]))
    assert np.all(s.tip_displacement_m == 0.0)


def test_bad_input(narrow):
    with pytest.raises(BeamInputError, match="level"):
        plate_static(narrow, level=-1)
    with pytest.raises(BeamInputError, match="tip_force_N"):
        plate_static(narrow, tip_force_N=np.array([0.0, np.nan, 1.0]))


@pytest.mark.slow
@pytest.mark.parametrize("name, thickness_m, low, high", [
    ("square-plate", None, -1e-3, 1e-3),
    # -0.23 % (solid level 3: -0.24 %): the plate theory misses the 3D flexibility of the
    # panel's narrow parts, so the plate is the stiffer model; the gap falls with the thickness
    # (-0.09 % at 5 mm, next case at 2.5 mm)
    ("reference-random", None, -5e-3, 0.0),
    ("reference-random", 0.0025, -1e-3, 1e-3),
])
def test_plate_agrees_with_the_linear_3d_solid(name, thickness_m, low, high):
    from prbdm_pin.member.geometry import Beam
    from prbdm_pin.truth.solid import solid_static

    beam = load_beam(BEAMS / f"{name}.json")
    if thickness_m is not None:
        beam = Beam(beam.x_m, beam.half_width_m, thickness_m, beam.material, beam.tip_force_N)
    w_plate = plate_static(beam).tip_displacement_m[2]
    w_solid = solid_static(beam, level=2).tip_displacement_m[2]
    # a different theory and discretisation (27-node hexes, shear-flexible): measured +0.05 %
    # (square plate) and -0.009 % (reference planform, t = 2.5 mm), against 5 % and 0.3 %
    # between the plate and Euler-Bernoulli
    assert low < w_plate / w_solid - 1 < high


def test_elastica_truth_warns_where_plate_action_matters():
    """The square plate's linear plate tip deflection is ~5 % below the 1D beam's (P L^3/3EI
    bracket above), so a plain elastica large-deflection truth must say so; a slender strip must
    not. (The default calibrated elastica takes the plate's linear stiffness and has no such gap,
    so the plain one is asked for by name.)"""
    from prbdm_pin.truth import compute_truth

    square = load_beam(BEAMS / "square-plate.json")
    notes = compute_truth(square, modes=3, large_deflection="elastica").warnings
    assert any("plate action" in n for n in notes), notes
    narrow = load_beam(BEAMS / "uniform-narrow.json")
    assert not any("plate action" in n for n in compute_truth(
        narrow, modes=3, large_deflection="elastica").warnings)
