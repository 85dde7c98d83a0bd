"""The 1D Timoshenko truth against the closed-form cantilever (Huang 1961; Han, Benaroya & Wei
1999), its Euler-Bernoulli limit, the unit-load tip deflection, Cowper's coefficients, another
element, and the criterion's first-order estimate against the exact frequency equation."""

from __future__ import annotations

import numpy as np
import pytest
from reference import BETA_L
from scipy.integrate import quad
from timoshenko_reference import first_order_coefficients, timoshenko_cantilever_omega
from tolerances import EPS

from prbdm_pin.errors import BeamInputError, InputTypeError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.truth.beam import beam_modal
from prbdm_pin.truth.beam_timoshenko import (
    beam_timoshenko_modal,
    beam_timoshenko_static,
    timoshenko_modal,
    timoshenko_static,
)
from prbdm_pin.truth.timoshenko_criterion import (
    CANTILEVER_C,
    eb_error_estimate_pct,
    timoshenko_criterion,
)
from prbdm_pin.truth.timoshenko_sections import SectionLaws, shear_coefficient

E, NU, RHO = 205e9, 0.28, 7850.0
G = E / (2 * (1 + NU))
KAPPA = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper's rectangle, written out
B, T = 0.05, 0.01  # a 50 x 10 mm steel bar
A, I = B * T, B * T**3 / 12
RG = np.sqrt(I / A)


def _uniform(slenderness):
    return slenderness * RG, dict(EI_Nm2=E * I, kappaGA_N=KAPPA * G * A, rhoA_kg_m=RHO * A,
                                  rhoI_kg_m=RHO * I)


def _exact(L, laws, n=4):
    return timoshenko_cantilever_omega(L, laws["EI_Nm2"], laws["kappaGA_N"], laws["rhoA_kg_m"],
                                       laws["rhoI_kg_m"], n)


@pytest.mark.parametrize("slenderness", [10.0, 20.0, 50.0])
def test_frequencies_converge_like_h4_to_the_frequency_equation(slenderness):
    L, laws = _uniform(slenderness)
    exact = _exact(L, laws)
    err = [timoshenko_modal(SectionLaws(**laws), L, n_modes=4, n_elements=n).omega_rad_s
           / exact - 1.0
           for n in (20, 40)]
    # from above (consistent mass, conforming): Rayleigh-Ritz bound; 1e-9: the reference's
    # root tolerance and the eigensolve's rounding, both below 1e-12 here
    assert np.all(err[1] > -1e-9) and np.all(err[0] > err[1])
    # h^4: halving h divides the error by 16 (measured 15.6-16.0); 12..17 leaves room for the
    # next term of the expansion
    rate = err[0] / err[1]
    assert np.all((rate > 12.0) & (rate < 17.0)), rate
    # 40 elements: mode 4 within 1.2e-5 (measured 3.7e-6 at L/r_g = 10, 1.0e-5 at 50)
    assert np.all(err[1] < 1.2e-5), err[1]


def test_the_slender_limit_is_euler_bernoulli():
    # L / r_g = 1e4: Timoshenko's frequencies lie below beta_n^2 sqrt(EI / (rho A)) / L^2 by the
    # first-order estimate (<= 2.9e-6 here), and so do the closed form's and the element's
    L, laws = _uniform(1e4)
    eb = BETA_L[:4] ** 2 / L**2 * np.sqrt(E * I / (RHO * A))
    bound = eb_error_estimate_pct(4, 1e-4, E / (KAPPA * G)) / 100.0
    exact = _exact(L, laws)
    # 1.01: the estimate's second-order term (1e-2 of itself at most at this slenderness);
    # 1e-9: the reference's rounding (the determinant cancels to ~1e-11 of its terms)
    assert np.all(np.abs(exact / eb - 1.0) <= 1.01 * bound + 1e-9)
    fe = timoshenko_modal(SectionLaws(**laws), L, n_modes=4, n_elements=40).omega_rad_s
    # + 1.2e-5: the discretisation at 40 elements (previous test)
    assert np.all(np.abs(fe / eb - 1.0) <= 1.01 * bound + 1.2e-5)


