"""Section tables: a member known by E I, G J, rho A and rotary inertias at stations.

Reference: the planform member itself. A strip of uniform thickness with a linearly tapered
width has E I_y, rho A and rho I_y linear in x, so the table of its values at the vertices is
the same member by another code path (the table's own interpolation and quadrature, not the
rectangle's w(x) t^3); a uniform strip has every property constant, so its in-plane and
torsion modes match too. Bad input is refused naming the field and the station.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.chain.sections import link_sections
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam, save_beam
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.section_law import section_properties
from prbdm_pin.truth.beam import beam_modal, beam_stations
from prbdm_pin.truth.beam_spatial import beam_in_plane_modes, beam_torsion_modes

REQUIRED = ("EI_y_Nm2", "EI_z_Nm2", "GJ_Nm2", "rhoA_kg_m", "rhoI_y_kg_m", "rhoI_z_kg_m")
LENGTHS = np.array([0.3, 0.3, 0.4])


def _table_of(beam: Beam) -> dict:
    """The beam-JSON mapping of a table holding ``beam``'s section at its vertices."""
    sp = section_properties(beam, beam.x_m)
    section = {"kind": "table", **{k: [float(v) for v in getattr(sp, k)] for k in REQUIRED}}
    return {"x": [float(v) for v in beam.x_m], "section": section,
            "tip_force": [float(v) for v in beam.tip_force_N]}


@pytest.fixture(scope="module")
def trapezoid():
    return Beam([0.0, 0.4, 1.0], [0.05, 0.04, 0.02], 0.01, tip_force_N=[0.0, 0.0, -1.0])


def test_table_of_a_trapezoid_gives_the_planform_links_and_springs(trapezoid):
    table = beam_from_dict(_table_of(trapezoid))
    a, b = link_sections(table, LENGTHS), link_sections(trapezoid, LENGTHS)
    # mass, centre of mass, pitch inertia and mean area moment: linear laws integrated by two
    # different exact quadratures, a few roundings apart (20 EPS)
    np.testing.assert_allclose(a.mass_kg, b.mass_kg, rtol=20 * EPS)
    np.testing.assert_allclose(a.com_m, b.com_m, rtol=20 * EPS)
    np.testing.assert_allclose(a.inertia_com_kg_m2[:, 1, 1], b.inertia_com_kg_m2[:, 1, 1],
                               rtol=20 * EPS)
    np.testing.assert_allclose(a.area_moment_m4, b.area_moment_m4, rtol=20 * EPS)
    # springs: the rectangle's closed-form logarithm against the table's cut Gauss rule of
    # 1 / E I (E I linear: ~1e-16 per piece): 20 EPS
    np.testing.assert_allclose(finite_segment_stiffness(table, LENGTHS),
                               finite_segment_stiffness(trapezoid, LENGTHS), rtol=20 * EPS)
    assert abs(table.mass_kg / trapezoid.mass_kg - 1.0) < 20 * EPS


def test_table_of_a_trapezoid_gives_the_planform_bending_modes(trapezoid):
    table = beam_from_dict(_table_of(trapezoid))
    # the same element edges, both quadratures exact; what differs is rounding: scikit-fem
    # inverts each Hermite element's Vandermonde matrix, so the matrices carry EPS times its
    # condition (1.3e-7 at 200 elements; changing only the planform's exact quadrature order
    # from 7 to 12 points moves mode 1 by 6e-9, measured)
    rtol = EPS * hermite_basis_cond(beam_stations(trapezoid))
    np.testing.assert_allclose(beam_modal(table, 4).omega_rad_s,
                               beam_modal(trapezoid, 4).omega_rad_s, rtol=rtol)


def test_table_of_a_uniform_strip_gives_its_torsion_and_in_plane_modes():
    strip = Beam([0.0, 1.0], [0.03, 0.03], 0.004)
    table = beam_from_dict(_table_of(strip))
    # torsion on P2 elements: the stiffness' condition ~ (4 x 200)^2 = 6.4e5 times EPS is
    # 1.4e-10 (measured 1.4e-11); in-plane bending on Hermite elements: as for the bending
    # modes (a 1-ULP change of the width moves mode 1 by 2e-8, measured)
    np.testing.assert_allclose(beam_torsion_modes(table, 3)[0],
                               beam_torsion_modes(strip, 3)[0], rtol=6.4e5 * EPS)
    rtol = EPS * hermite_basis_cond(beam_stations(strip))
    np.testing.assert_allclose(beam_in_plane_modes(table, 3)[0],
                               beam_in_plane_modes(strip, 3)[0], rtol=rtol)
    # the spatial chain's springs: the rectangle's closed form (z) and 16-point Gauss of its
    # exact J (x) against the table's constants: 20 EPS
    np.testing.assert_allclose(spatial_stiffness(table, LENGTHS, "xyz"),
                               spatial_stiffness(strip, LENGTHS, "xyz"), rtol=20 * EPS)


