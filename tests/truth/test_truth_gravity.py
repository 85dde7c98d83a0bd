"""The 1D beam truth under its own weight against independent references.

Prestressed frequencies (hanging, standing) against Rayleigh-Ritz, the standing column's
buckling against Greenhill's Bessel-function result, the small sag against q L^4 / (8 EI), and
the elastica under its weight against shooting (tests/self_weight_reference.py).
"""

import numpy as np
import pytest
from scipy.integrate import quad
from self_weight_reference import (
    GREENHILL,
    GREENHILL_PUBLISHED,
    ritz_frequencies,
    ritz_planform_frequencies,
    shoot_self_weight,
)
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.errors import BeamInputError
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.truth.beam import beam_stations
from prbdm_pin.truth.beam_gravity import (
    beam_gravity_modal,
    beam_gravity_static,
    beam_self_weight_buckling,
)
from prbdm_pin.truth.elastica import elastica_static
from prbdm_pin.truth.self_weight import MAX_GRAVITY_M_S2, check_gravity, outboard_mass_kg

MAT = Material("steel", 205e9, 7850.0, 0.28)
# a stepped, tapered planform: steps and kinks in rho A(x)
STEPPED = Beam(np.array([0.0, 0.3, 0.3, 1.0]), np.array([0.05, 0.04, 0.03, 0.015]), 0.01, MAT)


def _uniform(beam):
    EI = beam.root_EI_Nm2
    rhoA = beam.mass_kg / beam.length_m
    return EI, rhoA, beam.length_m


@pytest.mark.parametrize("gamma", [4.0, -4.0])  # rho A g_x L^3 / EI: hanging, standing
def test_prestressed_frequencies_match_ritz(narrow, gamma):
    EI, rhoA, L = _uniform(narrow)
    g = gamma * EI / (rhoA * L**3)
    # 10 polynomials: converged to 1e-10 on modes 1-2 (their change from 9 terms)
    ref = ritz_frequencies(EI, rhoA, L, g, n_terms=10, n_modes=2)
    err = {n: np.abs(beam_gravity_modal(narrow, [g, 0.0, 0.0], 2, n).omega_rad_s / ref - 1)
           for n in (12, 25, 50)}
    # cubic Hermite eigenvalues converge as h^4: (25/12)^4 = 19 from 12 to 25 elements
    assert np.all(err[25] < err[12] / 12)
    # at 50 elements h^4 leaves 1.3e-6 / (50/12)^4 = 4e-9 (mode 1), 6e-8 (mode 2)
    assert np.all(err[50] < 1e-7)
    unloaded = ritz_frequencies(EI, rhoA, L, 0.0, n_terms=10, n_modes=1)[0]
    assert (ref[0] > unloaded) == (gamma > 0)  # tension stiffens, compression softens


@pytest.mark.parametrize("g_x, tension_N", [(500.0, 0.0), (-500.0, 0.0), (0.0, 300.0),
                                             (300.0, -100.0)])
def test_tapered_prestress_with_tip_tension_matches_ritz(g_x, tension_N):
    # a tapered strip (rho A, EI linear; N(x) quadratic) hanging, standing, pulled at the tip
    # by F_x, and both (a tip push against the hanging weight)
    beam = Beam(np.array([0.0, 1.0]), np.array([0.05, 0.015]), 0.01, MAT)
    # 10 polynomials with Gauss quadrature: 1e-10 from 11 (measured)
    ref = ritz_planform_frequencies(beam.x_m, beam.half_width_m, beam.thickness_m,
                                    MAT.E_Pa, MAT.rho_kg_m3, g_x, tension_N, n_terms=10)
    err = {n: np.abs(beam_gravity_modal(beam, [g_x, 0.0, 0.0], 2, n,
                                        tip_force_N=[tension_N, 0.0, 0.0]).omega_rad_s
                     / ref - 1) for n in (12, 25, 50)}
    assert np.all(err[25] < err[12] / 12)  # h^4: 19x from 12 to 25 elements
    # h^4 from 12 elements' 1.4e-5: 5e-8 at 50
    assert np.all(err[50] < 1e-7)


def test_standing_column_buckles_at_greenhill(narrow):
    EI, rhoA, L = _uniform(narrow)
    # Timoshenko and Gere print 4 digits: 7.837 +- 5e-4
    assert GREENHILL == pytest.approx(GREENHILL_PUBLISHED, abs=5e-4)
    gam = {n: rhoA * beam_self_weight_buckling(narrow, n) * L**3 / EI for n in (12, 25, 50)}
    e12, e25 = abs(gam[12] / GREENHILL - 1), abs(gam[25] / GREENHILL - 1)
    assert e25 < e12 / 12  # h^4 (19x from 12 to 25 elements)
    # h^4 from 12 elements' 2.6e-6: 9e-9 at 50
    assert gam[50] == pytest.approx(GREENHILL, rel=1e-7)


def test_standing_beyond_buckling_is_refused():
    # a 3 m strip 5 mm thick buckles standing at 1.6 g
    tall = Beam(np.array([0.0, 3.0]), np.array([0.025, 0.025]), 0.005, MAT)
    EI, rhoA, L = _uniform(tall)
    g = -1.05 * GREENHILL * EI / (rhoA * L**3)
    assert -20.0 < g < -9.81
    with pytest.raises(BeamInputError, match="buckles under its own weight"):
        beam_gravity_modal(tall, [g, 0.0, 0.0], 2)
    with pytest.raises(BeamInputError, match="buckles under its own weight"):
        beam_gravity_static(tall, [g, 0.0, -1.0])