def test_no_locking_on_a_coarse_mesh_of_a_slender_beam():
    # a locking element on L / r_g = 1000 with 10 elements would be stiffer by (L / (h r_g))^2-ish
    # factors; this one is within its h^4 error (2.6e-6 measured on mode 1, 2.9e-3 on mode 4)
    L, laws = _uniform(1000.0)
    rel = (timoshenko_modal(SectionLaws(**laws), L, n_modes=4, n_elements=10).omega_rad_s
           / _exact(L, laws) - 1)
    assert np.all(rel > -1e-9) and np.all(rel < [1e-5, 2e-4, 1e-3, 4e-3]), rel


@pytest.mark.parametrize("element", ["quadratic", "interdependent"])
def test_uniform_tip_deflection_is_the_closed_form(element):
    L, laws = _uniform(10.0)
    F = 120.0
    s = timoshenko_static(SectionLaws(**laws), L, F, n_elements=3, element=element)
    w = F * L**3 / (3 * E * I) + F * L / (KAPPA * G * A)
    th = F * L**2 / (2 * E * I)
    # both elements are nodally exact for a tip force (their fields hold the static solution):
    # rounding only, bounded by the free stiffness' condition number times EPS (3.4e6 for the
    # quadratic, 5e5 for the interdependent element at 3 elements; measured 8e-14, 3e-14)
    assert s.tip_deflection_m == pytest.approx(w, rel=4e6 * EPS, abs=0)
    assert s.tip_rotation_rad == pytest.approx(th, rel=4e6 * EPS, abs=0)


def test_tapered_tip_deflection_is_the_unit_load_integral():
    # w_tip = int (L - x)^2 / EI dx + int 1 / kappaGA dx (virtual work, exact), by quad
    L = 0.2
    t = lambda x: 0.03 - 0.02 * x / L  # noqa: E731
    EI = lambda x: E * B * t(x) ** 3 / 12  # noqa: E731
    GA = lambda x: KAPPA * G * B * t(x)  # noqa: E731
    ref = (quad(lambda x: (L - x) ** 2 / EI(x), 0, L, epsabs=0, epsrel=450 * EPS)[0]
           + quad(lambda x: 1 / GA(x), 0, L, epsabs=0, epsrel=450 * EPS)[0])
    sections = SectionLaws(EI, GA, 1.0, 1.0)  # the mass laws do not enter
    fine = timoshenko_static(sections, L, 1.0, n_elements=80).tip_deflection_m
    coarse = timoshenko_static(sections, L, 1.0, n_elements=40).tip_deflection_m
    # h^4 (a tapered element's field is not the exact one): 1.7e-7 at 40 elements, 1.07e-8
    # at 80 (ratio 15.9; 12..17 leaves room for the next term), so 2e-8 at 80
    e_fine, e_coarse = fine / ref - 1, coarse / ref - 1
    assert abs(e_fine) < 2e-8 and 12.0 < e_coarse / e_fine < 17.0, (e_fine, e_coarse)


def test_the_two_elements_agree_on_a_tapered_thick_beam():
    # a thickness taper 30 -> 10 mm over 0.3 m (L / r_g = 35 ... 104): another element, another
    # convergence order (h^2, exactly 4 per halving, measured 3.99-4.01)
    L = 0.3

    def tl(x):
        return 0.03 - 0.02 * x / L

    laws = dict(EI_Nm2=lambda x: E * B * tl(x) ** 3 / 12, kappaGA_N=lambda x: KAPPA * G * B * tl(x),
                rhoA_kg_m=lambda x: RHO * B * tl(x), rhoI_kg_m=lambda x: RHO * B * tl(x) ** 3 / 12)
    q = timoshenko_modal(SectionLaws(**laws), L, n_modes=4, n_elements=160).omega_rad_s
    sections = SectionLaws(**laws)
    f1 = timoshenko_modal(sections, L, n_modes=4, n_elements=160, element="interdependent")
    f2 = timoshenko_modal(sections, L, n_modes=4, n_elements=320, element="interdependent")
    e1, e2 = f1.omega_rad_s / q - 1, f2.omega_rad_s / q - 1
    # the quadratic element at 160 is within 5e-8 of converged (h^4: it moves 7e-7 on mode 4
    # from 80 elements, so 7e-7 / 15 is left), so the differences are the interdependent
    # element's own h^2 errors (1e-5 ... 4e-5)
    assert np.all((e1 / e2 > 3.8) & (e1 / e2 < 4.2)), e1 / e2
    # Richardson on the h^2 pair: the extrapolated frequency meets the quadratic one within
    # the quadratic's remaining 5e-8 plus the pair's next term (its ratio is 4 to 1e-2, so
    # 1e-2 e2 / 3 <= 3e-8): 1e-7 (measured 0.6-2.6e-8)
    rich = (4 * f2.omega_rad_s - f1.omega_rad_s) / 3
    assert np.all(np.abs(rich / q - 1) < 1e-7), rich / q - 1


