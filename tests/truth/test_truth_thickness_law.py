"""The plate and 3D solid truths with a thickness law t(x), against independent references.

With nu = 0 a Kirchhoff strip's modes are the Euler-Bernoulli beam's exactly, whatever D(x):
w = w(x) leaves the free-edge moment D (w_yy + nu w_xx) and the Kirchhoff shear
D (w_yyy + (2 - nu) w_xxy) zero, and the twisting moment D (1 - nu) w_xy vanishes too. So the
plate must reproduce the 1D truth with the law (``truth/beam.py``, cubic Hermite, exact
quadrature of the quartic EI) and the tapered-member references (``tapered_reference``: Bessel
solutions and a separate Hermite FE), to its discretisation error.
"""

import numpy as np
import pytest
from scipy.integrate import quad
from tapered_reference import complete_taper_lambda1, richardson_lambda1
from tolerances import EPS, REFERENCE_RTOL

from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.beam import beam_modal
from prbdm_pin.truth.cache import cache_key
from prbdm_pin.truth.feature_mesh import planform_quad_mesh
from prbdm_pin.truth.law_mesh import law_stations
from prbdm_pin.truth.mesh import planform_tri_mesh
from prbdm_pin.truth.plate import plate_modes
from prbdm_pin.truth.plate_static import plate_static
from prbdm_pin.truth.solid import solid_mesh, solid_modal, solid_static

NU0 = Material("poisson-free aluminium", 70e9, 2700.0, 0.0)
X = np.array([0.0, 0.4, 1.0])
T = np.array([0.010, 0.007, 0.004])  # a kink at x = 0.4: slopes -7.5e-3 and -5e-3
WIDTH = 0.05


def _strip(thickness=T, material=NU0):
    return Beam(X, np.full(3, WIDTH / 2), thickness, material, np.array([0.0, 0.0, -1.0]))


def _nearest(w, ref):
    """The frequencies of ``w`` nearest to each of ``ref`` (drops torsion, in-plane modes)."""
    return np.array([w[np.argmin(np.abs(w / r - 1.0))] for r in ref])


def _tip_deflection_eb_m(beam, force_N=1.0):
    """Euler-Bernoulli tip deflection P int (L - s)^2 / EI(s) ds by adaptive quadrature, m."""
    E = beam.material.E_Pa

    def f(s):
        return (1.0 - s) ** 2 / (E * WIDTH * np.interp(s, X, beam.thickness_law_m) ** 3 / 12.0)

    return force_N * quad(f, 0.0, 1.0, points=[0.4], epsabs=0.0, epsrel=REFERENCE_RTOL)[0]


def _straddling(p_x, cells, x_k):
    v = p_x[cells]
    # nodes on the line carry x_k itself or a value a few roundings off it (x <= 1 m here)
    tol = 8 * EPS
    return int(np.sum((v.min(axis=0) < x_k - tol) & (v.max(axis=0) > x_k + tol)))


def test_meshes_have_edges_along_the_law_stations():
    beam = _strip()
    assert np.array_equal(law_stations(beam), [0.4])
    tri = planform_tri_mesh(beam, 0)
    quad_mesh = planform_quad_mesh(beam, 0)
    # no element straddles the kink: t is linear in every element, so quadrature is exact
    assert _straddling(tri.p[0], tri.t, 0.4) == 0
    assert _straddling(quad_mesh.p[0], quad_mesh.t, 0.4) == 0
    # the recovered station line still leaves a mesh that tiles the planform: the triangles'
    # areas sum to the rectangle's (a sum of n positive terms: n EPS relative at most)
    v = tri.p[:, tri.t]
    area = 0.5 * np.abs((v[0, 1] - v[0, 0]) * (v[1, 2] - v[1, 0])
                        - (v[0, 2] - v[0, 0]) * (v[1, 1] - v[1, 0]))
    np.testing.assert_allclose(area.sum(), WIDTH * 1.0, rtol=area.size * EPS)


