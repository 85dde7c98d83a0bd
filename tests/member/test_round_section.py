"""Round members (solid rods, tubes, cones): sections, springs, the 1D truths, the fit, beam JSON.

Independent references: the uniform cantilever's roots of cos(bL) cosh(bL) = -1 (beta_n L =
1.8751, 4.6941, 7.8548) with I = pi (D^4 - d^4) / 64; Saint-Venant torsion of a tube, omega_n =
(2n - 1) pi / (2 L) sqrt(G J / (rho I_p)), J = I_p = pi (D^4 - d^4) / 32; Kirchhoff's cone
(lambda_1 = 8.719) and a separate numpy Hermite FE with Richardson extrapolation
(``tests/tapered_reference.py``) for partial cones; the pen-and-paper frustum formulas for the
link masses, centres of mass and axial inertias; scipy's adaptive quadrature for the other
inertias and the spring compliances; central differences for the station derivatives.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from central_differences import central_difference
from scipy.integrate import quad
from scipy.optimize import brentq
from tapered_reference import complete_taper_lambda1, richardson_lambda1
from tolerances import EPS, ROOT_RTOL, hermite_basis_cond

from prbdm_pin.chain.sections import link_sections, link_sections_unchecked, planar_sections
from prbdm_pin.chain.sections_derivatives import (
    finite_segment_stiffness_gradient,
    planar_sections_gradient,
    roll_yaw_inertia_gradient,
)
from prbdm_pin.chain.spatial_stiffness import (
    axis_stiffness,
    link_mean_section_m4,
    spatial_stiffness,
)
from prbdm_pin.chain.spatial_stiffness_derivatives import axis_stiffness_gradient
from prbdm_pin.chain.stiffness import finite_segment_stiffness, finite_segment_stiffness_unchecked
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam, save_beam
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.design import Design
from prbdm_pin.member.geometry import beam_to_dict
from prbdm_pin.member.material import Material
from prbdm_pin.member.section_member import round_beam
from prbdm_pin.truth.beam import beam_modal, beam_stations
from prbdm_pin.truth.beam_spatial import beam_in_plane_modes, beam_torsion_modes
from prbdm_pin.truth.corner_static import corner_static
from prbdm_pin.truth.elastica import elastica_static
from prbdm_pin.truth.plate import plate_modal
from prbdm_pin.truth.solid import solid_modal

ALU = Material("aluminium 6061", 69e9, 2700.0, 0.33)
L, D, DI = 1.0, 0.03, 0.026  # m: a 1 m aluminium tube boom, 30 mm outer, 2 mm wall


def _tube():
    return round_beam([0.0, L], [D, D], [DI, DI], ALU, [0.0, 0.0, -1.0], "tube boom")


def _cone(ratio: float, D0: float = 0.04):
    """A solid cone from D0 at the clamp to ratio D0 at the tip."""
    return round_beam([0.0, L], [D0, ratio * D0], None, ALU, [0.0, 0.0, -1.0], "cone")


@pytest.fixture(scope="module")
def frustum():
    """A tapered tube with a kink: outer 40 -> 24 -> 8 mm, inner 30 -> 16 -> 2 mm."""
    return round_beam([0.0, 0.3, 1.0], [0.04, 0.024, 0.008], [0.03, 0.016, 0.002], ALU,
                      [0.0, 0.0, -1.0])


def _cantilever_roots(n: int) -> np.ndarray:
    return np.array([brentq(lambda z: np.cos(z) * np.cosh(z) + 1.0, (k - 0.5) * np.pi - 0.6,
                            (k - 0.5) * np.pi + 0.6, xtol=1e-15, rtol=ROOT_RTOL)
                     for k in range(1, n + 1)])


def test_tube_bending_matches_the_uniform_cantilever():
    bl = _cantilever_roots(3)
    # the tabulated beta_n L to their printed digits
    np.testing.assert_allclose(bl, [1.8751, 4.6941, 7.8548], atol=5e-5)
    I = np.pi * (D**4 - DI**4) / 64.0
    A = np.pi * (D**2 - DI**2) / 4.0
    ref = bl**2 / L**2 * np.sqrt(ALU.E_Pa * I / (ALU.rho_kg_m3 * A))
    b = _tube()
    # 200 Hermite elements: discretisation O(h^4), measured 2.6e-8 on mode 3 at 100 elements,
    # so ~2e-9 at 200 (1e-8 bounds it), plus the rounding of scikit-fem's Hermite basis (EPS
    # times its Vandermonde condition, 1.3e-7 at 200 elements; measured 1e-9 in all)
    rtol = 1e-8 + EPS * hermite_basis_cond(beam_stations(b))
    np.testing.assert_allclose(beam_modal(b, 3).omega_rad_s, ref, rtol=rtol)
    # a circle bends alike in both planes: the in-plane family has the same frequencies
    np.testing.assert_allclose(beam_in_plane_modes(b, 3)[0], ref, rtol=rtol)


def test_tube_torsion_matches_saint_venant():
    n = np.arange(1, 4)
    G = ALU.E_Pa / (2.0 * (1.0 + ALU.nu))
    J = np.pi * (D**4 - DI**4) / 32.0  # = I_p for a circle (no warping)
    ref = (2 * n - 1) * np.pi / (2.0 * L) * np.sqrt(G * J / (ALU.rho_kg_m3 * J))
    # 200 quadratic elements: O(h^4) on the frequencies, measured 2.6e-8 on mode 3 at 100
    np.testing.assert_allclose(beam_torsion_modes(_tube(), 3)[0], ref, rtol=1e-8)


def _lambda1(beam, D0: float) -> float:
    """lambda_1 = omega_1 L^2 sqrt(rho A_0 / (E I_0)) at the root section."""
    A0, I0 = np.pi * D0**2 / 4.0, np.pi * D0**4 / 64.0
    return float(beam_modal(beam, 1).omega_rad_s[0] * L**2
                 * np.sqrt(ALU.rho_kg_m3 * A0 / (ALU.E_Pa * I0)))


@pytest.mark.parametrize("ratio", [0.1, 0.05, 0.02])
def test_cone_matches_converged_hermite_fe(ratio):
    ref, err = richardson_lambda1(ratio, 2, 50)
    cone = _cone(ratio)
    lam = _lambda1(cone, 0.04)
    # 200 Hermite elements (O(h^4), the quartic E I integrated exactly) and the reference's
    # Richardson remainder (<= 1e-9): 1e-8 covers both; plus the Hermite basis' rounding
    # (EPS times its Vandermonde condition, 1.3e-7); measured 1e-10 ... 2e-9
    rtol = 1e-8 + EPS * hermite_basis_cond(beam_stations(cone))
    assert abs(lam / ref - 1.0) < rtol, (lam, ref, err)


def test_cone_trend_to_kirchhoffs_complete_cone():
    exact = complete_taper_lambda1(2)
    assert abs(exact - 8.719) < 5e-4  # the tabulated 8.719 (Conway et al.; Blevins)
    # the helper FE at the complete cone (D = 0 at the tip, which the package refuses): its
    # Richardson remainder 1e-9, measured 5e-12 from the Bessel root
    ref, _ = richardson_lambda1(0.0, 2, 50)
    assert abs(ref / exact - 1.0) < 1e-8
    ratios = np.array([0.1, 0.05, 0.02, 0.01, 0.001])
    lam = np.array([_lambda1(_cone(r, 0.04), 0.04) for r in ratios])
    # the sharper the cone, the nearer lambda_1 to Kirchhoff's 8.719, from below, and the
    # deficit closes linearly in the tip ratio: 1 - lambda / 8.719 = 1.99 r at r = 0.01 and
    # 2.00 r at r = 0.001 (measured); within 1 % of that slope
    assert np.all(np.diff(lam) > 0.0) and lam[-1] < exact, lam
    slope = (1.0 - lam[-2:] / exact) / ratios[-2:]
    assert np.all(np.abs(slope / 2.0 - 1.0) < 0.01), slope


def _quad(f, a, b):
    # the integrands kink at x = 0.3; scipy's own tolerance request 1e-13 (450 EPS)
    return quad(f, a, b, points=[0.3] if a < 0.3 < b else None, epsabs=0.0,
                epsrel=450 * EPS, limit=200)[0]


def _frustum_solid(R: float, r: float, h: float, rho: float):
    """Pen-and-paper solid frustum of radii R (start) and r (end), length h.

    Returns mass, centre of mass from the start, moment of inertia about the axis.
    """
    m = rho * np.pi * h * (R * R + R * r + r * r) / 3.0
    xc = h * (R * R + 2.0 * R * r + 3.0 * r * r) / (4.0 * (R * R + R * r + r * r))
    Ix = 0.3 * m * (R**5 - r**5) / (R**3 - r**3) if R != r else 0.5 * m * R * R
    return m, xc, Ix


def test_link_sections_match_frustum_formulas_and_quadrature(frustum):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])  # the second link straddles the kink at 0.3 m
    s = link_sections(frustum, lengths)
    rho = ALU.rho_kg_m3
    sec = frustum.section

    def Dx(x):
        return float(np.interp(x, frustum.x_m, sec.outer_diameter_m))

    def dx(x):
        return float(np.interp(x, frustum.x_m, sec.inner_diameter_m))

    def I4(x):
        return np.pi * (Dx(x) ** 4 - dx(x) ** 4) / 64.0

    def _area(x):
        return np.pi * (Dx(x) ** 2 - dx(x) ** 2) / 4.0

    for i, (a, b) in enumerate(zip(s.start_m, s.end_m, strict=True)):
        # a tube frustum is an outer solid frustum less an inner one (both diameters linear);
        # the straddling link is two such pieces
        pieces = [(a, min(b, 0.3)), (max(a, 0.3), b)] if a < 0.3 < b else [(a, b)]
        m = mx = Ix = 0.0
        for u, v in pieces:
            mo, xo, Io = _frustum_solid(Dx(u) / 2, Dx(v) / 2, v - u, rho)
            mi, xi, Ii = _frustum_solid(dx(u) / 2, dx(v) / 2, v - u, rho)
            m += mo - mi
            mx += mo * (u + xo) - mi * (u + xi)
            Ix += Io - Ii
        xc = mx / m
        Iyy = rho * _quad(lambda x, xc=xc: _area(x) * (x - xc) ** 2 + I4(x), a, b)
        I_mean = _quad(I4, a, b) / (b - a)
        got = [s.mass_kg[i], s.com_m[i, 0], *np.diag(s.inertia_com_kg_m2[i]),
               s.area_moment_m4[i]]
        # closed forms and quad's request 1e-13, a few roundings of the Gauss sums; the
        # frustum differences (outer less inner) lose up to ~10x more: 2e-12 relative
        np.testing.assert_allclose(got, [m, xc, Ix, Iyy, Iyy, I_mean], rtol=1e4 * EPS)
        assert s.inertia_com_kg_m2[i][0, 1] == s.inertia_com_kg_m2[i][0, 2] == 0.0  # symmetry
    # the sum of the links (3-point Gauss) against the member's mass (Simpson): 20 EPS
    assert abs(s.mass_kg.sum() / frustum.mass_kg - 1.0) < 20 * EPS
    _, _, Iyy_p, _ = planar_sections(frustum, lengths)
    np.testing.assert_allclose(Iyy_p, s.inertia_com_kg_m2[:, 1, 1], rtol=20 * EPS)


def test_springs_match_quadrature_of_compliance():
    b = round_beam([0.0, 0.3, 1.0], [0.04, 0.024, 0.004], [0.03, 0.016, 0.0036], ALU)
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    K = finite_segment_stiffness(b, lengths)
    c = [0.0, 0.35, 0.65, 1.0]  # the springs' spans: clamp, link mid-points, tip
    sec = b.section

    def EI(x):
        Dx = np.interp(x, b.x_m, sec.outer_diameter_m)
        dx = np.interp(x, b.x_m, sec.inner_diameter_m)
        return ALU.E_Pa * np.pi * (Dx**4 - dx**4) / 64.0

    ref = [1.0 / _quad(lambda x: 1.0 / EI(x), c[j], c[j + 1]) for j in range(3)]
    # 1 / E I varies ~4000-fold on the last span (a wall 0.2 mm at the tip); quad's request
    # 1e-13 and the geometrically cut 8-point Gauss (~1e-16 per piece): 1e-12 relative
    np.testing.assert_allclose(K, ref, rtol=5000 * EPS)


STATIONS = np.array([0.2, 0.45, 0.8])  # m: joints away from the kink at 0.3 m


def _lengths(x):
    return np.diff(np.r_[0.0, x, 1.0])


def _check(analytic, f, scale):
    # each value of f carries ~100 EPS of its scale in rounding (sums over a few Gauss points)
    fd, bound = central_difference(f, STATIONS, 1e-4, 100 * EPS * scale)
    assert np.all(np.abs(analytic - fd) <= bound + 100 * EPS * np.abs(fd)), (analytic, fd)


def test_station_derivatives_match_central_differences(frustum):
    g = planar_sections_gradient(frustum, _lengths(STATIONS))
    for k, d in enumerate((g.d_mass_kg_per_m, g.d_com_offset, g.d_inertia_yy_kg_m,
                           g.d_area_moment_m3)):
        def f(x, k=k):
            return planar_sections(frustum, _lengths(x))[k]
        _check(d, f, np.max(np.abs(f(STATIONS))))
    _, _, d_xx, d_zz = roll_yaw_inertia_gradient(frustum, _lengths(STATIONS))
    for a, d in ((0, d_xx), (2, d_zz)):
        def f(x, a=a):
            return link_sections_unchecked(frustum, _lengths(x)).inertia_com_kg_m2[:, a, a]
        _check(d, f, np.max(np.abs(f(STATIONS))))
    _, dK = finite_segment_stiffness_gradient(frustum, _lengths(STATIONS))

    def fk(x):
        return finite_segment_stiffness_unchecked(frustum, _lengths(x))
    _check(dK, fk, np.max(np.abs(fk(STATIONS))))


@pytest.mark.parametrize("beam", [_tube(), _cone(0.1)], ids=["tube", "cone"])
def test_joint_spring_5r_fit_reaches_the_truth(beam):
    omega = beam_modal(beam, 5).omega_rad_s
    r = fit(beam, FitTarget(omega, beam.tip_force_N), 5, frequencies=5, starts=3, seed=0,
            progress=False, stiffness="joint")
    # 10 parameters for 5 frequencies: the fit reaches them to the least-squares tolerance
    # (measured by prbdm fit: worst 1.7e-11 % on the tube, 3.6e-13 % on the cone, mode 5);
    # 1e-8 % leaves gtol room
    assert np.max(np.abs(r.omega_export_errors_pct)) < 1e-8, r.omega_export_errors_pct


def test_elastica_small_load_matches_linear_theory(frustum):
    # at P = 0.01 N the geometric nonlinearity is ~1e-10 relative: the elastica meets the
    # linear P ∫ (L - x)^2 / EI dx
    P = 0.01
    e = elastica_static(frustum, [0.0, 0.0, -P])
    ref = P * _quad(lambda x: (1.0 - x) ** 2 / (ALU.E_Pa * float(frustum.area_moment_at(x))),
                    0.0, 1.0)
    # solve_bvp's residual tolerance 1e-9 of the moment scale, a few times that in the tip
    assert abs(-e.tip_displacement_m[2] / ref - 1.0) < 1e-7


def test_beam_json_round_trip(frustum, tmp_path):
    p = save_beam(frustum, tmp_path / "b.json")
    d = json.loads(p.read_text())
    assert "half_width" not in d and "thickness" not in d
    assert d["section"] == {"kind": "round", "outer_diameter": [0.04, 0.024, 0.008],
                            "inner_diameter": [0.03, 0.016, 0.002]}
    back = load_beam(p)
    # lossless JSON: the same diameters give the same links bit for bit
    assert np.array_equal(back.section.inner_diameter_m, frustum.section.inner_diameter_m)
    lengths = np.array([0.2, 0.3, 0.5])
    assert np.array_equal(link_sections(back, lengths).inertia_com_kg_m2,
                          link_sections(frustum, lengths).inertia_com_kg_m2)
    # a solid rod leaves out the inner diameter
    rod = beam_from_dict({"x": [0.0, 1.0], "section": {"kind": "round",
                                                       "outer_diameter": [0.02, 0.01]}})
    assert rod.section.solid and "inner_diameter" not in beam_to_dict(rod)["section"]
    # half-width is the outer radius, thickness the outer diameter (strain's half thickness)
    assert rod.half_width_at(0.5) == 0.0075 and rod.thickness_at(0.5) == 0.015
    # copies keep the section
    assert dataclasses.replace(frustum, name="c").section is frustum.section
    assert frustum.with_tip_force([0.0, 0.0, -2.0]).section is frustum.section


@pytest.mark.parametrize("section, words", [
    ({"kind": "round", "outer_diameter": [0.02, 0.01], "inner_diameter": [0.01, 0.01]},
     "section.inner_diameter[1] = 0.01 m (station 1): must be below "
     "section.outer_diameter[1] = 0.01 m"),
    ({"kind": "round", "outer_diameter": [0.02, 0.0]},
     "section.outer_diameter[1] = 0.0 m (station 1): must be > 0"),
    ({"kind": "round", "outer_diameter": [0.02, -0.01]}, "section.outer_diameter[1] = -0.01 m"),
    ({"kind": "round", "outer_diameter": [0.02, 0.01], "inner_diameter": [-0.001, 0.0]},
     "section.inner_diameter[0] = -0.001 m (station 0): must be >= 0"),
    ({"kind": "round", "outer_diameter": [0.02, 0.01, 0.005]},
     "section.outer_diameter has 3 entries: must be aligned with x (2 entries"),
    ({"kind": "round", "outer_diameter": [0.02, 0.01], "inner_diameter": [0.001]},
     "section.inner_diameter has 1 entries: must match section.outer_diameter"),
    ({"kind": "hexagon", "outer_diameter": [0.02, 0.01]}, "section.kind = 'hexagon': unknown"),
    ({"kind": "round"}, "section.outer_diameter missing"),
    ({"kind": "round", "outer_diameter": 0.02}, "section.outer_diameter = 0.02: must be a list"),
    ({"kind": "round", "outer_diameter": [0.02, "a"]},
     "section.outer_diameter[1] = 'a': must be a number (m)"),
    ({"kind": "round", "outer_diameter": [0.02, 0.01], "wall": 1}, "unknown key(s) in section"),
    ("round", "section = 'round': must be an object"),
])
def test_bad_round_section_is_refused_by_name(section, words):
    with pytest.raises(BeamInputError) as e:
        beam_from_dict({"x": [0.0, 1.0], "section": section})
    assert words in str(e.value)


def test_round_member_refuses_planform_keys_and_width_steps():
    with pytest.raises(BeamInputError, match=r"unknown key\(s\) \['half_width'\] \(a section "
                                             "replaces half_width and thickness\\)"):
        beam_from_dict({"x": [0.0, 1.0], "half_width": [0.01, 0.01],
                        "section": {"kind": "round", "outer_diameter": [0.02, 0.01]}})
    with pytest.raises(BeamInputError, match=r"x\[2\] = x\[1\] = 0.5 m: a round member has no "
                                             "width steps"):
        round_beam([0.0, 0.5, 0.5, 1.0], [0.02, 0.02, 0.01, 0.01])
    with pytest.raises(BeamInputError,
                       match=r"x\[2\] = 0.4 m: must not decrease \(x\[1\] = 0.5 m\)"):
        round_beam([0.0, 0.5, 0.4, 1.0], [0.02, 0.02, 0.01, 0.01])


@pytest.mark.parametrize("argv", [["fit", "--joints", "2", "--truth-model", "beam"],
                                  ["truth", "--model", "beam"]])
def test_cli_refuses_a_bad_tube_in_one_line(tmp_path, capsys, argv):
    p = tmp_path / "b.json"
    p.write_text(json.dumps({"x": [0.0, 0.5, 1.0], "tip_force": [0, 0, -1],
                             "section": {"kind": "round", "outer_diameter": [0.03, 0.02, 0.01],
                                         "inner_diameter": [0.02, 0.02, 0.005]}}))
    code = main([argv[0], str(p), *argv[1:], "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1, err
    assert "section.inner_diameter[1] = 0.02 m (station 1): must be below" in err, err
    assert not (tmp_path / "o").exists()  # nothing half-written


def test_spatial_springs_match_quadrature(frustum):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    K = spatial_stiffness(frustum, lengths, "xyz").reshape(3, 3)  # node-major: y, z, x
    c = [0.0, 0.35, 0.65, 1.0]
    sec = frustum.section
    G = ALU.E_Pa / (2.0 * (1.0 + ALU.nu))

    def I4(x):
        Dx = np.interp(x, frustum.x_m, sec.outer_diameter_m)
        dx = np.interp(x, frustum.x_m, sec.inner_diameter_m)
        return np.pi * (Dx**4 - dx**4) / 64.0

    comp = np.array([_quad(lambda x: 1.0 / I4(x), c[j], c[j + 1]) for j in range(3)])
    # E I_z = E I_y about the two diameters; G J with J = 2 I (a circle does not warp); quad's
    # request 1e-13 and the cut 8-point Gauss: 1e-12 relative
    np.testing.assert_allclose(K[:, 0], ALU.E_Pa / comp, rtol=5000 * EPS)
    np.testing.assert_allclose(K[:, 1], ALU.E_Pa / comp, rtol=5000 * EPS)
    np.testing.assert_allclose(K[:, 2], 2.0 * G / comp, rtol=5000 * EPS)
    for axis in ("z", "x"):
        _, dK = axis_stiffness_gradient(frustum, _lengths(STATIONS), axis)

        def f(x, axis=axis):
            return axis_stiffness(frustum, _lengths(x), axis)
        _check(dK, f, np.max(np.abs(f(STATIONS))))


def test_link_mean_sections_of_the_spatial_paper_springs_match_quadrature(frustum):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    starts = np.r_[0.0, np.cumsum(lengths)[:-1]]
    ends = np.cumsum(lengths)
    sec = frustum.section

    def I4(x):
        Dx = np.interp(x, frustum.x_m, sec.outer_diameter_m)
        dx = np.interp(x, frustum.x_m, sec.inner_diameter_m)
        return np.pi * (Dx**4 - dx**4) / 64.0

    mean = np.array([_quad(I4, a, b) / (b - a) for a, b in zip(starts, ends, strict=True)])
    # 16-point Gauss, exact for the quartic I (and J = 2 I of a circle); quad's 1e-13
    for axis, factor in (("y", 1.0), ("z", 1.0), ("x", 2.0)):
        np.testing.assert_allclose(link_mean_section_m4(frustum, lengths, axis), factor * mean,
                                   rtol=1e3 * EPS)


def test_rectangle_models_refuse_a_round_member_by_name(frustum):
    with pytest.raises(BeamInputError, match="the plate truth takes the planform rectangle"):
        plate_modal(frustum)
    with pytest.raises(BeamInputError, match="the 3D solid truth takes the planform rectangle"):
        solid_modal(frustum)
    with pytest.raises(BeamInputError, match="design variations takes the planform rectangle"):
        Design(frustum, ("E",))
    with pytest.raises(BeamInputError, match="the anticlastic elastica takes the planform"):
        elastica_static(frustum, anticlastic=True)
    with pytest.raises(BeamInputError, match="the self-weight truth takes the planform"):
        elastica_static(frustum, gravity_m_s2=[0.0, 0.0, -9.81])
    with pytest.raises(BeamInputError, match="section = {'kind': 'round', ...}: the plate truth"):
        corner_static(frustum)
    assert frustum.kirchhoff_warnings() == ()  # no plate of a rod to warn about


def test_cli_truth_and_joint_fit_of_a_tube_file(tmp_path):
    p = tmp_path / "tube.json"
    save_beam(_tube(), p)
    assert main(["truth", str(p), "--model", "beam", "--modes", "3",
                 "--out", str(tmp_path / "t")]) == 0
    truth = json.loads((tmp_path / "t" / "truth.json").read_text())
    bl = _cantilever_roots(3)
    I, A = np.pi * (D**4 - DI**4) / 64.0, np.pi * (D**2 - DI**2) / 4.0
    ref = bl**2 / L**2 * np.sqrt(ALU.E_Pa * I / (ALU.rho_kg_m3 * A))
    # as in the tube test above: discretisation 1e-8 plus the Hermite basis' rounding
    rtol = 1e-8 + EPS * hermite_basis_cond(beam_stations(_tube()))
    np.testing.assert_allclose(truth["omega_rad_s"][:3], ref, rtol=rtol)
    assert main(["fit", str(p), "--joints", "3", "--truth-model", "beam", "--stiffness",
                 "joint", "--starts", "4", "--out", str(tmp_path / "f")]) == 0
    fitted = json.loads((tmp_path / "f" / "fit.json").read_text())
    assert fitted["beam"]["section"]["kind"] == "round"  # the model file keeps the section
    # the 3R joint fit reaches the truth's 3 modes to the least-squares tolerance (measured
    # 1e-13 %): 1e-8 % leaves gtol room
    assert max(abs(e) for e in fitted["omega_export_errors_pct"]) < 1e-8