def test_cowper_coefficients():
    # Cowper (1966) Table 1 at nu = 0.3, to the table's 3 digits (half a unit: 5e-4)
    assert shear_coefficient("rectangle", 0.3) == pytest.approx(0.850, abs=5e-4)
    assert shear_coefficient("solid_circle", 0.3) == pytest.approx(0.886, abs=5e-4)
    assert shear_coefficient("thin_tube", 0.3) == pytest.approx(0.531, abs=5e-4)
    # the hollow circle's formula: m = 0 is the solid circle, m -> 1 the thin tube (its limit
    # is reached like (1 - m): 1e-6 away at m = 1 - 1e-6, so 1e-5)
    solid = 6 * 1.3 / (7 + 1.8)
    # the same arithmetic in another order: a few roundings, 4 EPS
    assert shear_coefficient("tube", 0.3, 0.0) == pytest.approx(solid, rel=4 * EPS, abs=0)
    assert shear_coefficient("tube", 0.3, 1 - 1e-6) == pytest.approx(2.6 / 4.9, rel=1e-5, abs=0)


def test_a_planform_beam_is_the_rectangle_of_the_closed_form():
    L = 20 * T / np.sqrt(12)  # L / r_g = 20
    beam = Beam([0.0, L], [B / 2, B / 2], T, Material(E_Pa=E, rho_kg_m3=RHO, nu=NU))
    _, laws = _uniform(20.0)
    exact = _exact(L, laws)
    m = beam_timoshenko_modal(beam, n_modes=4, n_elements=40)
    # the discretisation at 40 elements, L / r_g = 20 (below 1.2e-5: first test)
    np.testing.assert_allclose(m.omega_rad_s, exact, rtol=1.2e-5)
    assert np.all(m.deflection_m[:, -1] > 0) and m.x_m[-1] == L


@pytest.mark.parametrize("inner_ratio", [0.0, 0.8])
def test_a_round_member_is_the_tube_of_the_closed_form(inner_ratio):
    # a uniform rod (d = 0) and tube (d = 0.8 D) at L / r_g = 20, r_g = sqrt(D^2 + d^2) / 4,
    # against the exact frequency equation with the section's values written out by hand
    import prbdm_pin as pp

    D = 0.04
    d = inner_ratio * D
    L = 20 * np.sqrt(D**2 + d**2) / 4
    mat = Material(E_Pa=E, rho_kg_m3=RHO, nu=NU)
    beam = pp.round_beam(np.array([0.0, L]), np.array([D, D]), np.array([d, d]), material=mat)
    A = np.pi * (D**2 - d**2) / 4
    Iy = np.pi * (D**4 - d**4) / 64
    m = 1 - 1e-12 if inner_ratio == 0.0 else inner_ratio  # Cowper's hollow circle, by hand
    q = (1 + m * m) ** 2 if inner_ratio else 1.0
    m2 = m * m if inner_ratio else 0.0
    kappa = 6 * (1 + NU) * q / ((7 + 6 * NU) * q + (20 + 12 * NU) * m2)
    G = E / (2 * (1 + NU))
    exact = timoshenko_cantilever_omega(L, E * Iy, kappa * G * A, RHO * A, RHO * Iy, 4)
    w = beam_timoshenko_modal(beam, n_modes=4, n_elements=40).omega_rad_s
    # the discretisation at 40 elements, L / r_g = 20 (below 1.2e-5, as the rectangle's)
    np.testing.assert_allclose(w, exact, rtol=1.2e-5)
    # the criterion's estimate of mode 1 against the exact equation's gap to Euler-Bernoulli
    from prbdm_pin.truth.timoshenko_criterion import timoshenko_criterion

    c = timoshenko_criterion(beam, 2, solve=False)
    eb = BETA_L[0] ** 2 / L**2 * np.sqrt(E * Iy / (RHO * A))
    gap = 100 * (1 - exact[0] / eb)
    assert c.slenderness == pytest.approx(20.0, rel=50 * EPS)  # L / r_g: a few roundings
    # first order in (r_g / L)^2: within 10 % of the exact gap at L / r_g = 20
    assert c.estimate_pct[0] == pytest.approx(gap, rel=0.1)


