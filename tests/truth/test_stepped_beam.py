"""Width steps (two planform vertices at one station) against an exact stepped Euler-Bernoulli
cantilever (tests/stepped_eb.py: the 8x8 determinant of the two segments' general solutions),
hand integrals of the sections and an independent shooting solution of the elastica."""

import json

import numpy as np
import pytest
from paths import BEAMS
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq
from stepped_eb import stepped_frequencies, stepped_tip_compliance
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.chain.sections import link_sections
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam
from prbdm_pin.member.geometry import Beam, beam_to_dict
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.truth.beam import beam_modal, beam_stations
from prbdm_pin.truth.beam_static import beam_static
from prbdm_pin.truth.elastica import elastica_static

E, RHO, T = 205e9, 7850.0, 0.005
A, L, W1, W2 = 0.4, 1.0, 0.02, 0.01


def stepped() -> Beam:
    return Beam([0.0, A, A, L], [W1, W1, W2, W2], T, tip_force_N=np.array([0.0, 0.0, -20.0]))


def exact(n: int) -> np.ndarray:
    EI1, EI2 = E * 2 * W1 * T**3 / 12, E * 2 * W2 * T**3 / 12
    return stepped_frequencies(n, A, L, EI1, RHO * 2 * W1 * T, EI2, RHO * 2 * W2 * T)


def test_stations_rules():
    b = Beam([0.0, 0.5, 0.5, 1.0], [0.05, 0.05, 0.02, 0.02], 0.01)
    # right-continuous, with the root-side limit on request; integrals exact
    assert b.half_width_at(0.5) == 0.02 and b.half_width_at(0.5, "left") == 0.05
    np.testing.assert_array_equal(b.half_width_at([0.25, 0.5, 0.75]), [0.05, 0.02, 0.02])
    # the same trapezoids (exact here); kept: the test's 1e-15
    assert b.planform_area_m2 == pytest.approx(2 * (0.5 * 0.05 + 0.5 * 0.02), rel=5 * EPS)
    for x, w, pattern in [
        ([0, 0, 1], [1, 2, 2], r"x\[1\] = 0\.0 m: a width step at the root"),
        ([0, 1, 1], [1, 2, 2], r"x\[2\] = 1\.0 m: a width step at the tip"),
        ([0, .5, .5, .5, 1], [1, 2, 3, 4, 5], r"x\[1\] = x\[2\] = x\[3\] = 0\.5 m: at most two"),
        ([0, .5, .5, 1], [1, 2, 2, 1], r"x\[2\] = x\[1\] = 0\.5 m with half_width 2\.0 m on both"),
        ([0, .6, .5, 1], [1, 2, 2, 1], r"x\[2\] = 0\.5 m: must not decrease"),
    ]:
        with pytest.raises(BeamInputError, match=pattern):
            Beam(x, w, 0.01)


def test_json_round_trip_and_example(tmp_path):
    b = stepped()
    d = beam_to_dict(b)
    assert d["x"] == [0.0, A, A, L]
    b2 = beam_from_dict(json.loads(json.dumps(d)))
    np.testing.assert_array_equal(b2.half_width_m, b.half_width_m)
    assert b2.fingerprint() == b.fingerprint()
    ex = load_beam(BEAMS / "stepped-narrow.json")
    assert ex.step_index.size == 1


def _hand_sections(beam: Beam, a: float, b: float):
    """Mass, COM x and the three principal inertias of the link [a, b] by adaptive quadrature
    split at the step (independent of the package's Gauss rule)."""
    pts = [x for x in beam.x_m if a < x < b]
    w = beam.half_width_at
    rt = RHO * T

    def q(f):
        # the quadrature's request: 450 EPS (1e-13); QUADPACK's floor is 50 EPS
        return quad(f, a, b, points=pts or None, epsabs=0, epsrel=450 * EPS, limit=200)[0]

    m = rt * q(lambda x: 2 * w(x))
    xc = rt * q(lambda x: 2 * w(x) * x) / m
    syy = q(lambda x: 2 * w(x) ** 3 / 3)
    sxx = q(lambda x: 2 * w(x) * (x - xc) ** 2)
    thick = m * T**2 / 12
    return m, xc, np.array([rt * syy + thick, rt * sxx + thick, rt * (sxx + syy)])


