"""The elastica with Ashwell's anticlastic restraint: the closed-form factor against a
quadrature of the strip's cross-section, its derivatives against differences, and the
large-deflection tip gradients against fourth-order central differences of
``elastica_static(anticlastic=True)``."""


import numpy as np
import pytest
from elastica_differences import REL, TOL, check, fd_design, fd_force
from paths import BEAMS
from scipy.integrate import quad
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.member.geometry import Beam
from prbdm_pin.truth.anticlastic import (
    anticlastic_factor,
    anticlastic_terms,
    eta_per_root_curvature,
    section_curvature,
)
from prbdm_pin.truth.elastica import elastica_static


def _quadrature_factor(eta: float, nu: float) -> float:
    """M / (EI kappa) from the stresses of the strip's cross-section: the deflection
    f = nu kappa a^2 g(xi) solves g'''' + 4 eta^4 g = 0, g''(1) = -1, g'''(1) = 0 (even
    solutions Re, Im cosh((1 + i) eta xi), constants by a 2 x 2 solve), and M integrates
    D (kappa + nu f'') + E t kappa f^2 over the width, int g^2 by adaptive quadrature."""
    k = (1.0 + 1.0j) * eta
    c2, s3 = k**2 * np.cosh(k), k**3 * np.sinh(k)
    A, B = np.linalg.solve([[c2.real, c2.imag], [s3.real, s3.imag]], [-1.0, 0.0])
    g1 = k * np.sinh(k)

    def g(x):
        h = np.cosh(k * x)
        return A * h.real + B * h.imag

    # the quadrature's request: 4500 EPS (1e-12) relative, QUADPACK's floor being 50 EPS
    g2 = 2.0 * quad(lambda x: g(x) ** 2, 0.0, 1.0, limit=200, epsabs=0.0,
                    epsrel=4500 * EPS)[0]
    return (1.0 + nu**2 * (A * g1.real + B * g1.imag + 2.0 * eta**4 * g2)) / (1.0 - nu**2)


@pytest.mark.parametrize("nu", [0.28, 0.45, -0.3])
def test_closed_form_factor_is_the_cross_section_quadrature(nu):
    eta = np.array([0.05, 0.3, 0.8, 1.5, 2.5, 5.0, 12.0, 30.0])
    ref = np.array([_quadrature_factor(e, nu) for e in eta])
    assert np.abs(anticlastic_factor(eta, nu) - ref).max() < 1e-13
    assert np.all(np.diff(anticlastic_factor(eta, nu)) > 0.0)  # monotone in the curvature


def test_factor_limits():
    """r - 1 = (8 / 45) nu^2 eta^4 / (1 - nu^2) (1 + O(eta^4)) near 0 (the series is used below
    1e-2, the closed form above); r = (1 - 3 nu^2 / (4 eta)) / (1 - nu^2) up to exp(-2 eta)
    for large eta."""
    nu = 0.28
    e = np.array([0.009, 0.011, 0.02])
    series = 8.0 / 45.0 * nu**2 * e**4 / (1.0 - nu**2)
    assert np.abs((anticlastic_factor(e, nu) - 1.0) / series - 1.0).max() < 1e-6
    e = np.array([30.0, 200.0, 1e4])
    assert np.abs(anticlastic_factor(e, nu) - (1.0 - 0.75 * nu**2 / e) / (1.0 - nu**2)).max() \
        < 1e-15
    assert anticlastic_factor(np.array([0.0, -0.5]), nu)[0] == 1.0
    assert anticlastic_factor(np.array([-0.5]), nu) == anticlastic_factor(np.array([0.5]), nu)


