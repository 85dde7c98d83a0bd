"""Bounded truth work: a mesh above max_mesh_dofs is refused before it is built; the 1D beam
takes nanometre intervals and 200k vertices without a LinAlgError."""


import numpy as np
import pytest
from paths import BEAMS
from reference import BETA_L as REF_BETA_L
from skfem import Basis
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam, save_beam
from prbdm_pin.member.geometry import Beam
from prbdm_pin.truth import compute_truth, mesh, solid, solid_fe
from prbdm_pin.truth.beam import beam_modal, beam_stations
from prbdm_pin.truth.beam_static import beam_static
from prbdm_pin.truth.feature_mesh import planform_quad_mesh
from prbdm_pin.truth.mesh_budget import estimate_plate_dofs
from prbdm_pin.truth.plate_elements import ElementTriArgyrisLocal

# Euler-Bernoulli clamped-free: beta_n L
BETA_L = REF_BETA_L[:5]


def _strip_omega(beam: Beam) -> np.ndarray:
    b, t = 2 * beam.half_width_m[0], beam.thickness_m
    EI = beam.material.E_Pa * b * t**3 / 12
    rhoA = beam.material.rho_kg_m3 * b * t
    return BETA_L**2 * np.sqrt(EI / (rhoA * beam.length_m**4))


def _short(d: float, w=(0.1, 0.1, 0.12, 0.1), t=0.01) -> Beam:
    return Beam(np.array([0.0, 0.5, 0.5 + d, 1.0]), np.array(w), t, name="short")