def test_argyris_strip_with_law_is_the_1d_truth_at_nu_0():
    beam = _strip()
    ref = beam_modal(beam, 5).omega_rad_s
    for level in (0, 1):
        w = _nearest(plate_modes(beam, level, 10).omega_rad_s, ref)
        # measured 4.5e-8 (mode 5, level 0): the 1D truth's 200 Hermite elements and the plate's
        # shift-invert solve (eigenpair relative residual up to 6e-8, mode 1 at level 1); the
        # bound is 3x that residual
        np.testing.assert_allclose(w, ref, rtol=2e-7)


def test_morley_strip_with_law_converges_from_below_at_rate_two():
    beam = _strip()
    ref = beam_modal(beam, 3).omega_rad_s
    err = np.array([_nearest(plate_modes(beam, lv, 10, "morley").omega_rad_s, ref) / ref - 1.0
                    for lv in (0, 1, 2)])
    # Morley is nonconforming: from below, error O(h^2) (measured ratios 3.85 ... 3.97)
    assert np.all(err < 0.0)
    ratio = err[:-1] / err[1:]
    assert np.all((ratio > 3.5) & (ratio < 4.5)), ratio


def test_plate_static_with_law_is_the_euler_bernoulli_integral():
    beam = _strip()
    u = plate_static(beam, 0).tip_displacement_m[2]
    # measured 1.5e-9: Argyris quintics against a cubic-in-x moment curvature; quad at
    # REFERENCE_RTOL (1e-12)
    np.testing.assert_allclose(u, -_tip_deflection_eb_m(beam), rtol=1e-8)


@pytest.mark.parametrize("ratio", [0.5, 0.2, 0.05])
def test_wedge_plate_lambda1_matches_tables_and_tends_to_5_315(ratio):
    L, t0 = 1.0, 0.01
    beam = Beam(np.array([0.0, L]), np.full(2, WIDTH / 2), np.array([t0, ratio * t0]), NU0)
    E, rho = NU0.E_Pa, NU0.rho_kg_m3
    lam = plate_modes(beam, 0, 4).omega_rad_s[0] * L**2 * np.sqrt(rho * t0 / (E * t0**3 / 12))
    ref, ref_err = richardson_lambda1(ratio, 1)
    # measured 7.8e-9 ... 2.9e-10 from the Richardson value (itself good to ref_err <= 2e-9)
    assert abs(lam - ref) < 1e-7 + ref_err
    # the complete wedge (ratio 0) is Kirchhoff's Bessel root 5.315: approached from below
    assert lam < complete_taper_lambda1(1)


def test_uniform_law_is_the_uniform_thickness():
    t = 0.008
    law, one = _strip(np.full(3, t)), _strip(t)
    assert law.thickness_law_m is None  # equal entries are the uniform thickness
    a = plate_modes(law, 0, 6).omega_rad_s
    b = plate_modes(one, 0, 6).omega_rad_s
    np.testing.assert_array_equal(a, b)  # the same beam, mesh and arithmetic: exact
    assert cache_key(law, model="plate") == cache_key(one, model="plate")


def test_a_law_changes_the_cache_key():
    assert cache_key(_strip(), model="plate") != cache_key(_strip(0.01), model="plate")


def test_solid_strip_with_law_below_euler_bernoulli_by_timoshenko():
    beam = _strip()
    ref = beam_modal(beam, 3).omega_rad_s
    gap = 1.0 - _nearest(solid_modal(beam, 0, 12).omega_rad_s, ref) / ref
    # shear and rotary inertia lower bending mode m by about (beta_m t / L)^2 / 24
    # (1 + E / (kappa G)) (Timoshenko, kappa = 5/6, nu = 0): at the root thickness an upper bound
    # for a member thinner elsewhere; measured 3.7e-5, 1.5e-4, 3.3e-4 against bounds 5.0e-5,
    # 3.1e-4, 8.7e-4
    beta = np.array([1.8751, 4.6941, 7.8548])
    bound = (beta * T[0]) ** 2 / 24.0 * (1.0 + 2.0 / (5.0 / 6.0))
    assert np.all((gap > 0.0) & (gap < bound)), (gap, bound)


