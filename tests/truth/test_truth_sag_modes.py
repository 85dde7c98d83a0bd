"""Vibrations about the sag (truth.elastica_modes) against Ritz and a fine chain in gravity.

About a straight member (the weight along it) the frequencies are the prestressed beam's:
Rayleigh-Ritz (tests/self_weight_reference.py). About a finite sag the reference is another
discretisation of the same member: a chain of rigid links (half links at both ends, springs
EI/h; Pinocchio's mass matrix and gravity, the package's sag equilibrium), converging as h^2
and extrapolated by Richardson from 32 and 64 links.
"""

import numpy as np
import pytest
from self_weight_reference import GREENHILL, ritz_frequencies, ritz_planform_frequencies
from tolerances import EPS, hermite_basis_cond

from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.gravity_chain import chain_in_gravity
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.truth.beam import beam_stations
from prbdm_pin.truth.beam_gravity import beam_gravity_modal
from prbdm_pin.truth.elastica_modes import elastica_gravity_modes

MAT = Material("steel", 205e9, 7850.0, 0.28)
# 0.2 m x 1 mm: rho A g L^3 / EI = 1 at g = 272 m/s^2, where it sags 0.12 L
THIN = Beam(np.array([0.0, 0.2]), np.array([0.0125, 0.0125]), 0.001, MAT)


def _uniform(beam):
    return beam.root_EI_Nm2, beam.mass_kg / beam.length_m, beam.length_m


@pytest.mark.parametrize("gamma", [4.0, -4.0])
def test_about_the_straight_member_it_is_the_prestressed_beam(narrow, gamma):
    EI, rhoA, L = _uniform(narrow)
    g = gamma * EI / (rhoA * L**3)
    ref = ritz_frequencies(EI, rhoA, L, g, n_terms=10, n_modes=2)  # 1e-10 from 9 terms
    err = {n: np.abs(elastica_gravity_modes(narrow, [g, 0.0, 0.0], None, 2, n)[0] / ref - 1)
           for n in (12, 25, 50)}
    assert np.all(err[25] < err[12] / 12)  # h^4: 19x from 12 to 25 elements
    assert np.all(err[50] < 1e-7)  # h^4 from 12 elements' 1.7e-5: 6e-8 at 50


@pytest.mark.parametrize("g_x, tension_N", [(500.0, 0.0), (-500.0, 100.0)])
def test_a_tapered_member_pulled_at_its_tip_is_the_prestressed_beam(g_x, tension_N):
    beam = Beam(np.array([0.0, 1.0]), np.array([0.05, 0.015]), 0.01, MAT)
    # Gauss-quadrature Ritz, 10 polynomials: 1e-10 from 11
    ref = ritz_planform_frequencies(beam.x_m, beam.half_width_m, beam.thickness_m,
                                    MAT.E_Pa, MAT.rho_kg_m3, g_x, tension_N, n_terms=10)
    w = elastica_gravity_modes(beam, [g_x, 0.0, 0.0], [tension_N, 0.0, 0.0], 2, 50)[0]
    np.testing.assert_allclose(w, ref, rtol=1e-7)  # h^4 at 50 elements (as above)


@pytest.mark.parametrize("g", [[500.0, 0.0, 0.0], [-500.0, 0.0, 0.0]])
def test_a_stepped_member_about_straight_is_the_hermite_beam(g):
    # another formulation on a stepped, tapered planform: the angle theta with its nonlocal
    # mass against the Hermite beam's displacement w with its geometric stiffness. theta = w'
    # of the Hermite cubics is piecewise quadratic, so the two spaces nearly coincide and the
    # results differ by the Hermite bases' rounding (EPS times their condition number)
    stepped = Beam(np.array([0.0, 0.3, 0.3, 1.0]), np.array([0.05, 0.04, 0.03, 0.015]), 0.01,
                   MAT)
    w = elastica_gravity_modes(stepped, g, None, 3, 100)[0]
    ref = beam_gravity_modal(stepped, g, 3, 100).omega_rad_s
    rel = 2 * EPS * hermite_basis_cond(beam_stations(stepped, 100))
    np.testing.assert_allclose(w, ref, rtol=rel)


def _chain(n: int, g) -> np.ndarray:
    EI, _, L = _uniform(THIN)
    h = L / n
    lengths = np.r_[h / 2, np.full(n - 1, h), h / 2]
    model = build_model(THIN, lengths, np.full(n, EI / h), min_fraction=0.1 / n)
    return chain_in_gravity(model, g).omega_rad_s[:3]


@pytest.mark.parametrize("g", [[0.0, 0.0, -272.0], [150.0, 0.0, -200.0]])
def test_about_a_sag_it_is_the_fine_chain_s(g):
    """The sag's effect on the frequencies, truth against the extrapolated chain.

    The chain's links carry the section's rotary inertia (m t^2 / 12), which the
    Euler-Bernoulli truth leaves out: -5e-6 on mode 1, -8e-5 on mode 3 whatever the gravity.
    Compared as ratios to the same member under a weight 1000 times smaller (sag 1.2e-4 L),
    that offset cancels.
    """
    tiny = np.asarray(g) * 1e-3
    truth = elastica_gravity_modes(THIN, g, None, 3)[0]
    truth_0 = elastica_gravity_modes(THIN, tiny, None, 3)[0]
    chain = {n: (4 * _chain(2 * n, g) - _chain(n, g)) / 3 for n in (16, 32)}
    chain_0 = (4 * _chain(64, tiny) - _chain(32, tiny)) / 3
    # Richardson on h^2: 16-32 and 32-64 agree to 2e-6 (the h^4 remainder)
    np.testing.assert_allclose(chain[16], chain[32], rtol=5e-6)
    effect = truth / truth_0 - 1
    assert np.abs(effect).max() > 5e-3  # the sag moves the frequencies
    # the truth's h^4 (1e-9 at 100 elements) and the chain's h^4 remainder (2e-6 between
    # the two extrapolations, a sixteenth of it after them): 1e-6
    np.testing.assert_allclose(truth / truth_0, chain[32] / chain_0, rtol=1e-6)


def test_a_buckled_equilibrium_is_refused():
    tall = Beam(np.array([0.0, 3.0]), np.array([0.025, 0.025]), 0.005, MAT)
    EI, rhoA, L = _uniform(tall)
    g = -1.05 * GREENHILL * EI / (rhoA * L**3)
    with pytest.raises(BeamInputError, match="buckles"):
        elastica_gravity_modes(tall, [g, 0.0, 0.0], None, 2, 25)