@pytest.mark.parametrize("lengths", [[0.3, 0.3, 0.4], [0.4, 0.6], [0.25, 0.15, 0.6]])
def test_sections_of_links_that_straddle_or_end_on_the_step(lengths):
    # a tapered stepped planform: the hand integrals are not rectangles
    beam = Beam([0.0, A, A, L], [0.03, 0.02, 0.012, 0.006], T)
    sec = link_sections(beam, np.array(lengths))
    ends = np.cumsum(lengths)
    starts = np.r_[0.0, ends[:-1]]
    for i, (a, b) in enumerate(zip(starts, ends, strict=True)):
        m, xc, inertia = _hand_sections(beam, a, b)
        # Gauss rules against adaptive quadrature (450 EPS requested) of polynomial pieces: a
        # few roundings (<= 1.6 EPS measured); kept: the tests' 1e-12
        assert sec.mass_kg[i] == pytest.approx(m, rel=5000 * EPS)
        assert sec.com_m[i, 0] == pytest.approx(xc, rel=5000 * EPS)
        np.testing.assert_allclose(np.diag(sec.inertia_com_kg_m2[i]), inertia, rtol=1e-11)
        mean_I = quad(lambda x: 2 * beam.half_width_at(x) * T**3 / 12, a, b,
                      points=[A] if a < A < b else None, epsrel=450 * EPS)[0] / (b - a)
        assert sec.area_moment_m4[i] == pytest.approx(mean_I, rel=5000 * EPS)


def test_finite_segment_spring_across_the_step():
    beam = stepped()
    lengths = np.array([0.2, 0.4, 0.4])  # both springs' spans end on the step
    K = finite_segment_stiffness(beam, lengths)
    centres = [0.0, 0.4, 1.0]  # the clamp, link 1's mid-span, the tip (end links count to ends)
    I1, I2 = 2 * W1 * T**3 / 12, 2 * W2 * T**3 / 12
    # joint 0: [0, 0.4] all I1; joint 1: [0.4, 1.0] all I2 (a one-sided limit at each end)
    # integrals of 1 / EI over the spans against the hand sums: a few roundings (1.8 EPS
    # measured); kept: the tests' 1e-13
    np.testing.assert_allclose(K, [E * I1 / (centres[1] - centres[0]),
                                   E * I2 / (centres[2] - centres[1])], rtol=500 * EPS)
    lengths = np.array([0.3, 0.3, 0.4])  # joint 0 spans [0, 0.45]: 0.4 of I1 and 0.05 of I2
    K = finite_segment_stiffness(beam, lengths)
    assert K[0] == pytest.approx(E / (0.4 / I1 + 0.05 / I2), rel=500 * EPS)


def test_beam_truth_matches_the_exact_stepped_cantilever():
    ex = exact(4)
    m = beam_modal(stepped(), n_modes=4, n_elements=200)
    np.testing.assert_allclose(m.omega_rad_s, ex, rtol=1e-6)
    # the step is an element edge: a coarse mesh is already close (the integrals are exact)
    coarse = beam_modal(stepped(), n_modes=4, n_elements=40)
    np.testing.assert_allclose(coarse.omega_rad_s, ex, rtol=1e-4)


def test_beam_static_matches_the_stepped_compliance():
    beam = stepped()
    c = stepped_tip_compliance(A, L, E * 2 * W1 * T**3 / 12, E * 2 * W2 * T**3 / 12)
    st = beam_static(beam, n_elements=20)
    # Hermite elements are exact at the nodes, but their basis comes from inverting each
    # element's Vandermonde matrix (condition c_V = 5.4e5 here): the element matrices, and the
    # statics, are good to EPS c_V = 1.2e-10 relative, the solve adds as much (4e-12 measured;
    # the test's 1e-12 held only through approx's default absolute 1e-12)
    c_V = hermite_basis_cond(beam_stations(beam, 20))
    assert st.tip_displacement_m[2] == pytest.approx(-20.0 * c, rel=2 * EPS * c_V)


def test_finite_segment_prbdm_converges_to_the_exact_stepped_frequencies():
    ex = exact(4)
    errs = []
    for n in (20, 40):
        h = L / n
        lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
        model = build_model(stepped(), lengths,
                            finite_segment_stiffness(stepped(), lengths, min_fraction=1e-3),
                            min_fraction=1e-3)
        errs.append(np.abs(model.natural_frequencies()[:4] / ex - 1))
    # second order in the segment length
    assert np.all(errs[1] < 1e-3)
    assert np.all(errs[0] / errs[1] > 3.5)


