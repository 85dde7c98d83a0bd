"""A thickness law t(x) along the planform member: sections, springs, the 1D truth, beam JSON.

Independent references: Kirchhoff's Bessel-function wedge (lambda_1 = 5.3151) and a separate
numpy cubic-Hermite FE with Richardson extrapolation (``tests/tapered_reference.py``) for the
partial tapers; scipy's adaptive quadrature of the section integrals for the link properties and
the springs; field names written in the tests for bad input.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from scipy.integrate import quad
from tapered_reference import complete_taper_lambda1, richardson_lambda1
from tolerances import EPS

from prbdm_pin.chain.sections import link_sections, planar_sections
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam, save_beam
from prbdm_pin.member.geometry import Beam, beam_to_dict
from prbdm_pin.truth.beam import beam_modal
from prbdm_pin.truth.beam_spatial import beam_spatial_modal
from prbdm_pin.truth.elastica import elastica_static

L, W, T0 = 1.0, 0.05, 0.01  # m: a 1 m strip 0.1 m wide, 10 mm thick at the root


def _wedge(ratio: float) -> Beam:
    """Constant width, thickness tapering linearly from T0 to ratio T0 at the tip."""
    return Beam([0.0, L], [W, W], [T0, ratio * T0])


def _lambda1(beam: Beam) -> float:
    """lambda_1 = omega_1 L^2 sqrt(rho A_0 / (E I_0)) at the root section."""
    rhoA0 = beam.material.rho_kg_m3 * 2.0 * W * T0
    return float(beam_modal(beam, 1).omega_rad_s[0] * L**2 * np.sqrt(rhoA0 / beam.root_EI_Nm2))


def test_reference_fe_reproduces_kirchhoff_wedge():
    # the helper FE at a complete taper (t = 0 at the tip, which the package refuses) against
    # the Bessel root: Richardson remainder 2e-10, dense-eigensolver rounding ~1e-10
    ref, err = richardson_lambda1(0.0, 1, 50)
    exact = complete_taper_lambda1(1)
    assert abs(exact - 5.315) < 5e-4  # the tabulated 5.315 (Blevins; Conway et al.)
    assert abs(ref / exact - 1.0) < 1e-9, (ref, exact, err)


@pytest.mark.parametrize("ratio", [0.1, 0.02, 0.01])
def test_wedge_truth_matches_converged_fe(ratio):
    ref, err = richardson_lambda1(ratio, 1, 50)
    lam = _lambda1(_wedge(ratio))
    # 200 Hermite elements: discretisation error O(h^4) ~1e-9 here (measured 4e-10 at 0.01),
    # the reference's Richardson remainder <= 1e-9: 1e-8 covers both with margin
    assert abs(lam / ref - 1.0) < 1e-8, (lam, ref, err)


def test_wedge_trend_to_the_complete_wedge():
    exact = complete_taper_lambda1(1)
    lam = np.array([_lambda1(_wedge(r)) for r in (0.1, 0.05, 0.02, 0.01, 0.002)])
    # a fuller taper sheds more mass than stiffness near the tip: lambda_1 rises toward 5.3151
    assert np.all(np.diff(lam) > 0.0) and lam[-1] < exact, lam
    assert abs(lam[-1] / exact - 1.0) < 5e-3, lam  # 0.2 % thickness left at the tip


@pytest.fixture(scope="module")
def tapered():
    """A trapezoid planform with a kinked thickness law (two laws with different stations)."""
    return Beam([0.0, 0.3, 1.0], [0.05, 0.04, 0.02], [0.01, 0.006, 0.0003],
                tip_force_N=[0.0, 0.0, -1.0])


def _quad(f, a, b):
    # the integrands kink at x = 0.3; scipy's own tolerance request 1e-13 (450 EPS)
    return quad(f, a, b, points=[0.3] if a < 0.3 < b else None, epsabs=0.0,
                epsrel=450 * EPS, limit=200)[0]


def test_link_sections_match_quadrature(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    s = link_sections(tapered, lengths)
    rho = tapered.material.rho_kg_m3

    def w(x):
        return float(tapered.half_width_at(x))

    def t(x):
        return float(np.interp(x, [0.0, 0.3, 1.0], [0.01, 0.006, 0.0003]))

    for i, (a, b) in enumerate(zip(s.start_m, s.end_m, strict=True)):
        m = rho * _quad(lambda x: 2 * w(x) * t(x), a, b)
        xc = rho * _quad(lambda x: 2 * w(x) * t(x) * x, a, b) / m
        Ixx = rho * _quad(lambda x: 2 * w(x) ** 3 / 3 * t(x) + 2 * w(x) * t(x) ** 3 / 12, a, b)
        Iyy = rho * _quad(lambda x, xc=xc: 2 * w(x) * t(x) * (x - xc) ** 2
                          + 2 * w(x) * t(x) ** 3 / 12, a, b)
        Izz = rho * _quad(lambda x, xc=xc: 2 * w(x) * t(x) * (x - xc) ** 2
                          + 2 * w(x) ** 3 / 3 * t(x), a, b)
        I_mean = _quad(lambda x: 2 * w(x) * t(x) ** 3 / 12, a, b) / (b - a)
        got = [s.mass_kg[i], s.com_m[i, 0], *np.diag(s.inertia_com_kg_m2[i]),
               s.area_moment_m4[i]]
        # quad's request 1e-13 and a few roundings of the Gauss sums: 2e-12 relative
        np.testing.assert_allclose(got, [m, xc, Ixx, Iyy, Izz, I_mean], rtol=1e4 * EPS)
    assert abs(s.mass_kg.sum() / tapered.mass_kg - 1.0) < 20 * EPS  # sums of 4 links: 20 EPS
    mass, offset, Iyy_p, _ = planar_sections(tapered, lengths)
    np.testing.assert_allclose(Iyy_p, s.inertia_com_kg_m2[:, 1, 1], rtol=20 * EPS)


def test_elastica_small_load_matches_linear_theory(tapered):
    # at P = 0.01 N the tip turns by ~1e-5 rad: the geometric nonlinearity is ~1e-10 relative,
    # so the elastica meets the linear P ∫ (L - x)^2 / EI dx
    P = 0.01
    e = elastica_static(tapered, [0.0, 0.0, -P])
    E = tapered.material.E_Pa
    ref = P * _quad(lambda x: (1.0 - x) ** 2 / (E * float(tapered.area_moment_at(x))), 0.0, 1.0)
    # solve_bvp's residual tolerance 1e-9 of the moment scale, a few times that in the tip
    # (measured 9e-9 on another taper): 1e-7
    assert abs(-e.tip_displacement_m[2] / ref - 1.0) < 1e-7


def test_springs_match_quadrature_of_compliance(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    K = finite_segment_stiffness(tapered, lengths)
    c = [0.0, 0.35, 0.65, 1.0]  # the springs' spans: clamp, link mid-points, tip
    E = tapered.material.E_Pa
    ref = [E / _quad(lambda x: 1.0 / float(tapered.area_moment_at(x)), c[j], c[j + 1])
           for j in range(3)]
    # 1 / I varies 1e4-fold on the last span; quad's request 1e-13 and the split 8-point
    # Gauss (error ~1e-16 per piece): 1e-12 relative
    np.testing.assert_allclose(K, ref, rtol=5000 * EPS)


def test_uniform_law_is_bit_identical_to_the_number():
    x, w = [0.0, 0.4, 1.0], [0.05, 0.03, 0.02]
    a = Beam(x, w, 0.004)
    b = Beam(x, w, [0.004, 0.004, 0.004])
    lengths = np.array([0.25, 0.25, 0.25, 0.25])
    assert b.thickness_law_m is None and b.thickness_m == a.thickness_m
    sa, sb = link_sections(a, lengths), link_sections(b, lengths)
    for f in ("mass_kg", "com_m", "inertia_com_kg_m2", "area_moment_m4"):
        assert np.array_equal(getattr(sa, f), getattr(sb, f)), f  # exact by construction
    assert np.array_equal(finite_segment_stiffness(a, lengths),
                          finite_segment_stiffness(b, lengths))
    assert np.array_equal(beam_modal(a, 3).omega_rad_s, beam_modal(b, 3).omega_rad_s)


def test_beam_json_round_trip(tapered, tmp_path):
    p = save_beam(tapered, tmp_path / "b.json")
    d = json.loads(p.read_text())
    assert d["thickness"] == [0.01, 0.006, 0.0003]
    back = load_beam(p)
    assert np.array_equal(back.thickness_law_m, tapered.thickness_law_m)  # lossless JSON
    lengths = np.array([0.2, 0.3, 0.5])
    assert np.array_equal(link_sections(back, lengths).inertia_com_kg_m2,
                          link_sections(tapered, lengths).inertia_com_kg_m2)
    assert beam_to_dict(Beam([0, 1], [0.05, 0.05], 0.01))["thickness"] == 0.01
    # copies keep the law (dataclasses.replace passes it back through the checks)
    assert np.array_equal(dataclasses.replace(tapered, name="c").thickness_law_m,
                          tapered.thickness_law_m)
    assert np.array_equal(tapered.with_tip_force([0.0, 0.0, -2.0]).thickness_law_m,
                          tapered.thickness_law_m)


@pytest.mark.parametrize("thickness, words", [
    ([0.01, 0.0], "thickness[1] = 0.0 m at x = 1.0 m: must be > 0"),
    ([0.01, -0.002], "thickness[1] = -0.002 m at x = 1.0 m"),
    ([0.01], "thickness has 1 entries: a thickness law must be aligned with x"),
    ([0.01, 0.005, 0.002], "thickness has 3 entries"),
    ([0.01, "a"], "thickness[1] = 'a': must be a number (m)"),
    ("0.01", "thickness = '0.01': must be a number"),
    ([None, []], "thickness[0] = None: must be a number (m)"),  # ragged: no numpy traceback
    ([[0.01], [0.02]], "thickness[0] = [0.01]: must be a number (m)"),
])
def test_bad_thickness_law_is_refused_by_name(thickness, words):
    with pytest.raises(BeamInputError) as e:
        beam_from_dict({"x": [0.0, 1.0], "half_width": [0.05, 0.05], "thickness": thickness})
    assert words in str(e.value)


def test_thickness_jump_at_a_width_step_is_refused():
    with pytest.raises(BeamInputError, match=r"thickness\[2\] = 0.004 m at the width step"):
        Beam([0.0, 0.5, 0.5, 1.0], [0.05, 0.05, 0.03, 0.03], [0.01, 0.006, 0.004, 0.002])


def test_cli_refuses_a_law_reaching_zero_in_one_line(tmp_path, capsys):
    p = tmp_path / "b.json"
    p.write_text(json.dumps({"x": [0.0, 0.5, 1.0], "half_width": [0.05, 0.05, 0.05],
                             "thickness": [0.01, 0.0, 0.004], "tip_force": [0, 0, -1]}))
    code = main(["fit", str(p), "--joints", "2", "--truth-model", "beam",
                 "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "thickness[1] = 0.0 m at x = 0.5 m" in err, err
    assert not (tmp_path / "o").exists()  # nothing half-written


def test_a_model_without_the_law_refuses_it_by_name(tapered):
    # the plate and solid truths take the law (tests/truth/test_truth_thickness_law.py); the
    # 1D torsion truth does not
    with pytest.raises(BeamInputError,
                       match="varies along x: the 1D torsion truth takes a uniform"):
        beam_spatial_modal(tapered)