def test_a_section_table_has_no_shear_stiffness():
    import prbdm_pin as pp
    from prbdm_pin.truth.timoshenko_criterion import timoshenko_warnings

    x = np.array([0.0, 1.0])
    one = np.ones(2)
    table = pp.table_beam(x, pp.SectionTable(EI_y_Nm2=100 * one, EI_z_Nm2=400 * one,
                                             GJ_Nm2=50 * one, rhoA_kg_m=one,
                                             rhoI_y_kg_m=1e-6 * one, rhoI_z_kg_m=4e-6 * one))
    with pytest.raises(BeamInputError, match="section table"):
        beam_timoshenko_modal(table, 2)
    assert timoshenko_warnings(table, 5) == ()  # the truth computes, without the estimate


def test_first_order_coefficients_are_the_closed_form_modes():
    # quadrature of the closed-form modes (quad's relative 1.5e-8 default) against the table
    np.testing.assert_allclose(CANTILEVER_C, first_order_coefficients(6), rtol=1e-8)


@pytest.mark.parametrize("slenderness", [10.0, 50.0, 100.0, 200.0, 400.0])
def test_the_criterion_is_the_exact_equation_to_first_order(slenderness):
    L, laws = _uniform(slenderness)
    eb = BETA_L[:4] ** 2 / L**2 * np.sqrt(E * I / (RHO * A))
    gap = 100 * (eb / _exact(L, laws) - 1)
    est = eb_error_estimate_pct(4, 1 / slenderness, E / (KAPPA * G))
    # the estimate is first order: the rest is second order, est / 100 relative times a factor
    # 0.75-0.8 (measured at 100-400 for modes 1-4); 1.5 bounds that factor
    assert np.all(np.abs(gap / est - 1) < 1.5 * est / 100), (gap / est - 1, est)
    # and it errs on the safe side: never below the exact error (ratios 0.52-1.000)
    assert np.all(gap <= est), (gap, est)


def test_criterion_report_of_a_thick_and_a_slender_bar():
    thick = Beam([0.0, 0.2], [0.02, 0.02], 0.01)  # t / L = 0.05
    r = timoshenko_criterion(thick, n_modes=3)
    assert r.needs_timoshenko.tolist() == [True, True, True] and r.first_mode_needing == 1
    # the 1D solves' gap against the estimate: second order apart (above) plus the taper-free
    # solves' discretisation (< 1e-7); 0.1 % of est^2 / 100 per the previous test's factor
    assert np.all(np.abs(r.gap_pct / r.estimate_pct - 1) < 1.5 * r.estimate_pct / 100 + 1e-5)
    slender = Beam([0.0, 1.0], [0.01, 0.01], 0.002)  # t / L = 0.002: mode 5 at 0.015 %
    s = timoshenko_criterion(slender, n_modes=5, solve=False)
    assert not s.needs_timoshenko.any() and s.gap_pct is None and s.first_mode_needing is None
    # L / (t / sqrt(12)) against sqrt(12) / t: a few roundings, 4 EPS
    assert s.slenderness == pytest.approx(np.sqrt(12) / 0.002, rel=4 * EPS, abs=0)


def test_thickness_law_timoshenko_tends_to_the_euler_bernoulli_truth():
    # a thickness taper 2 -> 1 mm over 1 m: L / r_g >= 1700, every mode within 0.01 % of
    # Euler-Bernoulli (estimate, thickest section: 3.7e-3 % on mode 4)
    beam = Beam([0.0, 0.5, 1.0], [0.02, 0.015, 0.01], [0.002, 0.0015, 0.001])
    eb = beam_modal(beam, n_modes=4).omega_rad_s
    tim = beam_timoshenko_modal(beam, n_modes=4).omega_rad_s
    est = timoshenko_criterion(beam, n_modes=4, solve=False).estimate_pct
    gap = 100 * (eb / tim - 1)
    # Timoshenko below Euler-Bernoulli, by no more than the thickest section's estimate
    # (each section's share of the correction scales with its own, smaller r_g^2)
    assert np.all(gap > 0) and np.all(gap <= est), (gap, est)