def test_solid_static_with_law_between_euler_bernoulli_and_timoshenko():
    beam = _strip()
    eb = _tip_deflection_eb_m(beam)
    G = NU0.G_Pa
    shear = quad(lambda s: 1.0 / (5.0 / 6.0 * G * WIDTH * np.interp(s, X, T)), 0.0, 1.0,
                 points=[0.4], epsabs=0.0, epsrel=REFERENCE_RTOL)[0]
    u = -solid_static(beam, 1).tip_displacement_m[2]
    # above Euler-Bernoulli by less than Timoshenko's shear term (the clamp blocks some of the
    # root's shear): measured 2.7e-5 against 4.4e-5
    assert eb < u < eb + shear, ((u - eb) / eb, shear / eb)


def test_compute_truth_plate_with_law_selects_the_1d_modes(tmp_path):
    beam = _strip()
    r = compute_truth(beam, model="plate", modes=3, static=False, cache_dir=tmp_path)
    ref = beam_modal(beam, 3).omega_rad_s
    # the selection, labels and error estimate run on the law's plate: the 1D modes at nu = 0
    # (bound as in the plate test above)
    np.testing.assert_allclose(r.omega_rad_s, ref, rtol=2e-7)
    assert all(k == "bending" for k in r.labels[: 3])
    # a second call is served from the cache under the law's key: the same numbers
    again = compute_truth(beam, model="plate", modes=3, static=False, cache_dir=tmp_path)
    np.testing.assert_array_equal(again.omega_rad_s, r.omega_rad_s)


def test_solid_nodes_follow_the_law_faces():
    beam = _strip()
    nodes = solid_mesh(beam, 0).p.T  # the solid truth's mesh: its VTU's points
    half = 0.5 * np.interp(nodes[:, 0], X, T)  # t(x) / 2 from the stations directly
    # every vertex on a face z = +-t(x)/2: the mapped z is t(x) / 2 times +-1, one rounding
    np.testing.assert_allclose(np.abs(nodes[:, 2]), half, rtol=4 * EPS)


def _min_angle_deg(mesh):
    """Smallest interior angle of a triangle mesh, degrees."""
    v = mesh.p[:, mesh.t]
    out = []
    for a, b, c in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        u, w = v[:, b] - v[:, a], v[:, c] - v[:, a]
        cos = (u * w).sum(axis=0) / (np.linalg.norm(u, axis=0) * np.linalg.norm(w, axis=0))
        out.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    return float(np.min(out))


def test_a_station_line_too_steep_against_the_outline_is_left_out():
    # at x = 0.5 the outline drops 90 mm over 1 mm (0.6 degrees from the station line): a line
    # there would make slivers; at x = 0.501 the drop rises away from the line (179.4 degrees)
    # and the outline continues straight (90 degrees), as at x = 0.8
    beam = Beam([0.0, 0.5, 0.501, 0.8, 1.0], [0.1, 0.1, 0.01, 0.01, 0.01],
                [0.01, 0.008, 0.00799, 0.004, 0.003], NU0)
    np.testing.assert_array_equal(law_stations(beam), [0.501, 0.8])
    assert _straddling(planform_tri_mesh(beam, 0).p[0], planform_tri_mesh(beam, 0).t, 0.8) == 0


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 5, 7])
def test_random_panels_with_a_law_keep_their_mesh_quality(seed):
    from prbdm_pin.member.random_beams import random_beam
    from prbdm_pin.truth.feature_mesh import feature_size_tri_mesh
    from prbdm_pin.truth.mesh import element_size

    b = random_beam(np.random.default_rng(seed))
    x = b.x_m
    xu = np.unique(x)
    t = np.interp(x, xu, np.random.default_rng(100 + seed).uniform(0.003, 0.01, xu.size))
    law = Beam(x, b.half_width_m, t, b.material)
    for xk in law_stations(law):
        for m in (planform_tri_mesh(law, 0), planform_quad_mesh(law, 0)):
            assert _straddling(m.p[0], m.t, xk) == 0
    # the station lines cost the plate mesh no angle (measured: equal on seeds 0-7) and the
    # solid's triangle mesh at most a factor 3 (measured worst 5.2 against 14.7 degrees)
    assert _min_angle_deg(planform_tri_mesh(law, 0)) >= _min_angle_deg(planform_tri_mesh(b, 0))
    h = 2.0 * element_size(b, 0)
    f = [_min_angle_deg(feature_size_tri_mesh(bb, h, 0.5, 0.25 * 0.003)) for bb in (law, b)]
    assert f[0] >= f[1] / 3.0, f