def _no_meshing(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("a mesh was built")

    monkeypatch.setattr(mesh, "planform_tri_mesh", refuse)
    monkeypatch.setattr(solid_fe, "solid_mesh", refuse)


@pytest.mark.parametrize("model, beam", [
    # the smallest features a beam takes (1e-5 m: the plausibility floor of its sizes) still
    # ask for meshes far beyond the cap
    ("plate", _short(1e-5)),
    ("plate", _short(2e-5)),
    ("plate-morley", _short(1e-5)),
    ("solid", Beam(np.array([0.0, 1.0]), np.array([0.1, 0.1]), 1e-5)),
])
def test_a_nanometre_feature_is_refused_before_meshing(monkeypatch, model, beam):
    _no_meshing(monkeypatch)
    with pytest.raises(BeamInputError, match=r"mesh DOFs .* max_mesh_dofs = 500000 .*"
                                             r"PRBDM_MAX_MESH_DOFS"):
        compute_truth(beam, model=model, modes=3, static=False)


def test_a_nanometre_waist_is_refused_by_the_beam_before_any_truth():
    # a waist at the plausibility floor (1e-5 m) meshes within the cap (about 2.4e5 DOFs at
    # level 2); one of 1e-9 m, which would have asked for far more, never becomes a Beam
    with pytest.raises(BeamInputError, match=r"half_width\[1\] = 1e-09 m: outside the plausible"):
        Beam(np.array([0.0, 0.5, 1.0]), np.array([0.1, 1e-9, 0.1]), 0.01)


def test_the_plate_static_solve_is_refused_before_meshing(monkeypatch):
    from prbdm_pin.truth.plate_static import plate_static

    _no_meshing(monkeypatch)
    with pytest.raises(BeamInputError, match="mesh DOFs"):
        plate_static(_short(1e-9))


def test_the_cli_refuses_in_one_line(tmp_path, capsys):
    path = save_beam(_short(1e-9), tmp_path / "short.json")
    rc = main(["truth", str(path), "--out", str(tmp_path / "t"), "-q"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and "max_mesh_dofs" in err, err
    assert "1e-09 m" in err  # the cause: the shortest vertex interval
    assert not (tmp_path / "t" / "truth.json").exists()


def test_the_cap_counts_the_built_mesh_exactly_and_can_be_raised(monkeypatch):
    beam = load_beam(BEAMS / "tapered.json")
    n = Basis(mesh.planform_tri_mesh(beam, 0), ElementTriArgyrisLocal()).N
    monkeypatch.setenv("PRBDM_MAX_MESH_DOFS", str(n))
    compute_truth(beam, modes=3, static=False, error_tol_pct=None)
    monkeypatch.setenv("PRBDM_MAX_MESH_DOFS", str(n - 1))
    with pytest.raises(BeamInputError, match=f"mesh DOFs \\(plate-argyris, level 0\\) = {n}"):
        compute_truth(beam, modes=3, static=False, error_tol_pct=None)


@pytest.mark.parametrize("name", sorted(p.name for p in BEAMS.glob("*.json")))
def test_the_estimates_never_exceed_the_mesh_they_estimate(name):
    # so the check before meshing never refuses a mesh that is within the cap
    beam = load_beam(BEAMS / name)
    n = Basis(mesh.planform_tri_mesh(beam, 0), ElementTriArgyrisLocal()).N
    assert 0.25 * n < estimate_plate_dofs(beam, 0) <= n
    from prbdm_pin.truth.mesh_budget import SOLID_DOFS_PER_AREA

    level = solid.default_solid_level(beam)
    q = planform_quad_mesh(beam, level, root_size_m=solid.ROOT_THICKNESSES * beam.thickness_m)
    exact = 9 * (q.p.shape[1] + q.facets.shape[1] + q.t.shape[1])
    h = 2 * mesh.element_size(beam, level)
    assert SOLID_DOFS_PER_AREA * beam.planform_area_m2 / h**2 <= exact


@pytest.mark.parametrize("d", [1e-7, 1e-9, 1e-12])
def test_the_1d_beam_takes_a_nanometre_interval(d):
    # the limit of a vanishing interval is a width step at x = 0.5
    step = Beam(np.array([0.0, 0.5, 0.5, 1.0]), np.array([0.1, 0.1, 0.12, 0.1]), 0.01)
    w = beam_modal(_short(d), 5).omega_rad_s
    np.testing.assert_allclose(w, beam_modal(step, 5).omega_rad_s, rtol=1e-6)
    F = np.array([0.0, 0.0, -100.0])
    u = beam_static(_short(d), F).tip_displacement_m[2]
    assert u == pytest.approx(beam_static(step, F).tip_displacement_m[2], rel=1e-6)


def test_a_1d_interval_of_a_vanishing_fraction_keeps_its_precision():
    # a vertex 1e-5 L from another on a uniform strip changes nothing physically: the
    # frequencies must stay those of the strip (were 0.8 % off)
    beam = Beam(np.array([0.0, 0.3, 0.3 + 1e-5, 1.0]), np.full(4, 0.05), 0.01)
    np.testing.assert_allclose(beam_modal(beam, 5).omega_rad_s, _strip_omega(beam), rtol=2e-6)


def test_a_1d_width_step_next_to_the_tip_is_an_input_error():
    beam = Beam(np.array([0.0, 0.5, 1.0 - 1e-9, 1.0 - 1e-9, 1.0]),
                np.array([0.1, 0.1, 0.1, 0.05, 0.05]), 0.01)
    with pytest.raises(BeamInputError, match=r"x\[\d\] = .*width step"):
        beam_modal(beam, 3)


def test_a_section_at_the_size_floor_in_1d_is_finite():
    # the narrowest half-width a beam takes (1e-5 m, 1e-4 of its neighbours)
    beam = Beam(np.array([0.0, 0.5, 1.0]), np.array([0.1, 1e-5, 0.1]), 0.01)
    r = compute_truth(beam, model="beam", modes=3, static=False, error_tol_pct=None)
    assert np.all(np.isfinite(r.omega_rad_s)) and np.all(np.diff(r.omega_rad_s) > 0)


def test_a_200k_vertex_beam_in_1d_is_the_uniform_strip():
    x = np.linspace(0.0, 1.0, 200_001)
    beam = Beam(x, np.full(x.size, 0.05), 0.01)
    r = compute_truth(beam, model="beam", modes=5, static=False)
    np.testing.assert_allclose(r.omega_rad_s, _strip_omega(beam), rtol=1e-6)


def test_the_sparse_1d_path_matches_theory_and_the_dense_path():
    beam = Beam(np.array([0.0, 1.0]), np.full(2, 0.05), 0.01)
    dense = beam_modal(beam, 5)
    sparse = beam_modal(beam, 5, dense_max_dofs=10)
    np.testing.assert_allclose(sparse.omega_rad_s, _strip_omega(beam), rtol=1e-6)
    np.testing.assert_allclose(sparse.omega_rad_s, dense.omega_rad_s, rtol=1e-7)
    F = np.array([0.0, 0.0, -100.0])
    # two solvers of the same Hermite system (sparse LU against dense Cholesky): each is off by
    # up to EPS times the condition of the element basis (global coordinates), 1.3e-7 here
    rel = 2 * EPS * hermite_basis_cond(beam_stations(beam, 200))
    assert beam_static(beam, F, dense_max_dofs=10).tip_displacement_m[2] == pytest.approx(
        beam_static(beam, F).tip_displacement_m[2], rel=rel)


def test_the_elastica_of_a_dense_planform_is_that_of_the_strip():
    # 20k vertices started the collocation on 80k nodes (200k vertices: minutes)
    from prbdm_pin.truth.elastica import elastica_static

    F = np.array([0.0, 0.0, -100.0])
    x = np.linspace(0.0, 1.0, 20_001)
    dense = elastica_static(Beam(x, np.full(x.size, 0.05), 0.01, tip_force_N=F))
    strip = elastica_static(Beam(np.array([0.0, 1.0]), np.full(2, 0.05), 0.01, tip_force_N=F))
    # rtol: the collocation's tolerance; atol for the tip's zero y: kept, the test's 1e-12 m
    np.testing.assert_allclose(dense.tip_position_m, strip.tip_position_m, rtol=1e-8,
                               atol=5000 * EPS)