def test_bad_input_names_the_argument():
    L, laws = _uniform(10.0)
    with pytest.raises(BeamInputError, match="rhoA_kg_m"):
        timoshenko_modal(SectionLaws(**{**laws, "rhoA_kg_m": -1.0}), L)
    with pytest.raises(BeamInputError, match="EI_Nm2.*station 2"):
        SectionLaws(**{**laws, "EI_Nm2": ([0.0, 0.5 * L, 0.4 * L], [1.0, 1.0, 1.0])})
    with pytest.raises(BeamInputError, match=r"kappaGA_N = 0\.0 at x"):
        timoshenko_modal(SectionLaws(**{**laws, "kappaGA_N": lambda x: 1e6 * (x < 0.5 * L)}), L)
    with pytest.raises(InputTypeError, match="rhoI_kg_m"):
        SectionLaws(**{**laws, "rhoI_kg_m": "heavy"})
    with pytest.raises(BeamInputError, match="element"):
        timoshenko_modal(SectionLaws(**laws), L, element="linear")
    with pytest.raises(BeamInputError, match="n_modes"):
        timoshenko_modal(SectionLaws(**laws), L, n_modes=0)
    with pytest.raises(BeamInputError, match="stations_m"):
        timoshenko_modal(SectionLaws(**laws), L, stations_m=[0.0, 0.2, 0.1])
    with pytest.raises(BeamInputError, match="length_m"):
        timoshenko_modal(SectionLaws(**laws), -1.0)
    with pytest.raises(InputTypeError, match="sections"):
        timoshenko_modal(laws, L)
    with pytest.raises(BeamInputError, match="tip_force_N"):
        timoshenko_static(SectionLaws(**laws), L, float("nan"))
    with pytest.raises(InputTypeError, match="kind"):
        shear_coefficient(3, 0.3)
    with pytest.raises(BeamInputError, match="kind"):
        shear_coefficient("I-beam", 0.3)
    with pytest.raises(BeamInputError, match="nu"):
        shear_coefficient("rectangle", 0.5)
    with pytest.raises(BeamInputError, match="inner_ratio"):
        shear_coefficient("tube", 0.3, 1.0)
    with pytest.raises(BeamInputError, match="tol_pct"):
        timoshenko_criterion(Beam([0.0, 1.0], [0.01, 0.01], 0.01), tol_pct=0.0)
    with pytest.raises(InputTypeError, match="beam"):
        timoshenko_criterion("beam.json")
    with pytest.raises(BeamInputError, match="rg_over_L"):
        eb_error_estimate_pct(3, -0.1, 3.0)


def test_the_1d_truth_warns_past_one_percent_and_says_by_how_much(narrow):
    from prbdm_pin.truth import compute_truth

    L = 0.2
    thick = Beam([0.0, L], [B / 2, B / 2], T, Material(E_Pa=E, rho_kg_m3=RHO, nu=NU))  # L/r_g 69
    r = compute_truth(thick, model="beam", modes=3, static=False, error_tol_pct=None)
    notes = [w for w in r.warnings if "Euler-Bernoulli truth" in w]
    assert len(notes) == 1 and "mode 2 by about" in notes[0] and "mode 3 by about" in notes[0]
    quoted = float(notes[0].split("mode 3 by about ")[1].split(" %")[0])
    # the quoted estimate against the exact equation's gap: first order (1.5 est / 100 of
    # itself, above) and the quote's 2 significant digits (5 % of it)
    _, laws = _uniform(L / RG)
    eb = BETA_L[2] ** 2 / L**2 * np.sqrt(E * I / (RHO * A))
    exact_gap = 100 * (eb / _exact(L, laws, 3)[2] - 1)
    assert quoted == pytest.approx(exact_gap, rel=0.05 + 1.5 * exact_gap / 100)
    # the shipped strip (L / r_g = 346) at 5 modes: 0.38 % on mode 5, below the warning
    slender = compute_truth(narrow, model="beam", modes=5, static=False, error_tol_pct=None)
    assert not any("Euler-Bernoulli truth" in w for w in slender.warnings)