@pytest.mark.parametrize("n", [25, 50])
def test_uniform_sag_is_q_l4_over_8ei(narrow, n):
    EI, rhoA, L = _uniform(narrow)
    s = beam_gravity_static(narrow, [0.0, 0.0, -9.81], n_elements=n)
    ref = -rhoA * 9.81 * L**4 / (8 * EI)
    # Hermite cubics are nodally exact for a uniform load: only the rounding of the element
    # bases is left (EPS times their condition number, twice: stiffness and load)
    rel = 2 * EPS * hermite_basis_cond(beam_stations(narrow, n))
    assert s.tip_displacement_m[2] == pytest.approx(ref, rel=rel)
    assert s.tip_displacement_m[[0, 1]].tolist() == [0.0, 0.0]


def test_sag_and_tip_force_superpose(narrow):
    EI, rhoA, L = _uniform(narrow)
    F = -50.0
    s = beam_gravity_static(narrow, [0.0, 0.0, -9.81], tip_force_N=[0.0, 0.0, F],
                            n_elements=25)
    ref = F * L**3 / (3 * EI) - rhoA * 9.81 * L**4 / (8 * EI)
    # nodally exact (as above): rounding of the element bases only
    rel = 2 * EPS * hermite_basis_cond(beam_stations(narrow, 25))
    assert s.tip_displacement_m[2] == pytest.approx(ref, rel=rel)


def test_horizontal_member_vibrates_as_unloaded(narrow):
    # g_z loads without prestress: the frequencies about a small sag are the unloaded ones,
    # 1.8751^2 sqrt(EI / (rho A L^4)) for mode 1 (Euler-Bernoulli)
    EI, rhoA, L = _uniform(narrow)
    w = beam_gravity_modal(narrow, [0.0, 0.0, -9.81], 1, 50).omega_rad_s[0]
    beta = 1.8751040687119611  # root of cos b cosh b = -1
    # h^4 at 50 elements (see the Ritz test): 1e-8
    assert w == pytest.approx(beta**2 * np.sqrt(EI / (rhoA * L**4)), rel=1e-7)


def test_outboard_mass_matches_quadrature():
    x = np.array([0.0, 0.1, 0.3, 0.55, 1.0])
    rho_t = MAT.rho_kg_m3 * STEPPED.thickness_m

    def ref(a):
        pts = [p for p in (0.3,) if a < p]
        return quad(lambda s: rho_t * 2 * STEPPED.half_width_at(s), a, 1.0, points=pts,
                    epsabs=0.0, epsrel=450 * EPS)[0]  # quad's request 1e-13

    want = [ref(a) for a in x]
    # a sum of a few positive terms: a few roundings
    assert outboard_mass_kg(STEPPED, x) == pytest.approx(want, rel=20 * EPS, abs=0.0)
    assert outboard_mass_kg(STEPPED, 0.0) == pytest.approx(STEPPED.mass_kg, rel=20 * EPS)


@pytest.mark.parametrize("g, F", [
    ([0.0, 0.0, -9.81 * 50], [0.0, 0.0, 0.0]),       # large sag under its weight alone
    ([-3.0, 0.0, -9.81 * 50], [0.0, 0.0, -300.0]),   # oblique gravity and a tip force
    ([200.0, 0.0, -400.0], [50.0, 0.0, 0.0]),        # hanging obliquely, pulled at the tip
])
def test_elastica_under_self_weight_matches_shooting(narrow, g, F):
    EI, rhoA, L = _uniform(narrow)
    s = elastica_static(narrow, np.array(F), gravity_m_s2=g)
    ref = shoot_self_weight(EI, rhoA, L, g, F)
    # collocation residual tolerance 1e-9 (relative to the moment scale), the shooting's
    # 1e-12: the tip agrees to about the former times L (measured 3e-13 m)
    assert s.tip_position_m == pytest.approx(ref, abs=1e-9 * L)
    assert abs(s.tip_displacement_m[2]) > 0.1 * L or abs(g[2]) < 100  # large deflection


def test_elastica_small_weight_matches_linear_sag():
    # another algorithm on a stepped, tapered planform: the collocated elastica at a small
    # weight against the Hermite beam's linear sag
    g = [0.0, 0.0, -0.01]
    nl = elastica_static(STEPPED, np.zeros(3), gravity_m_s2=g).tip_displacement_m[2]
    lin = beam_gravity_static(STEPPED, g, n_elements=50).tip_displacement_m[2]
    # geometric nonlinearity enters at relative order (sag / L)^2 ~ 1e-11; the 1D beam's
    # h^4 error on this kinked planform ~ 1e-9 at 50 elements; the collocation's 1e-9
    assert nl == pytest.approx(lin, rel=1e-7)


def test_gravity_bad_input(narrow):
    with pytest.raises(BeamInputError, match="gravity_m_s2.*above"):
        check_gravity([0.0, 0.0, -1.01 * MAX_GRAVITY_M_S2])
    with pytest.raises(BeamInputError, match="g_y must be 0"):
        beam_gravity_modal(narrow, [0.0, 1.0, -9.81], 2)
    with pytest.raises(BeamInputError, match="3 finite numbers"):
        beam_gravity_static(narrow, [0.0, np.nan, -9.81])
    with pytest.raises(BeamInputError, match="3 finite numbers"):
        elastica_static(narrow, np.zeros(3), gravity_m_s2=[0.0, -9.81])
    with pytest.raises(BeamInputError, match="--gravity"):
        check_gravity("down", "--gravity")