def test_factor_derivatives_against_differences():
    """eta r_eta and r_nu against fourth-order central differences, across the series switch
    (1e-2), the transition (eta ~ 1) and the algebraic tail."""
    nu = 0.28
    e = np.concatenate([np.geomspace(1e-3, 300.0, 400), [0.00999, 0.01, 0.01001]])
    r, eta_dr, dr_dnu = anticlastic_terms(e, nu)
    h = 1e-4 * e

    def d4(f, x, hx):
        return (8.0 * (f(x + hx) - f(x - hx)) - (f(x + 2 * hx) - f(x - 2 * hx))) / (12.0 * hx)

    fd_eta = e * d4(lambda x: anticlastic_factor(x, nu), e, h)
    assert np.abs(fd_eta - eta_dr).max() < 1e-11
    fd_nu = d4(lambda v: anticlastic_factor(e, v), nu, 1e-3)
    assert np.abs(fd_nu - dr_dnu).max() < 1e-10
    # the moment grows with the curvature: d(kappa r) / d kappa = r + eta r_eta / 2 >= 1
    assert np.all(r + 0.5 * eta_dr >= 1.0)


def test_section_curvature_solves_the_moment_law():
    rng = np.random.default_rng(3)
    w = rng.uniform(0.005, 0.2, 50)
    t, nu, E = 0.002, 0.3, 70e9
    ei = E * 2.0 * w * t**3 / 12.0
    m = rng.uniform(-1.0, 1.0, 50) * ei * rng.uniform(0.0, 50.0, 50)
    kappa = section_curvature(m, ei, w, t, nu)
    eta = eta_per_root_curvature(w, t, nu) * np.sqrt(np.abs(kappa))
    assert eta.max() > 5.0 and eta.min() < 1.0  # both regimes
    assert np.abs(ei * kappa * anticlastic_factor(eta, nu) - m).max() <= 1e-13 * np.abs(m).max()


def _steel():
    return pp.load_beam(BEAMS / "tapered.json").material


def _thin_tapered() -> Beam:
    """2 mm thick, 100 mm wide at the root, tapering by kinks; combined tip load: eta about 1.2
    at the root, the anticlastic restraint lifts the tip by 1.1 mm."""
    return Beam(np.array([0.0, 0.2, 0.45, 0.6]), np.array([0.05, 0.04, 0.03, 0.02]), 0.002,
                _steel(), np.array([-5.0, 0.0, -15.0]), "thin-tapered", "")


def _thin_stepped() -> Beam:
    """A width step at x = 0.5 m between kinked spans, 2 mm thick; eta about 1.1 at the root."""
    return Beam(np.array([0.0, 0.25, 0.5, 0.5, 0.8, 1.0]),
                np.array([0.05, 0.045, 0.04, 0.025, 0.022, 0.02]), 0.002, _steel(),
                np.array([0.0, 0.0, -8.0]), "thin-stepped", "")


def _anticlastic_matters(g, beam, names, **kwargs):
    """The anticlastic terms move the gradient by far more than the tests' bound."""
    plain = pp.elastica_gradient(beam, names, tol=TOL, **kwargs).d_tip_position_m
    scale = np.abs(g.d_tip_position_m).max(axis=0)
    assert (np.abs(g.d_tip_position_m - plain).max(axis=0) / scale).max() > 1e3 * REL


def test_uniform_strip_against_differences():
    beam = pp.load_beam(BEAMS / "uniform-narrow.json")  # P L^2 / EI = 1
    names = ("thickness", "half_width[1]", "nu")
    g = pp.elastica_gradient(beam, names, tol=TOL, anticlastic=True)
    assert g.anticlastic
    # exact by construction: elastica_static is the same primal solve; slack 5000 EPS L
    # (the test's 1e-12 m on this 1 m strip)
    assert np.allclose(g.tip_position_m,
                       elastica_static(beam, tol=TOL, anticlastic=True).tip_position_m,
                       rtol=0.0, atol=5000 * EPS * beam.length_m)
    check(g.d_tip_position_m[:, :2], fd_design(beam, names[:2], anticlastic=True))
    # on this narrow strip the tip's nu derivative is 5e-5 of the others: the reference's
    # rounding over the default step (1e-4) scatters by 1e-9 of it, over 1e-3 by 4e-11
    check(g.d_tip_position_m[:, 2:], fd_design(beam, names[2:], rel=1e-2, anticlastic=True))
    _anticlastic_matters(g, beam, names)
    assert np.all(g.d_tip_position_m[1] == 0.0)