def test_roll_inertia_defaults_to_the_perpendicular_axis_sum():
    strip = Beam([0.0, 1.0], [0.03, 0.03], 0.004)
    d = _table_of(strip)
    table = beam_from_dict(d)
    np.testing.assert_array_equal(table.section.rhoI_x_kg_m,  # the sum itself, exact
                                  np.add(d["section"]["rhoI_y_kg_m"], d["section"]["rhoI_z_kg_m"]))
    # every link's full inertia tensor, roll included, is the strip's (constant laws): 20 EPS
    np.testing.assert_allclose(link_sections(table, LENGTHS).inertia_com_kg_m2,
                               link_sections(strip, LENGTHS).inertia_com_kg_m2, rtol=20 * EPS,
                               atol=0.0)
    d["section"]["rhoI_x_kg_m"] = [1.0, 2.0]  # given: used as given
    assert beam_from_dict(d).section.rhoI_x_kg_m[1] == 2.0


def test_beam_json_round_trip(trapezoid, tmp_path):
    table = beam_from_dict(_table_of(trapezoid))
    back = load_beam(save_beam(table, tmp_path / "t.json"))
    d = json.loads((tmp_path / "t.json").read_text())
    assert d["section"]["kind"] == "table" and "half_width" not in d
    for k in (*REQUIRED, "rhoI_x_kg_m"):  # lossless JSON
        assert np.array_equal(getattr(back.section, k), getattr(table.section, k)), k
    with pytest.raises(BeamInputError, match="a section table has no thickness"):
        back.thickness_at(0.5)
    with pytest.raises(BeamInputError, match="a section table has no half_width"):
        back.half_width_at(0.5)


def _bad(**change):
    d = _table_of(Beam([0.0, 0.5, 1.0], [0.02, 0.02, 0.02], 0.004))
    for k, v in change.items():
        if v is None:
            del d["section"][k]
        else:
            d["section"][k] = v
    return d


@pytest.mark.parametrize("change, words", [
    ({"EI_y_Nm2": [1.0, 0.0, 1.0]}, "section.EI_y_Nm2[1] = 0.0 N m^2 (station 1): must be > 0"),
    ({"GJ_Nm2": [1.0, 1.0, -2.0]}, "section.GJ_Nm2[2] = -2.0 N m^2 (station 2): must be > 0"),
    ({"rhoA_kg_m": [0.6, 0.0, 0.6]}, "section.rhoA_kg_m[1] = 0.0 kg/m (station 1)"),
    ({"rhoI_y_kg_m": [1e-6, -1e-6, 1e-6]}, "section.rhoI_y_kg_m[1] = -1e-06 kg m (station 1): "
                                           "must be >= 0"),
    ({"EI_z_Nm2": [1.0, 1.0]}, "section.EI_z_Nm2 has 2 entries: must match section.EI_y_Nm2"),
    ({"GJ_Nm2": None}, "section.GJ_Nm2 missing: a section table needs"),
    ({"EI_y_Nm2": 3.0}, "section.EI_y_Nm2 = 3.0: must be a list aligned with x"),
    ({"mass": [1, 1, 1]}, "unknown key(s) in section ['mass']"),
])
def test_bad_table_is_refused_by_name(change, words):
    with pytest.raises(BeamInputError) as e:
        beam_from_dict(_bad(**change))
    assert words in str(e.value)


def test_unaligned_and_unordered_stations_are_refused():
    d = _bad()
    d["x"] = [0.0, 1.0]
    with pytest.raises(BeamInputError, match=r"section.EI_y_Nm2 has 3 entries: must be aligned "
                                             r"with x \(2 entries"):
        beam_from_dict(d)
    d["x"] = [0.0, 0.6, 0.5]
    with pytest.raises(BeamInputError, match=r"x\[2\] = 0.5 m: must not decrease"):
        beam_from_dict(d)