@pytest.mark.slow
def test_a_stepped_thickness_tapered_member_converges_like_h4_on_finer_meshes():
    # width step at 0.15 m, thickness 30 -> 10 mm (L / r_g 35 ... 104): the planform's vertices
    # are element edges, so the laws are smooth inside every element and the order stays 4
    beam = Beam([0.0, 0.15, 0.15, 0.3], [0.03, 0.03, 0.02, 0.02], [0.03, 0.02, 0.02, 0.01])
    w = np.array([beam_timoshenko_modal(beam, 4, n).omega_rad_s for n in (50, 100, 200, 400)])
    d = np.diff(w, axis=0)
    # modes 2-4 (mode 1 is converged to 1e-10 by 100 elements: its differences are rounding):
    # error ratios 16 for h^4 (measured 15.9-16.0); 14..17 for the next term
    rate = d[1:, 1:] / d[:-1, 1:]
    assert np.all((1 / rate > 14.0) & (1 / rate < 17.0)), 1 / rate
    # Richardson from 100/200 and from 200/400: two estimates of the converged frequencies,
    # apart by the expansion's next term (h^5 or h^6: below 2e-10 of them, measured on
    # modes 1-4: 1.5e-12 ... 3.6e-11) plus rounding (1e-11 at 1600 DOFs)
    rich = w[1:] + d / 15.0
    assert np.all(np.abs(rich[2] / rich[1] - 1) < 2e-10), rich[2] / rich[1] - 1


def test_a_planform_beams_tip_is_the_unit_load_integral():
    # width 60 -> 40 mm with a step to 30 mm at 0.1 m, thickness 20 -> 8 mm over 0.25 m
    x = [0.0, 0.1, 0.1, 0.25]
    w = [0.03, 0.025, 0.015, 0.015]
    t = [0.02, 0.0152, 0.0152, 0.008]
    beam = Beam(x, w, t, Material(E_Pa=E, rho_kg_m3=RHO, nu=NU))
    F = 250.0

    def piece(f):  # quad between the stations, the step's two sides apart
        return sum(quad(f(a, b, wa, wb, ta, tb), a, b, epsabs=0, epsrel=450 * EPS)[0]
                   for a, b, wa, wb, ta, tb in ((0.0, 0.1, 0.03, 0.025, 0.02, 0.0152),
                                                (0.1, 0.25, 0.015, 0.015, 0.0152, 0.008)))

    def lin(a, b, fa, fb):
        return lambda s: fa + (fb - fa) * (s - a) / (b - a)

    def bend(a, b, wa, wb, ta, tb):
        ww, tt = lin(a, b, wa, wb), lin(a, b, ta, tb)
        return lambda s: F * (0.25 - s) ** 2 / (E * 2 * ww(s) * tt(s) ** 3 / 12)

    def shear(a, b, wa, wb, ta, tb):
        ww, tt = lin(a, b, wa, wb), lin(a, b, ta, tb)
        return lambda s: F / (KAPPA * G * 2 * ww(s) * tt(s))

    def rot(a, b, wa, wb, ta, tb):
        ww, tt = lin(a, b, wa, wb), lin(a, b, ta, tb)
        return lambda s: F * (0.25 - s) / (E * 2 * ww(s) * tt(s) ** 3 / 12)

    s = beam_timoshenko_static(beam, [0.0, 0.0, F])
    # h^4 on elements whose laws are smooth inside (4.7e-8, 3.0e-9, 3.0e-10 at 50, 100, 200
    # elements: 16 per halving until rounding joins at 200): 1e-9
    assert s.tip_deflection_m == pytest.approx(piece(bend) + piece(shear), rel=1e-9, abs=0)
    assert s.tip_rotation_rad == pytest.approx(piece(rot), rel=1e-9, abs=0)
    with pytest.raises(BeamInputError, match="tip_force_N"):
        beam_timoshenko_static(beam, [0.0, F])