def test_modulus_and_the_invariant_scaling():
    """The tip depends on F / (E w t^3) and on eta ~ w / sqrt(t): d r / d E = -(1 / E) F . dr/dF
    (dr/dF by differences in the load), and scaling t by (1 + e), every half-width by
    (1 + e / 2) and E by (1 - 7 e / 2) leaves both, so t r_t + 1/2 sum w_i r_w_i - 7/2 E r_E = 0.
    On the thin tapered beam under its combined load."""
    beam = _thin_tapered()
    names = ("thickness", "half_width[0]", "half_width[1]", "half_width[2]", "half_width[3]",
             "E")
    g = pp.elastica_gradient(beam, names, tol=TOL, anticlastic=True)
    dF = fd_force(beam, anticlastic=True)
    check(g.d_tip_d_force_m_per_N[[0, 2]], dF[[0, 2]])
    along = dF @ beam.tip_force_N[[0, 2]]
    E, t = beam.material.E_Pa, beam.thickness_m
    d_E = g.d_tip_position_m[:, -1]
    assert np.abs(d_E + along / E).max() < REL * np.abs(along).max() / E
    terms = g.d_tip_position_m * np.r_[t, 0.5 * g.values[1:5], -3.5 * E]
    assert np.abs(terms.sum(axis=1)).max() < 1e-12 * np.abs(terms).max()
    # the restraint breaks the plain elastica's scaling t r_t = 3 E r_E (EI ~ E t^3)
    d_t = g.d_tip_position_m[:, 0]
    assert np.abs(d_t * t - 3.0 * E * d_E).max() > 1e-3 * np.abs(d_t * t).max()


def test_tapered_combined_load_against_differences():
    beam = _thin_tapered()
    names = ("half_width[1]", "x[2]", "nu")
    g = pp.elastica_gradient(beam, names, tol=TOL, anticlastic=True)
    check(g.d_tip_position_m, fd_design(beam, names, anticlastic=True))
    _anticlastic_matters(g, beam, names)


def test_stepped_against_differences_with_a_moved_step():
    beam = _thin_stepped()
    names = ("x[3]", "half_width[3]", "thickness")  # x[3] moves the step
    g = pp.elastica_gradient(beam, names, tol=TOL, anticlastic=True, ei_scale=0.9)
    check(g.d_tip_position_m, fd_design(beam, names, anticlastic=True, ei_scale=0.9))
    _anticlastic_matters(g, beam, names, ei_scale=0.9)


def test_plate_calibrated_scale_with_the_restraint():
    """``ei_scale="plate"`` chains the scale's gradient (tested in test_elastica_gradient.py)
    through d r / d scale, here against differences of the anticlastic elastica in the scale."""
    beam = pp.load_beam(BEAMS / "tapered.json")
    names = ("half_width[0]", "nu")
    g = pp.elastica_gradient(beam, names, ei_scale="plate", tol=TOL, anticlastic=True)
    fixed = pp.elastica_gradient(beam, names, ei_scale=g.ei_scale, tol=TOL, anticlastic=True)
    s, h = g.ei_scale, 1e-3 * g.ei_scale
    tip = {k: elastica_static(beam, tol=TOL, anticlastic=True,
                              ei_scale=s + k * h).tip_position_m for k in (-2, -1, 1, 2)}
    d_scale = (8.0 * (tip[1] - tip[-1]) - (tip[2] - tip[-2])) / (12.0 * h)
    check(g.d_tip_position_m, fixed.d_tip_position_m + np.outer(d_scale, g.d_ei_scale))
    assert np.abs(g.d_ei_scale).min() > 0.0