def _shooting_tip(beam: Beam, F_z: float) -> np.ndarray:
    """Elastica tip by shooting on the root moment, the step a breakpoint of the integration."""
    def run(m0):
        def f(s, y):
            phi, m = y[0], y[1]
            return [m / (E * beam.area_moment_at(s, "left" if s == A else "right")),
                    -F_z * np.cos(phi), np.cos(phi), np.sin(phi)]
        y = np.array([0.0, m0, 0.0, 0.0])
        for a, b in ((0.0, A), (A, L)):
            # the integrator's request: 4500 EPS (1e-12) relative, 45 EPS (1e-14) absolute
            y = solve_ivp(f, (a, b), y, rtol=4500 * EPS, atol=45 * EPS,
                          method="DOP853").y[:, -1]
        return y

    m_lin = F_z * L  # the linear root moment (EI phi'); the large-deflection one is smaller
    lo, hi = sorted((0.3 * m_lin, 1.01 * m_lin))
    m0 = brentq(lambda m: run(m)[1], lo, hi, xtol=1e-15)
    y = run(m0)
    return np.array([y[2], 0.0, y[3]])


@pytest.mark.parametrize("F_z", [-1e-3, -60.0])
def test_elastica_across_the_step_against_shooting(F_z):
    beam = stepped().with_tip_force(np.array([0.0, 0.0, F_z]))
    st = elastica_static(beam)
    ref = _shooting_tip(beam, F_z)
    np.testing.assert_allclose(st.tip_position_m, ref, rtol=0, atol=1e-8 * L)
    if F_z == -1e-3:  # small load: the linear compliance
        c = stepped_tip_compliance(A, L, E * 2 * W1 * T**3 / 12, E * 2 * W2 * T**3 / 12)
        assert st.tip_displacement_m[2] == pytest.approx(F_z * c, rel=1e-6)
    else:
        assert abs(st.tip_displacement_m[2]) > 0.2 * L  # a large deflection indeed


def _quad_area(mesh) -> float:
    x, y = mesh.p[:, mesh.t]
    return float(0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y,
                                      axis=0)).sum())


def test_planform_meshes_follow_the_step():
    from prbdm_pin.truth.feature_mesh import planform_quad_mesh
    from prbdm_pin.truth.mesh import planform_tri_mesh

    beam = Beam([0.0, 0.3, 0.3, 0.7, 0.7, 1.0], [0.1, 0.08, 0.04, 0.04, 0.06, 0.05], 0.01)
    area = 2 * (0.3 * 0.09 + 0.4 * 0.04 + 0.3 * 0.055)  # trapezoids by hand
    for mesh in (planform_tri_mesh(beam, 1), planform_quad_mesh(beam, 1)):
        # a sum of element areas against the trapezoids: a few roundings (0.5 EPS measured);
        # kept: the test's 1e-12
        assert _quad_area(mesh) == pytest.approx(area, rel=5000 * EPS)
        for corner in ([0.3, 0.08], [0.3, 0.04], [0.7, 0.04], [0.7, 0.06], [0.3, -0.08]):
            assert np.min(np.hypot(*(mesh.p - np.array(corner)[:, None]))) < 1e-12
        # no element crosses the outline: every element centroid is inside the planform
        c = mesh.p[:, mesh.t].mean(axis=1)
        inside = np.abs(c[1]) < np.interp(c[0], [0, 0.3, 0.3 + 1e-15, 0.7, 0.7 + 1e-15, 1],
                                          [0.1, 0.08, 0.04, 0.04, 0.06, 0.05])
        assert inside.all()


def test_plate_truth_of_a_narrow_stepped_strip_is_near_euler_bernoulli():
    from prbdm_pin.truth import compute_truth

    beam = load_beam(BEAMS
                     / "stepped-narrow.json")
    tr = compute_truth(beam, model="plate", modes=4)
    err = np.asarray(tr.omega_rad_s) / exact(4) - 1
    # the plate is stiffer by its clamped Poisson effect (a few tenths of a percent on a strip
    # 40 mm wide: 0.08 % ... 0.24 % measured), never softer beyond the discretisation
    assert np.all(err > -5e-4) and np.all(err < 3e-3), err
    # a true step costs a mesh of a few thousand DOFs (a 0.1 mm ramp: about 40 k)
    assert tr.modal.dofs < 5000
    # the plate's linear tip deflection: the stepped compliance (measured +0.03 %)
    c = stepped_tip_compliance(A, L, E * 2 * W1 * T**3 / 12, E * 2 * W2 * T**3 / 12)
    w = tr.static_linear.tip_displacement_m[2]
    assert w == pytest.approx(beam.tip_force_N[2] * c, rel=2e-3)


@pytest.mark.slow
def test_solid_truth_of_a_narrow_stepped_strip_is_near_euler_bernoulli():
    from prbdm_pin.truth import compute_truth

    beam = load_beam(BEAMS
                     / "stepped-narrow.json")
    tr = compute_truth(beam, model="solid", modes=4, static=False)
    # measured +0.01, +0.06, -0.05, +0.16 % (50 k DOFs, 10 s)
    np.testing.assert_allclose(tr.omega_rad_s, exact(4), rtol=3e-3)