def test_cli_refuses_a_bad_table_in_one_line(tmp_path, capsys):
    p = tmp_path / "t.json"
    p.write_text(json.dumps(_bad(EI_y_Nm2=[1.0, 0.0, 1.0])))
    code = main(["truth", str(p), "--model", "beam", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "section.EI_y_Nm2[1] = 0.0 N m^2 (station 1)" in err, err
    assert not (tmp_path / "o").exists()  # nothing half-written


def test_strain_of_a_table_member_is_refused_and_of_a_round_one_uses_the_outer_radius():
    from prbdm_pin import build_model
    from prbdm_pin.member.section_member import round_beam
    from prbdm_pin.model.strain import MICROSTRAIN, strain_terms

    table = beam_from_dict(_table_of(Beam([0.0, 1.0], [0.03, 0.03], 0.004)))
    springs = finite_segment_stiffness(table, LENGTHS)
    with pytest.raises(BeamInputError, match="a section table has no thickness"):
        strain_terms(build_model(table, LENGTHS, springs), 0.5, "strain")
    rod = round_beam([0.0, 1.0], [0.02, 0.02], [0.01, 0.01])
    model = build_model(rod, LENGTHS, finite_segment_stiffness(rod, LENGTHS))
    scale = strain_terms(model, 0.5, "strain")[0]
    # strain = M c / (E I) with c = D / 2 and I = pi (D^4 - d^4) / 64, written out here
    ref = -MICROSTRAIN * 0.01 / (rod.material.E_Pa * np.pi * (0.02**4 - 0.01**4) / 64.0)
    assert abs(scale / ref - 1.0) < 10 * EPS  # a few roundings of the same product


def test_table_station_derivatives_match_central_differences(trapezoid):
    from central_differences import central_difference

    from prbdm_pin.chain.sections import link_sections_unchecked, planar_sections
    from prbdm_pin.chain.sections_derivatives import (
        finite_segment_stiffness_gradient,
        planar_sections_gradient,
        roll_yaw_inertia_gradient,
    )
    from prbdm_pin.chain.spatial_stiffness import axis_stiffness
    from prbdm_pin.chain.spatial_stiffness_derivatives import axis_stiffness_gradient
    from prbdm_pin.chain.stiffness import finite_segment_stiffness_unchecked

    table = beam_from_dict(_table_of(trapezoid))
    stations = np.array([0.2, 0.55, 0.8])  # m: off the table's station at 0.4 m

    def lengths(x):
        return np.diff(np.r_[0.0, x, 1.0])

    def check(analytic, f):
        # each value of f carries ~100 EPS of its scale in rounding (sums over Gauss points)
        scale = np.max(np.abs(f(stations)))
        fd, bound = central_difference(f, stations, 1e-4, 100 * EPS * scale)
        assert np.all(np.abs(analytic - fd) <= bound + 100 * EPS * np.abs(fd)), (analytic, fd)

    g = planar_sections_gradient(table, lengths(stations))
    for k, d in enumerate((g.d_mass_kg_per_m, g.d_com_offset, g.d_inertia_yy_kg_m,
                           g.d_area_moment_m3)):
        check(d, lambda x, k=k: planar_sections(table, lengths(x))[k])
    _, _, d_xx, d_zz = roll_yaw_inertia_gradient(table, lengths(stations))
    def inertia(x):
        return link_sections_unchecked(table, lengths(x)).inertia_com_kg_m2

    for a, d in ((0, d_xx), (2, d_zz)):
        check(d, lambda x, a=a: inertia(x)[:, a, a])
    check(finite_segment_stiffness_gradient(table, lengths(stations))[1],
          lambda x: finite_segment_stiffness_unchecked(table, lengths(x)))
    for axis in ("z", "x"):
        check(axis_stiffness_gradient(table, lengths(stations), axis)[1],
              lambda x, axis=axis: axis_stiffness(table, lengths(x), axis))


def test_a_very_soft_uniform_table_is_taken_and_matches_the_cantilever():
    from prbdm_pin.member.section_member import table_beam
    from prbdm_pin.member.section_table import SectionTable

    # E I = 1e-12 N m^2: its "equivalent square" would be 4 um, below the planform's size
    # range; a table has no such geometry, so it is not refused under a size it does not have
    one = [1.0, 1.0]
    b = table_beam([0.0, 1.0], SectionTable(np.multiply(one, 1e-12), one, one,
                                            np.multiply(one, 1e-6), one, one))
    bl = np.array([1.8751040687, 4.6940911330])  # roots of cos cosh = -1 to 11 digits
    ref = bl**2 * np.sqrt(1e-12 / 1e-6)
    # discretisation (O(h^4), ~1e-9) plus the Hermite basis' rounding, as above
    rtol = 1e-8 + EPS * hermite_basis_cond(beam_stations(b))
    np.testing.assert_allclose(beam_modal(b, 2).omega_rad_s, ref, rtol=rtol)


def test_tip_corners_need_a_width_a_table_does_not_have():
    from prbdm_pin import build_model
    from prbdm_pin.member.section_member import round_beam

    table = beam_from_dict(_table_of(Beam([0.0, 1.0], [0.03, 0.03], 0.004)))
    model = build_model(table, LENGTHS, finite_segment_stiffness(table, LENGTHS))
    tip, _ = model.point_kinematics("tip")
    assert tip[0] == pytest.approx(1.0, rel=10 * EPS)  # the straight chain's tip at x = L
    with pytest.raises(BeamInputError, match="a section table has no half_width"):
        model.point_kinematics("tip_corner_left")
    rod = round_beam([0.0, 1.0], [0.02, 0.01])
    corner, _ = build_model(rod, LENGTHS, finite_segment_stiffness(rod, LENGTHS)
                            ).point_kinematics("tip_corner_left")
    assert abs(abs(corner[1]) - 0.005) < 10 * EPS  # the outer radius at the tip, 5 mm


def test_joint_spring_fit_of_a_table_member_reaches_its_truth(trapezoid):
    from prbdm_pin.fitting import fit
    from prbdm_pin.fitting.target import FitTarget

    table = beam_from_dict(_table_of(trapezoid))
    omega = beam_modal(table, 3).omega_rad_s
    r = fit(table, FitTarget(omega, table.tip_force_N), 3, frequencies=3, starts=3, seed=0,
            progress=False, stiffness="joint")
    # 6 parameters for 3 frequencies: the least-squares tolerance (measured 1.2e-13 % by
    # prbdm fit on this table); 1e-8 % leaves gtol room
    assert np.max(np.abs(r.omega_export_errors_pct)) < 1e-8, r.omega_export_errors_pct
